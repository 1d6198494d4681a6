// Per-reading residuals on spread frames (residuals.hpp).
#include "stac/residuals.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "stac/calibrate.hpp"
#include "stac/parallel.hpp"
#include "stac/q_phase.hpp"
#include "methods/wide_basin.hpp"

namespace stac {

bool ResidualSampleOptions::isValid(std::string* error) const {
  auto fail = [&](const std::string& e) {
    if (error) *error = e;
    return false;
  };
  if (max_frames < 1) return fail("max_frames must be at least 1");
  if (threads < 0) return fail("threads must be >= 0 (0 = all cores)");
  if (!(loss_scale > 0) || !std::isfinite(loss_scale))
    return fail("loss scale must be positive and finite");
  return true;
}

double ResidualSample::rms(SensorGroup g) const {
  const std::vector<double>& v = magnitude[static_cast<int>(g)];
  double s = 0;
  for (double x : v) s += x * x;
  return v.empty() ? 0.0 : std::sqrt(s / v.size());
}

ResidualSample sampleResiduals(const RobotModel& robot, const SensorSet& sensors,
                               const SensorParameters& theta, const Observations& obs,
                               const RowMatrix* q, const ResidualSampleOptions& options) {
  std::string error;
  if (!options.isValid(&error)) throw std::invalid_argument("sampleResiduals: " + error);
  if (q && (q->rows() != obs.num_frames || q->cols() != robot.dof()))
    throw std::invalid_argument("sampleResiduals: q is not frames x dof");
  const MeasurementModel model(robot, sensors);
  const int threads = resolveThreads(options.threads);
  ResidualSample out;
  out.frames = spreadFrames(obs.num_frames, options.max_frames);
  const Observations sub = selectFrames(obs, out.frames);
  const int T = sub.num_frames;
  RowMatrix qs(T, robot.dof());
  if (q) {
    for (int k = 0; k < T; ++k) qs.row(k) = q->row(out.frames[k]);
  } else {
    // As calibrate() fits q to the seed for summary.before_rms: from the
    // neutral pose, ten LM-batch steps per frame, at the seed σ.
    std::vector<FrameWorkspace> ws;
    for (int i = 0; i < threads; ++i) ws.emplace_back(model);
    QState state;
    state.q = neutralPose(robot).transpose().replicate(T, 1);
    QPhaseOptions qo;
    qo.method = QPhaseMethod::kLmBatch;
    qo.max_steps = 10;
    qo.threads = threads;
    qPhase(model, theta, NoiseModel::fromSeeds(sensors),
           RobustLoss(options.loss, options.loss_scale), sub, qo, &ws, &state);
    qs = state.q;
  }

  // Per chunk, then joined in chunk order: the same output with any thread count.
  const int M = static_cast<int>(sensors.markers.size());
  const int J = static_cast<int>(sensors.joint_sensors.size());
  const int N = static_cast<int>(sensors.tendon_sensors.size());
  std::vector<ResidualSample> chunks(numChunks(T));
  std::vector<KinematicsWorkspace> kin(threads, KinematicsWorkspace(robot));
  parallelFor(numChunks(T), threads, [&](int chunk, int tid) {
    ResidualSample& c = chunks[chunk];
    Eigen::VectorXd qt(robot.dof()), pm(3 * M), pj(J), pt(N);
    const int end = std::min(T, (chunk + 1) * kFramesPerChunk);
    for (int t = chunk * kFramesPerChunk; t < end; ++t) {
      qt = qs.row(t).transpose();
      predictFrame(model, theta, qt, &kin[tid], pm.data(), pj.data(), pt.data());
      auto add = [&](SensorGroup g, int i, double e) {
        c.magnitude[static_cast<int>(g)].push_back(e);
        c.sensor[static_cast<int>(g)].push_back(i);
      };
      for (int m = 0; m < M; ++m) {
        const double* x = sub.marker.row(t).data() + 3 * m;
        if (!std::isnan(x[0]))
          add(SensorGroup::kMarker, m,
              (pm.segment<3>(3 * m) - Eigen::Vector3d(x[0], x[1], x[2])).norm());
      }
      for (int j = 0; j < J; ++j)
        if (!std::isnan(sub.joint(t, j)))
          add(SensorGroup::kJoint, j, std::abs(pj[j] - sub.joint(t, j)));
      for (int k = 0; k < N; ++k)
        if (!std::isnan(sub.tendon(t, k)))
          add(SensorGroup::kTendon, k, std::abs(pt[k] - sub.tendon(t, k)));
    }
  });
  for (const ResidualSample& c : chunks)
    for (int g = 0; g < kNumSensorGroups; ++g) {
      out.magnitude[g].insert(out.magnitude[g].end(), c.magnitude[g].begin(), c.magnitude[g].end());
      out.sensor[g].insert(out.sensor[g].end(), c.sensor[g].begin(), c.sensor[g].end());
    }
  return out;
}

}  // namespace stac
