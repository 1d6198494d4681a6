#include "stac/uncertainty.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <stdexcept>

#include "stac/parallel.hpp"
#include "stac/q_phase.hpp"

namespace stac {
namespace {

constexpr double kConfoundedPart = 0.01;
constexpr double kNamedPart = 0.1;

// Frames are summed in this many fixed blocks (independent of threads).
constexpr int kBlocks = 16;
constexpr int kBatch = 8;  // frames per rank update

// The owner of a θ entry for messages: "markers.m1.position.x" -> "marker m1
// position"; "joint_sensors.p.bias" -> "bias of p".
std::string ownerPhrase(const std::string& name, std::string* key) {
  const auto last = name.rfind('.');
  const std::string head = name.substr(0, last), tail = name.substr(last + 1);
  if (name.rfind("markers.", 0) == 0) {
    *key = head;
    const std::string m = head.substr(8, head.size() - 8 - 9);  // strip ".position"
    return "marker " + m + " position";
  }
  if (name.rfind("mocap.frame.rotation", 0) == 0) {
    *key = "mocap.frame.rotation";
    return "the mocap rotation";
  }
  if (name.rfind("mocap.frame.translation", 0) == 0) {
    *key = "mocap.frame.translation";
    return "the mocap translation";
  }
  *key = name;
  const std::string sensor = head.substr(head.find('.') + 1);
  return tail + " of " + sensor;
}

std::string axisPhrase(const Eigen::Vector3d& a) {
  const char* names[3] = {"x", "y", "z"};
  for (int i = 0; i < 3; ++i)
    if (std::abs(std::abs(a[i]) - 1.0) < 0.05) return std::string("about ") + names[i];
  char buf[96];
  std::snprintf(buf, sizeof buf, "about the axis [%.2f, %.2f, %.2f]", a.x(), a.y(), a.z());
  return buf;
}

}  // namespace

UncertaintyResult estimateUncertainty(const MeasurementModel& model,
                                      const SensorParameters& theta,
                                      const NoiseModel& noise, const RobustLoss& loss,
                                      const Observations& obs, const RowMatrix& q,
                                      int threads, std::vector<FrameWorkspace>* ws) {
  const int n_theta = model.thetaSize();
  const int dof = model.dof();
  const int T = obs.num_frames;
  UncertaintyResult out;
  std::vector<int> free_of(n_theta, -1);
  for (int i = 0; i < n_theta; ++i)
    if (model.thetaFree()[i]) {
      free_of[i] = static_cast<int>(out.free_index.size());
      out.free_index.push_back(i);
    }
  const int nf = static_cast<int>(out.free_index.size());
  out.std = Eigen::VectorXd::Zero(n_theta);
  if (nf == 0 || T == 0) {
    out.information = Eigen::MatrixXd::Zero(nf, nf);
    return out;
  }

  std::vector<Eigen::MatrixXd> block_S(kBlocks, Eigen::MatrixXd::Zero(nf, nf));
  threads = std::min<int>(resolveThreads(threads), static_cast<int>(ws->size()));
  EvalOptions eo;
  eo.jacobians = true;
  eo.theta_jacobians = true;
  parallelFor(kBlocks, threads, [&](int block, int tid) {
    FrameWorkspace& w = (*ws)[tid];
    Eigen::MatrixXd Hqq(dof, dof), Hqt(dof, nf), X(dof * kBatch, nf);
    Eigen::VectorXd g(dof), qt(dof);
    Eigen::MatrixXd& S = block_S[block];
    const int begin = static_cast<int>(static_cast<long>(T) * block / kBlocks);
    const int end = static_cast<int>(static_cast<long>(T) * (block + 1) / kBlocks);
    int in_batch = 0;
    auto flush = [&]() {
      if (in_batch == 0) return;
      S.selfadjointView<Eigen::Lower>().rankUpdate(
          X.topRows(in_batch * dof).transpose(), -1.0);
      in_batch = 0;
    };
    for (int t = begin; t < end; ++t) {
      qt = q.row(t).transpose();
      evaluateFrame(model, theta, noise, loss, frameReadings(obs, t), qt, eo, &w);
      accumulateNormalEquations(w, &Hqq, &g);
      Hqt.setZero();
      for (int i = 0; i < w.count; ++i) {
        const ReadingJacobian& rj = w.readings[i];
        const std::vector<int>& cols = *rj.q_cols;
        for (int b = 0; b < rj.theta_count; ++b) {
          const int fb = free_of[rj.theta_index[b]];
          if (fb < 0) continue;
          const auto jb = rj.Jtheta.col(b).head(rj.rows);
          for (size_t a = 0; a < cols.size(); ++a)
            Hqt(cols[a], fb) += rj.Jq.col(a).head(rj.rows).dot(jb);
          for (int c = 0; c <= b; ++c) {
            const int fc = free_of[rj.theta_index[c]];
            if (fc < 0) continue;
            const double v = rj.Jtheta.col(c).head(rj.rows).dot(jb);
            S(std::max(fb, fc), std::min(fb, fc)) += v;
            if (fb == fc && b != c) S(fb, fc) += v;  // never: indices distinct
          }
        }
      }
      // Joints no reading sees contribute nothing; a tiny ridge keeps the
      // factorisation defined without changing the observed directions.
      const double eps = 1e-12 * std::max(1.0, Hqq.diagonal().maxCoeff());
      Hqq.diagonal().array() += eps;
      Eigen::LLT<Eigen::MatrixXd> llt(Hqq);
      X.middleRows(in_batch * dof, dof) = llt.matrixL().solve(Hqt);
      if (++in_batch == kBatch) flush();
    }
    flush();
  });
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(nf, nf);
  for (const Eigen::MatrixXd& b : block_S) S += b;
  S = S.selfadjointView<Eigen::Lower>();
  return uncertaintyFromInformation(model, theta, S);
}

UncertaintyResult uncertaintyFromInformation(const MeasurementModel& model,
                                             const SensorParameters& theta,
                                             const Eigen::MatrixXd& S) {
  const int n_theta = model.thetaSize();
  UncertaintyResult out;
  for (int i = 0; i < n_theta; ++i)
    if (model.thetaFree()[i]) out.free_index.push_back(i);
  const int nf = static_cast<int>(out.free_index.size());
  if (S.rows() != nf || S.cols() != nf)
    throw std::invalid_argument("information matrix does not match the free parameters");
  out.std = Eigen::VectorXd::Zero(n_theta);
  out.information = S;
  if (nf == 0) return out;

  // Identifiability in comparable units.
  const Eigen::VectorXd full_scale = model.thetaScale(theta);
  Eigen::VectorXd D(nf);
  for (int i = 0; i < nf; ++i) D[i] = full_scale[out.free_index[i]];
  const Eigen::MatrixXd St = D.asDiagonal() * S * D.asDiagonal();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(St);
  const Eigen::VectorXd lambda = eig.eigenvalues();
  const Eigen::MatrixXd V = eig.eigenvectors();
  const double lmax = std::max(lambda.maxCoeff(), 1e-300);
  Eigen::MatrixXd Sinv = Eigen::MatrixXd::Zero(nf, nf);
  std::vector<bool> confounded(nf, false);
  const Eigen::Matrix3d R = theta.mocap.rotation.toRotationMatrix();
  for (int k = 0; k < nf; ++k) {
    // Unidentifiable: numerically null, or so weak that one standard
    // deviation along it exceeds the parameters' own typical size.
    const bool null = lambda[k] <= 1e-9 * lmax || lambda[k] < 1.0;
    if (!null) {
      Sinv += V.col(k) * V.col(k).transpose() / lambda[k];
      continue;
    }
    const Eigen::VectorXd v = V.col(k) / V.col(k).cwiseAbs().maxCoeff();
    UnidentifiableDirection dir;
    std::vector<std::pair<double, std::string>> owners;
    std::map<std::string, double> owner_weight;
    std::map<std::string, std::string> owner_phrase;
    Eigen::Vector3d rot = Eigen::Vector3d::Zero();
    std::string joint_axis;
    for (int i = 0; i < nf; ++i) {
      // Any part in a null direction makes a parameter undetermined (the
      // drift along it is arbitrary, not small): listed and given no std
      // from 1% of the direction's largest part; named in the reason from
      // 10%.
      if (std::abs(v[i]) < kConfoundedPart) continue;
      confounded[i] = true;
      const std::string& name = model.thetaNames()[out.free_index[i]];
      dir.parameters.push_back(name);
      if (std::abs(v[i]) < kNamedPart) continue;
      std::string key;
      const std::string phrase = ownerPhrase(name, &key);
      owner_weight[key] = std::max(owner_weight[key], std::abs(v[i]));
      owner_phrase[key] = phrase;
      const int ti = out.free_index[i];
      if (ti < 3) rot[ti] = v[i];
      if (ti >= model.jointOffset(0) && ti < model.tendonOffset(0) &&
          (ti - model.jointOffset(0)) % 2 == 1 && joint_axis.empty()) {
        const int s = (ti - model.jointOffset(0)) / 2;
        joint_axis = " about the " + model.sensors().joint_sensors[s].joint_name + " axis";
      }
    }
    for (auto& [key, w] : owner_weight) owners.emplace_back(-w, key);
    std::sort(owners.begin(), owners.end());
    std::string reason;
    for (size_t i = 0; i < owners.size(); ++i) {
      std::string phrase = owner_phrase[owners[i].second];
      if (owners[i].second == "mocap.frame.rotation" && rot.norm() > 0)
        phrase += " " + axisPhrase((R.transpose() * rot).normalized());
      reason += i == 0 ? phrase : (i == 1 ? " trades off with " : ", ") + phrase;
    }
    if (owners.size() == 1) {
      reason += lambda[k] <= 1e-9 * lmax ? " is not determined by the data"
                                         : " is only weakly determined by the data";
    } else {
      reason += joint_axis;
    }
    dir.reason = reason;
    out.unidentifiable.push_back(dir);
  }
  const double inf = std::numeric_limits<double>::infinity();
  for (int i = 0; i < nf; ++i) {
    const int ti = out.free_index[i];
    out.std[ti] = confounded[i] ? inf : D[i] * std::sqrt(std::max(Sinv(i, i), 0.0));
  }
  return out;
}

ParameterStd toParameterStd(const MeasurementModel& model, const Eigen::VectorXd& std) {
  ParameterStd p;
  const SensorSet& s = model.sensors();
  p.mocap_rotation = std.segment<3>(MeasurementModel::kRotationOffset);
  p.mocap_translation = std.segment<3>(MeasurementModel::kTranslationOffset);
  for (size_t m = 0; m < s.markers.size(); ++m)
    p.marker_position.push_back(std.segment<3>(model.markerOffset(static_cast<int>(m))));
  for (size_t j = 0; j < s.joint_sensors.size(); ++j) {
    const int o = model.jointOffset(static_cast<int>(j));
    p.joint_sensor.push_back({std[o], std[o + 1]});
  }
  for (size_t j = 0; j < s.tendon_sensors.size(); ++j) {
    const int o = model.tendonOffset(static_cast<int>(j));
    p.tendon_sensor.push_back({std[o], std[o + 1]});
  }
  return p;
}

}  // namespace stac
