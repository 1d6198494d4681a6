#include "solve/pot_chart.hpp"

#include <cmath>

namespace stac {

namespace {
// The pot's share of its joint's angle information above which the
// inverse chart is the nearer-quadratic one (pot_chart.hpp).
constexpr double kDominatedShare = 0.5;
}  // namespace

PotCharts::PotCharts(const ThetaSpace& space, const SensorParameters& theta,
                     const Eigen::MatrixXd& S, const Eigen::VectorXd& D,
                     const std::vector<double>& pivots)
    : space_(&space) {
  const std::vector<int>& free_of = space.freePosition();
  for (size_t j = 0; j < theta.joint_sensor.size(); ++j) {
    const int o = space.jointOffset(static_cast<int>(j));
    Pot p;
    p.sensor = static_cast<int>(j);
    p.gain = free_of[o];
    p.bias = free_of[o + 1];
    const double g = theta.joint_sensor[j].gain, b = theta.joint_sensor[j].bias;
    if (p.gain < 0 || !(std::abs(g) > 0) || !std::isfinite(g)) continue;
    // h = 1 - S_gg / D_gg: the share of the gain's curvature the q_t take.
    if (!(D[p.gain] > 0) || !(S(p.gain, p.gain) < (1 - kDominatedShare) * D[p.gain])) continue;
    // g = 1/α, b = p̄ - β/α with β = (p̄ - b)/g: dg = -g² dα,
    // db = g (p̄ - b) dα - g dβ.
    p.pivot = pivots[j];
    p.T << -g * g, 0.0, g * (p.pivot - b), -g;
    pots_.push_back(p);
  }
}

void PotCharts::toChart(Eigen::MatrixXd* S, Eigen::VectorXd* g) const {
  for (const Pot& p : pots_) {
    if (p.bias < 0) {
      const double t = p.T(0, 0);
      S->col(p.gain) *= t;
      S->row(p.gain) *= t;
      (*g)[p.gain] *= t;
      continue;
    }
    Eigen::MatrixXd cols(S->rows(), 2);
    cols << S->col(p.gain), S->col(p.bias);
    cols = cols * p.T;
    S->col(p.gain) = cols.col(0);
    S->col(p.bias) = cols.col(1);
    Eigen::MatrixXd rows(2, S->cols());
    rows << S->row(p.gain), S->row(p.bias);
    rows = p.T.transpose() * rows;
    S->row(p.gain) = rows.row(0);
    S->row(p.bias) = rows.row(1);
    const Eigen::Vector2d gb = p.T.transpose() * Eigen::Vector2d((*g)[p.gain], (*g)[p.bias]);
    (*g)[p.gain] = gb[0];
    (*g)[p.bias] = gb[1];
  }
}

Eigen::VectorXd PotCharts::linearStep(const Eigen::VectorXd& chart_step) const {
  Eigen::VectorXd d = chart_step;
  for (const Pot& p : pots_) {
    if (p.bias < 0) {
      d[p.gain] = p.T(0, 0) * chart_step[p.gain];
      continue;
    }
    const Eigen::Vector2d gb =
        p.T * Eigen::Vector2d(chart_step[p.gain], chart_step[p.bias]);
    d[p.gain] = gb[0];
    d[p.bias] = gb[1];
  }
  return d;
}

SensorParameters PotCharts::retract(const SensorParameters& theta,
                                    const Eigen::VectorXd& chart_step) const {
  SensorParameters out = space_->plusFree(theta, linearStep(chart_step));
  for (const Pot& p : pots_) {
    const GainBias& was = theta.joint_sensor[p.sensor];
    const double alpha = 1.0 / was.gain + chart_step[p.gain];
    const double beta =
        (p.pivot - was.bias) / was.gain + (p.bias < 0 ? 0.0 : chart_step[p.bias]);
    // α = 0 exactly is the joint held still, g = ∞: keep the linear step.
    if (!(std::abs(alpha) > 0) || !std::isfinite(1.0 / alpha)) continue;
    GainBias& gb = out.joint_sensor[p.sensor];
    gb.gain = 1.0 / alpha;
    if (p.bias >= 0) gb.bias = p.pivot - beta / alpha;
  }
  return out;
}

std::vector<double> potPivots(const Observations& obs) {
  std::vector<double> out(static_cast<size_t>(obs.joint.cols()), 0.0);
  for (Eigen::Index j = 0; j < obs.joint.cols(); ++j) {
    double sum = 0;
    int n = 0;
    for (Eigen::Index t = 0; t < obs.joint.rows(); ++t)
      if (std::isfinite(obs.joint(t, j))) sum += obs.joint(t, j), ++n;
    if (n > 0) out[j] = sum / n;
  }
  return out;
}

}  // namespace stac
