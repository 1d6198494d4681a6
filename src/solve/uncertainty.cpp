#include "solve/uncertainty.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <stdexcept>

#include "solve/origin_prior.hpp"
#include "solve/schur.hpp"

namespace stac {
namespace {

constexpr double kConfoundedPart = 0.01;
constexpr double kNamedPart = 0.1;

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
  const ThetaSpace& space = model.thetaSpace();
  if (space.freeSize() == 0 || obs.num_frames == 0) {
    UncertaintyResult out;
    out.free_index = space.freeIndex();
    out.std = Eigen::VectorXd::Zero(space.size());
    out.information = Eigen::MatrixXd::Zero(space.freeSize(), space.freeSize());
    return out;
  }
  // The undamped reduction (λ = 0): S is the information about θ alone.
  Eigen::MatrixXd scores;
  ReducedSystem rs = reduceOntoTheta(model, theta, noise, loss, obs, q, 0.0, true, threads, ws,
                                     FrameOptions(), nullptr, &scores);
  // The posterior's information: the prior counts in the bread and, being
  // no data, as itself in the meat.
  Eigen::MatrixXd prior = Eigen::MatrixXd::Zero(rs.S.rows(), rs.S.cols());
  Eigen::VectorXd prior_gradient = Eigen::VectorXd::Zero(rs.g.size());
  addOriginPrior(space, theta, &prior, &prior_gradient);
  rs.S += prior;
  rs.g += prior_gradient;
  scores += prior;
  return uncertaintyFromInformation(model, theta, rs.S, &scores, &rs.g, rs.q_decrement);
}

namespace {

// One null (or weak) direction v of the scaled information, as parameters
// and a sentence: "bias of p trades off with the mocap rotation about z
// about the j1 axis". Marks the entries taking part in *confounded.
UnidentifiableDirection describeDirection(const ThetaSpace& space, const SensorParameters& theta,
                                          const std::vector<int>& free_index,
                                          const Eigen::VectorXd& v, bool exactly_null,
                                          std::vector<bool>* confounded) {
  UnidentifiableDirection dir;
  std::map<std::string, double> owner_weight;
  std::map<std::string, std::string> owner_phrase;
  Eigen::Vector3d rot = Eigen::Vector3d::Zero();
  std::string joint_axis;
  for (int i = 0; i < static_cast<int>(free_index.size()); ++i) {
    // Any part in a null direction makes a parameter undetermined (the
    // drift along it is arbitrary, not small): listed and given no std
    // from 1% of the direction's largest part; named in the reason from
    // 10%.
    if (std::abs(v[i]) < kConfoundedPart) continue;
    (*confounded)[i] = true;
    const int ti = free_index[i];
    dir.parameters.push_back(space.names()[ti]);
    if (std::abs(v[i]) < kNamedPart) continue;
    const std::string key = space.ownerKey(ti);
    owner_weight[key] = std::max(owner_weight[key], std::abs(v[i]));
    owner_phrase[key] = space.ownerPhrase(ti);
    const ThetaEntry e = space.entry(ti);
    if (e.block == ThetaBlock::kMocapRotation) rot[e.component] = v[i];
    if (e.block == ThetaBlock::kJointSensor && e.component == 1 && joint_axis.empty())
      joint_axis = " about the " + space.sensors().joint_sensors[e.item].joint_name + " axis";
  }
  std::vector<std::pair<double, std::string>> owners;
  for (auto& [key, w] : owner_weight) owners.emplace_back(-w, key);
  std::sort(owners.begin(), owners.end());
  const Eigen::Matrix3d R = theta.mocap.rotation.toRotationMatrix();
  std::string reason;
  for (size_t i = 0; i < owners.size(); ++i) {
    std::string phrase = owner_phrase[owners[i].second];
    if (owners[i].second == "mocap.frame.rotation" && rot.norm() > 0)
      phrase += " " + axisPhrase((R.transpose() * rot).normalized());
    reason += i == 0 ? phrase : (i == 1 ? " trades off with " : ", ") + phrase;
  }
  if (owners.size() == 1) {
    reason += exactly_null ? " is not determined by the data"
                           : " is only weakly determined by the data";
  } else {
    reason += joint_axis;
  }
  dir.reason = reason;
  dir.kind = exactly_null ? Undetermined::kNull : Undetermined::kWeak;
  return dir;
}

}  // namespace

UncertaintyResult uncertaintyFromInformation(const MeasurementModel& model,
                                             const SensorParameters& theta,
                                             const Eigen::MatrixXd& S,
                                             const Eigen::MatrixXd* score_outer,
                                             const Eigen::VectorXd* gradient,
                                             double q_decrement) {
  const ThetaSpace& space = model.thetaSpace();
  UncertaintyResult out;
  out.free_index = space.freeIndex();
  const int nf = space.freeSize();
  if (S.rows() != nf || S.cols() != nf)
    throw std::invalid_argument("information matrix does not match the free parameters");
  out.std = Eigen::VectorXd::Zero(space.size());
  out.information = S;
  if (nf == 0) return out;

  // Identifiability in comparable units.
  const Eigen::VectorXd full_scale = space.scale(theta);
  Eigen::VectorXd D(nf);
  for (int i = 0; i < nf; ++i) D[i] = full_scale[out.free_index[i]];
  const Eigen::MatrixXd St = D.asDiagonal() * S * D.asDiagonal();
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(St);
  const Eigen::VectorXd lambda = eig.eigenvalues();
  const Eigen::MatrixXd V = eig.eigenvectors();
  const double lmax = std::max(lambda.maxCoeff(), 1e-300);
  Eigen::MatrixXd Sinv = Eigen::MatrixXd::Zero(nf, nf);
  std::vector<bool> confounded(nf, false);
  for (int k = 0; k < nf; ++k) {
    // Unidentifiable: numerically null, or so weak that one standard
    // deviation along it exceeds the parameters' own typical size.
    // A direction the origin prior (MAP) determines more than the data
    // does is not unidentifiable: it stays on the prior (reported apart).
    double prior_part = 0;
    for (int i = 0; i < nf; ++i) {
      const double p = space.priorStd(out.free_index[i]);
      if (p > 0) prior_part += V(i, k) * V(i, k) * std::pow(D[i] / p, 2);
    }
    const bool on_prior = prior_part > 0.5 * lambda[k];
    const bool null = !on_prior && (lambda[k] <= 1e-9 * lmax || lambda[k] < 1.0);
    if (!null) {
      Sinv += V.col(k) * V.col(k).transpose() / lambda[k];
      continue;
    }
    const Eigen::VectorXd v = V.col(k) / V.col(k).cwiseAbs().maxCoeff();
    out.unidentifiable.push_back(describeDirection(space, theta, out.free_index, v,
                                                   lambda[k] <= 1e-9 * lmax, &confounded));
  }
  if (gradient) {
    const Eigen::VectorXd scaled = D.asDiagonal() * (*gradient);
    out.decrement = q_decrement + 0.5 * scaled.dot(Sinv * scaled);
  }
  // The sandwich S⁺ B S⁺ where the frames' scores were given: the larger of
  // it and S⁺ (see the header).
  Eigen::VectorXd var = Sinv.diagonal();
  if (score_outer) {
    if (score_outer->rows() != nf || score_outer->cols() != nf)
      throw std::invalid_argument("score outer product does not match the free parameters");
    const Eigen::MatrixXd Bt = D.asDiagonal() * (*score_outer) * D.asDiagonal();
    var = var.cwiseMax((Sinv * Bt * Sinv).diagonal());
  }
  const double inf = std::numeric_limits<double>::infinity();
  for (int i = 0; i < nf; ++i) {
    const int ti = out.free_index[i];
    out.std[ti] = confounded[i] ? inf : D[i] * std::sqrt(std::max(var[i], 0.0));
  }
  return out;
}

}  // namespace stac
