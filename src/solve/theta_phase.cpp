#include "solve/theta_phase.hpp"

#include <Eigen/Cholesky>
#include <Eigen/SVD>
#include <cmath>

#include "solve/parallel.hpp"
#include "stac/sensor_models.hpp"

namespace stac {

LineFit fitGainBias(const double* x, const double* p, const double* w, int n,
                    const GainBias& previous) {
  LineFit fit;
  fit.value = previous;
  double sw = 0, sx = 0, sp = 0;
  for (int i = 0; i < n; ++i) {
    if (std::isnan(p[i]) || std::isnan(x[i])) continue;
    const double wi = w ? w[i] : 1.0;
    sw += wi, sx += wi * x[i], sp += wi * p[i];
  }
  if (!(sw > 0)) {
    fit.any_data = false;
    fit.gain_identifiable = false;
    return fit;
  }
  const double mx = sx / sw, mp = sp / sw;
  double sxx = 0, sxp = 0;
  for (int i = 0; i < n; ++i) {
    if (std::isnan(p[i]) || std::isnan(x[i])) continue;
    const double wi = w ? w[i] : 1.0;
    sxx += wi * (x[i] - mx) * (x[i] - mx);
    sxp += wi * (x[i] - mx) * (p[i] - mp);
  }
  // A joint that never moved (spread below ~1e-9 of its magnitude) cannot
  // separate gain from bias: keep the gain, fit the bias given it.
  if (sxx <= 1e-18 * sw * (1.0 + mx * mx)) {
    fit.gain_identifiable = false;
    fit.value.bias = mp - previous.gain * mx;
    return fit;
  }
  fit.value.gain = sxp / sxx;
  fit.value.bias = mp - fit.value.gain * mx;
  return fit;
}

LineFit fitGainBias(const double* x, const double* p, const double* w, int n,
                    const GainBias& previous, const FixedGainBias& fixed) {
  if (!fixed.any()) return fitGainBias(x, p, w, n, previous);
  LineFit fit;
  fit.value = previous;
  if (fixed.all()) return fit;
  double sw = 0, sxx = 0, sxr = 0, sr = 0;  // r: the reading less the held part
  for (int i = 0; i < n; ++i) {
    if (std::isnan(p[i]) || std::isnan(x[i])) continue;
    const double wi = w ? w[i] : 1.0;
    sw += wi;
    sxx += wi * x[i] * x[i];
    sxr += wi * x[i] * (p[i] - previous.bias);
    sr += wi * (p[i] - previous.gain * x[i]);
  }
  fit.any_data = sw > 0;
  if (fixed.gain) {
    if (fit.any_data) fit.value.bias = sr / sw;
    return fit;  // the gain is known, not unidentifiable
  }
  // Bias held: x never away from 0 leaves the gain undetermined.
  fit.gain_identifiable = fit.any_data && sxx > 1e-18 * sw;
  if (fit.gain_identifiable) fit.value.gain = sxr / sxx;
  return fit;
}

namespace {

// The proper rotation R maximising tr(R C) (Kabsch), or nullopt when C does
// not determine it (rank below 2: the points are collinear or coincident,
// and rotation about their line is free).
std::optional<Eigen::Matrix3d> properRotation(const Eigen::Matrix3d& C) {
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(C, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Vector3d s = svd.singularValues();
  if (!(s[1] > 1e-12 * std::max(s[0], 1e-300)) || !(s[0] > 0)) return std::nullopt;
  const Eigen::Matrix3d U = svd.matrixU(), V = svd.matrixV();
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  D(2, 2) = (V * U.transpose()).determinant() > 0 ? 1.0 : -1.0;  // proper rotation
  return Eigen::Matrix3d(V * D * U.transpose());
}

}  // namespace

std::optional<MocapFrame> procrustes(const std::vector<Eigen::Vector3d>& a,
                                     const std::vector<Eigen::Vector3d>& b,
                                     const std::vector<double>& w) {
  const size_t n = a.size();
  if (n < 3 || b.size() != n || w.size() != n) return std::nullopt;
  double sw = 0;
  Eigen::Vector3d ca = Eigen::Vector3d::Zero(), cb = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < n; ++i) {
    sw += w[i];
    ca += w[i] * a[i];
    cb += w[i] * b[i];
  }
  if (!(sw > 0)) return std::nullopt;
  ca /= sw;
  cb /= sw;
  Eigen::Matrix3d C = Eigen::Matrix3d::Zero();  // Σ w (a - ā)(b - b̄)^T
  for (size_t i = 0; i < n; ++i) C += w[i] * (a[i] - ca) * (b[i] - cb).transpose();
  const std::optional<Eigen::Matrix3d> R = properRotation(C);
  if (!R) return std::nullopt;
  MocapFrame f;
  f.rotation = Eigen::Quaterniond(*R).normalized();
  f.translation = cb - *R * ca;
  return f;
}

std::optional<MocapFrame> procrustes(const std::vector<Eigen::Vector3d>& a,
                                     const std::vector<Eigen::Vector3d>& b,
                                     const std::vector<double>& w, const MocapFrame& frame,
                                     const FixedFrame& fixed) {
  if (fixed.all()) return frame;
  if (!fixed.any()) return procrustes(a, b, w);
  const size_t n = a.size();
  if (b.size() != n || w.size() != n) return std::nullopt;
  MocapFrame f = frame;
  if (fixed.rotation) {
    const Eigen::Matrix3d R = frame.rotation.toRotationMatrix();
    double sw = 0;
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (size_t i = 0; i < n; ++i) sw += w[i], sum += w[i] * (b[i] - R * a[i]);
    if (!(sw > 0)) return std::nullopt;
    f.translation = sum / sw;
    return f;
  }
  if (n < 3) return std::nullopt;
  Eigen::Matrix3d C = Eigen::Matrix3d::Zero();  // Σ w a (b - t)^T, about the held t
  for (size_t i = 0; i < n; ++i) C += w[i] * a[i] * (b[i] - frame.translation).transpose();
  const std::optional<Eigen::Matrix3d> R = properRotation(C);
  if (!R) return std::nullopt;
  f.rotation = Eigen::Quaterniond(*R).normalized();
  return f;
}

MarkerPoseCache cacheMarkerPoses(const MeasurementModel& model, const RowMatrix& q,
                                 int threads, std::vector<FrameWorkspace>* ws,
                                 const SensorParameters* theta) {
  const int T = static_cast<int>(q.rows());
  const int M = static_cast<int>(model.sensors().markers.size());
  MarkerPoseCache cache;
  cache.markers = M;
  cache.rotation.resize(static_cast<size_t>(T) * M);
  cache.translation.resize(static_cast<size_t>(T) * M);
  if (M == 0) return cache;
  threads = std::min<int>(resolveThreads(threads), static_cast<int>(ws->size()));
  parallelFor(numChunks(T), threads, [&](int chunk, int tid) {
    KinematicsWorkspace& kin = (*ws)[tid].kin;
    if (theta)
      applyJointOrigins(model, *theta, &kin);
    else
      setOriginCorrections(model.robot(), {}, {}, &kin);
    Eigen::VectorXd qt(model.dof());
    const int end = std::min(T, (chunk + 1) * kFramesPerChunk);
    for (int t = chunk * kFramesPerChunk; t < end; ++t) {
      qt = q.row(t).transpose();
      forwardKinematics(model.robot(), qt, &kin);
      for (int m = 0; m < M; ++m) {
        const Eigen::Isometry3d& P = kin.link_pose[model.sensors().markers[m].link];
        cache.rotation[static_cast<size_t>(t) * M + m] = P.linear();
        cache.translation[static_cast<size_t>(t) * M + m] = P.translation();
      }
    }
  });
  return cache;
}

std::optional<Eigen::Vector3d> averageMarkerPosition(const MarkerPoseCache& poses,
                                                     const Observations& obs,
                                                     const MocapFrame& frame, int m) {
  const Eigen::Matrix3d Rt = frame.rotation.toRotationMatrix().transpose();
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  int n = 0;
  for (int t = 0; t < obs.num_frames; ++t) {
    const double* x = obs.marker.row(t).data() + 3 * m;
    if (std::isnan(x[0])) continue;
    const size_t i = static_cast<size_t>(t) * poses.markers + m;
    const Eigen::Vector3d xb = Rt * (Eigen::Vector3d(x[0], x[1], x[2]) - frame.translation);
    sum += poses.rotation[i].transpose() * (xb - poses.translation[i]);
    ++n;
  }
  if (n == 0) return std::nullopt;
  return Eigen::Vector3d(sum / n);
}

namespace {

// Robust weight ρ'(s) of a reading with whitened residual r.
double robustWeight(const RobustLoss& loss, double s) {
  if (!loss.enabled()) return 1.0;
  double rho[3];
  loss.evaluate(s, rho);
  return rho[1];
}

// Σ w ρ of the marker group over the cached poses.
double markerGroupCost(const MeasurementModel& model, const NoiseModel& noise,
                       const RobustLoss& loss, const Observations& obs,
                       const MarkerPoseCache& poses, const SensorParameters& th) {
  const int M = poses.markers;
  const Eigen::Matrix3d R = th.mocap.rotation.toRotationMatrix();
  double cost = 0;
  for (int t = 0; t < obs.num_frames; ++t) {
    for (int m = 0; m < M; ++m) {
      const double* x = obs.marker.row(t).data() + 3 * m;
      if (std::isnan(x[0])) continue;
      const size_t i = static_cast<size_t>(t) * M + m;
      const Eigen::Vector3d xb = poses.rotation[i] * th.marker_position[m] + poses.translation[i];
      const Eigen::Vector3d r =
          (R * xb + th.mocap.translation - Eigen::Vector3d(x[0], x[1], x[2])) / noise.marker[m];
      double rho[3];
      loss.evaluate(r.squaredNorm(), rho);
      cost += rho[0];
    }
  }
  (void)model;
  return 0.5 * cost;
}

// Where the marker group's free parameters sit in its Gauss-Newton system
// (-1: held): the mocap rotation δ, the translation, each marker position.
struct MarkerGroupLayout {
  int rotation = -1, translation = -1;
  std::vector<int> marker;
  int size = 0;
};

MarkerGroupLayout markerGroupLayout(const SensorSet& sensors) {
  MarkerGroupLayout l;
  if (!sensors.mocap_frame_fixed.rotation) l.rotation = l.size, l.size += 3;
  if (!sensors.mocap_frame_fixed.translation) l.translation = l.size, l.size += 3;
  l.marker.assign(sensors.markers.size(), -1);
  for (size_t m = 0; m < sensors.markers.size(); ++m)
    if (!sensors.markers[m].fixed) l.marker[m] = l.size, l.size += 3;
  return l;
}

// H = Σ w JᵀJ and g = Σ w Jᵀr of the marker group over the free parameters.
void markerGroupNormalEquations(const MarkerGroupLayout& layout, const NoiseModel& noise,
                                const RobustLoss& loss, const Observations& obs,
                                const MarkerPoseCache& poses, const SensorParameters& theta,
                                Eigen::MatrixXd* H, Eigen::VectorXd* g) {
  const int M = poses.markers;
  H->setZero(layout.size, layout.size);
  g->setZero(layout.size);
  const Eigen::Matrix3d R = theta.mocap.rotation.toRotationMatrix();
  for (int t = 0; t < obs.num_frames; ++t) {
    for (int m = 0; m < M; ++m) {
      const double* x = obs.marker.row(t).data() + 3 * m;
      if (std::isnan(x[0])) continue;
      const size_t i = static_cast<size_t>(t) * M + m;
      const double inv = 1.0 / noise.marker[m];
      const Eigen::Vector3d xb =
          poses.rotation[i] * theta.marker_position[m] + poses.translation[i];
      const Eigen::Vector3d r =
          (R * xb + theta.mocap.translation - Eigen::Vector3d(x[0], x[1], x[2])) * inv;
      const double w = robustWeight(loss, r.squaredNorm());
      Eigen::Matrix<double, 3, 9> J;
      int idx[9], k = 0;
      auto columns = [&](int offset, const Eigen::Matrix3d& block) {
        J.block<3, 3>(0, k) = block;
        for (int a = 0; a < 3; ++a) idx[k++] = offset + a;
      };
      if (layout.rotation >= 0)
        columns(layout.rotation, inv * marker_sensor::rotationJacobian(R, xb));
      if (layout.translation >= 0) columns(layout.translation, inv * Eigen::Matrix3d::Identity());
      if (layout.marker[m] >= 0) columns(layout.marker[m], inv * (R * poses.rotation[i]));
      for (int a = 0; a < k; ++a) {
        (*g)[idx[a]] += w * J.col(a).dot(r);
        for (int b = 0; b < k; ++b) (*H)(idx[a], idx[b]) += w * J.col(a).dot(J.col(b));
      }
    }
  }
}

// θ moved by `step` over the marker group's free parameters.
SensorParameters markerGroupStep(const MarkerGroupLayout& layout, const SensorParameters& theta,
                                 const Eigen::VectorXd& step) {
  SensorParameters out = theta;
  if (layout.rotation >= 0) {
    const Eigen::Vector3d d = step.segment<3>(layout.rotation);
    const double angle = d.norm();
    const Eigen::Quaterniond dq = angle > 0
                                      ? Eigen::Quaterniond(Eigen::AngleAxisd(angle, d / angle))
                                      : Eigen::Quaterniond::Identity();
    out.mocap.rotation = (dq * theta.mocap.rotation).normalized();
  }
  if (layout.translation >= 0) out.mocap.translation += step.segment<3>(layout.translation);
  for (size_t m = 0; m < layout.marker.size(); ++m)
    if (layout.marker[m] >= 0) out.marker_position[m] += step.segment<3>(layout.marker[m]);
  return out;
}

// Gauss-Newton (IRLS for a robust loss) on the free parts of the mocap frame
// and the free marker positions together, q fixed.
void markerGroupGaussNewton(const MeasurementModel& model, const NoiseModel& noise,
                            const RobustLoss& loss, const Observations& obs,
                            const MarkerPoseCache& poses, int steps,
                            SensorParameters* theta) {
  const MarkerGroupLayout layout = markerGroupLayout(model.sensors());
  const int n = layout.size;
  if (n == 0) return;
  Eigen::MatrixXd H(n, n);
  Eigen::VectorXd g(n);
  double cost = markerGroupCost(model, noise, loss, obs, poses, *theta);
  for (int step = 0; step < steps; ++step) {
    markerGroupNormalEquations(layout, noise, loss, obs, poses, *theta, &H, &g);
    // Tiny damping: directions the data cannot see (a gauge) stay put.
    const double eps = 1e-12 * std::max(1.0, H.diagonal().maxCoeff());
    for (int a = 0; a < n; ++a) H(a, a) += 1e-9 * H(a, a) + eps;
    const Eigen::VectorXd delta = H.ldlt().solve(-g);
    if (!delta.allFinite()) return;
    for (double alpha = 1.0; alpha > 1e-3; alpha *= 0.5) {
      const SensorParameters trial = markerGroupStep(layout, *theta, alpha * delta);
      const double c = markerGroupCost(model, noise, loss, obs, poses, trial);
      if (c <= cost) {
        const bool done = cost - c <= 1e-14 * cost;
        *theta = trial;
        cost = c;
        if (done) return;
        break;
      }
      if (alpha < 0.01) return;
    }
  }
}

// Eq. 18-20: the (robustly weighted) line p ≈ gain * x + bias of one scalar
// sensor, x its joint angle or tendon length per frame, the parts in `fixed`
// held. Returns false where x never varied (the gain kept).
bool fitScalarSensor(const std::vector<double>& x, const double* p, Eigen::Index stride,
                     double sigma, const RobustLoss& loss, const FixedGainBias& fixed,
                     GainBias* gb) {
  const int T = static_cast<int>(x.size());
  std::vector<double> pv(T), w(T);
  for (int t = 0; t < T; ++t) {
    pv[t] = p[t * stride];
    const double r = (gb->gain * x[t] + gb->bias - pv[t]) / sigma;
    w[t] = std::isnan(pv[t]) ? 0.0 : robustWeight(loss, r * r);
  }
  const LineFit fit = fitGainBias(x.data(), pv.data(), w.data(), T, *gb, fixed);
  *gb = fit.value;
  return fit.gain_identifiable;
}

}  // namespace

ThetaPhaseReport thetaPhase(const MeasurementModel& model, const NoiseModel& noise,
                            const RobustLoss& loss, const Observations& obs,
                            const QState& state, const ThetaPhaseOptions& options,
                            std::vector<FrameWorkspace>* workspaces,
                            SensorParameters* theta) {
  ThetaPhaseReport report;
  const SensorSet& sensors = model.sensors();
  const RobotModel& robot = model.robot();
  const int T = obs.num_frames;
  const int threads = std::min<int>(resolveThreads(options.threads),
                                    static_cast<int>(workspaces->size()));

  // Joint sensors: angles come straight from q.
  if (options.update[1]) {
    std::vector<double> x(T);
    for (size_t s = 0; s < sensors.joint_sensors.size(); ++s) {
      const JointSensorConfig& sc = sensors.joint_sensors[s];
      if (sc.fixed.all()) continue;
      const MovableJoint& mj = robot.movableJoints()[sc.joint];
      for (int t = 0; t < T; ++t) x[t] = mj.multiplier * state.q(t, mj.q_index) + mj.offset;
      if (!fitScalarSensor(x, obs.joint.data() + s, obs.joint.cols(), noise.joint[s], loss,
                           sc.fixed, &theta->joint_sensor[s]))
        report.degenerate.push_back("joint_sensors." + sc.name + ".gain");
    }
  }

  // Tendon sensors: lengths need FK for paths.
  if (options.update[2] && !sensors.tendon_sensors.empty()) {
    const int S = static_cast<int>(sensors.tendon_sensors.size());
    RowMatrix L(T, S);
    parallelFor(numChunks(T), threads, [&](int chunk, int tid) {
      KinematicsWorkspace& kin = (*workspaces)[tid].kin;
      applyJointOrigins(model, *theta, &kin);
      Eigen::VectorXd qt(model.dof());
      const int end = std::min(T, (chunk + 1) * kFramesPerChunk);
      for (int t = chunk * kFramesPerChunk; t < end; ++t) {
        qt = state.q.row(t).transpose();
        forwardKinematics(robot, qt, &kin);
        for (int s = 0; s < S; ++s)
          L(t, s) = tendon_sensor::length(robot, sensors.tendon_sensors[s], kin);
      }
    });
    std::vector<double> x(T);
    for (int s = 0; s < S; ++s) {
      const TendonSensorConfig& sc = sensors.tendon_sensors[s];
      if (sc.fixed.all()) continue;
      for (int t = 0; t < T; ++t) x[t] = L(t, s);
      if (!fitScalarSensor(x, obs.tendon.data() + s, obs.tendon.cols(), noise.tendon[s], loss,
                           sc.fixed, &theta->tendon_sensor[s]))
        report.degenerate.push_back("tendon_sensors." + sc.name + ".gain");
    }
  }

  if (options.update[0] && !sensors.markers.empty()) {
    const MarkerPoseCache poses = cacheMarkerPoses(model, state.q, threads, workspaces, theta);
    markerGroupGaussNewton(model, noise, loss, obs, poses,
                           options.marker_gauss_newton_steps, theta);
  }
  return report;
}

void initialiseMarkerGroup(const MeasurementModel& model, const Observations& obs,
                           const QState& state, int rounds, int threads,
                           std::vector<FrameWorkspace>* workspaces,
                           SensorParameters* theta) {
  const SensorSet& sensors = model.sensors();
  const int M = static_cast<int>(sensors.markers.size());
  if (M == 0) return;
  const MarkerPoseCache poses = cacheMarkerPoses(model, state.q, threads, workspaces, theta);
  for (int round = 0; round < rounds; ++round) {
    if (!sensors.mocap_frame_fixed.all()) {
      // Eq. 13-16 over every (frame, marker) reading.
      std::vector<Eigen::Vector3d> a, b;
      std::vector<double> w;
      for (int t = 0; t < obs.num_frames; ++t)
        for (int m = 0; m < M; ++m) {
          const double* x = obs.marker.row(t).data() + 3 * m;
          if (std::isnan(x[0])) continue;
          const size_t i = static_cast<size_t>(t) * M + m;
          a.push_back(poses.rotation[i] * theta->marker_position[m] + poses.translation[i]);
          b.emplace_back(x[0], x[1], x[2]);
          w.push_back(1.0 / (sensors.markers[m].sigma * sensors.markers[m].sigma));
        }
      if (auto f = procrustes(a, b, w, theta->mocap, sensors.mocap_frame_fixed))
        theta->mocap = *f;
    }
    for (int m = 0; m < M; ++m) {
      if (sensors.markers[m].fixed) continue;
      if (auto d = averageMarkerPosition(poses, obs, theta->mocap, m))
        theta->marker_position[m] = *d;
    }
  }
}

}  // namespace stac
