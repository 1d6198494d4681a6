#include "solve/spike_screen.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>
#include <vector>

namespace stac {
namespace {

constexpr int kHalfWindow = 3;     // frames each side
constexpr double kCandidateScales = 5.0;
constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
constexpr double kMadToSigma = 1.4826;
constexpr double kSmoothness = 0.1;  // neighbour scale / spread, at most
constexpr double kStillScale = 3.0;  // or neighbour scale / seed σ

// Median of v (non-empty); reorders v.
double median(std::vector<double>* v) {
  const size_t n = v->size();
  std::nth_element(v->begin(), v->begin() + n / 2, v->end());
  const double hi = (*v)[n / 2];
  if (n % 2) return hi;
  return 0.5 * (hi + *std::max_element(v->begin(), v->begin() + n / 2));
}

// x_t − the median of its present neighbours within kHalfWindow frames (at
// least 3 of them): robust to two gross neighbours among six, but biased by the
// motion's curvature (4 x'' Δt² on a parabola).
std::vector<double> medianDeviations(const Eigen::Ref<const Eigen::VectorXd>& x) {
  const int n = static_cast<int>(x.size());
  std::vector<double> d(n, kNan), near;
  for (int t = 0; t < n; ++t) {
    if (!std::isfinite(x[t])) continue;
    near.clear();
    for (int k = std::max(0, t - kHalfWindow); k <= std::min(n - 1, t + kHalfWindow); ++k)
      if (k != t && std::isfinite(x[k])) near.push_back(x[k]);
    if (near.size() >= 3) d[t] = x[t] - median(&near);
  }
  return d;
}

// x_t − the least-squares parabola through its present neighbours that
// `skip` does not exclude, within kHalfWindow frames or, where fewer than 3
// are left there or none on one side, within twice that (at least 5 there
// if all on one side): unbiased on smooth motion, not robust, hence the
// skip.
std::vector<double> parabolaDeviations(const Eigen::Ref<const Eigen::VectorXd>& x,
                                       const std::vector<double>& at,
                                       const std::vector<bool>& skip) {
  const int n = static_cast<int>(x.size());
  std::vector<double> d(n, kNan);
  for (int t = 0; t < n; ++t) {
    if (!std::isfinite(x[t])) continue;
    for (int half : {kHalfWindow, 2 * kHalfWindow}) {
      Eigen::Matrix3d A = Eigen::Matrix3d::Zero();
      Eigen::Vector3d b = Eigen::Vector3d::Zero();
      int count = 0, before = 0, after = 0;
      for (int k = std::max(0, t - half); k <= std::min(n - 1, t + half); ++k) {
        if (k == t || !std::isfinite(x[k]) || skip[k]) continue;
        const double u = at[k] - at[t];
        const Eigen::Vector3d f(1, u, u * u);
        A += f * f.transpose();
        b += f * x[k];
        ++count, before += k < t, after += k > t;
      }
      // At the log's ends, one side only, extrapolated by a frame.
      if ((count >= 3 && before > 0 && after > 0) || (half > kHalfWindow && count >= 5)) {
        d[t] = x[t] - A.ldlt().solve(b)[0];
        break;
      }
    }
  }
  return d;
}

// 1.4826 × the median |v| over the finite entries, and their count.
std::pair<double, int> robustScale(const std::vector<double>& v) {
  std::vector<double> a;
  for (double e : v)
    if (std::isfinite(e)) a.push_back(std::abs(e));
  return {a.empty() ? 0.0 : kMadToSigma * median(&a), static_cast<int>(a.size())};
}

}  // namespace

std::vector<double> framePositions(const std::vector<double>& time, int n) {
  std::vector<double> at(n);
  for (int t = 0; t < n; ++t) at[t] = t;
  if (static_cast<int>(time.size()) != n || n < 2) return at;
  std::vector<double> dt;
  for (int t = 1; t < n; ++t) {
    if (!(time[t] > time[t - 1])) return at;
    dt.push_back(time[t] - time[t - 1]);
  }
  const double step = median(&dt);
  for (int t = 0; t < n; ++t) at[t] = (time[t] - time[0]) / step;
  return at;
}

std::vector<bool> columnSpikes(const Eigen::Ref<const Eigen::VectorXd>& x, double sigma,
                               const std::vector<double>& positions) {
  const int n = static_cast<int>(x.size());
  const std::vector<double> at =
      static_cast<int>(positions.size()) == n ? positions : framePositions({}, n);
  std::vector<bool> spike(n, false);
  // Candidates first, by the robust median and a low bound; they only stop
  // being neighbours in the parabola's fit, so a good reading among them
  // costs nothing.
  const std::vector<double> d0 = medianDeviations(x);
  const double scale0 = robustScale(d0).first;
  std::vector<bool> candidate(n, false);
  for (int t = 0; t < n; ++t)
    candidate[t] = std::isfinite(d0[t]) && std::abs(d0[t]) > kCandidateScales * std::max(scale0, sigma);
  std::vector<double> d = parabolaDeviations(x, at, candidate);
  const auto [scale, verdicts] = robustScale(d);
  if (verdicts < kMinScreenedFrames) return spike;
  std::vector<double> values;
  for (int t = 0; t < n; ++t)
    if (std::isfinite(x[t])) values.push_back(x[t]);
  const double centre = median(&values);
  for (double& v : values) v = std::abs(v - centre);
  const double spread = kMadToSigma * median(&values);
  // Smooth in time: the neighbours predict a reading far better than the
  // column varies, or as well as its noise (a sensor that hardly moves).
  if (!(scale <= kSmoothness * spread || scale <= kStillScale * sigma)) return spike;
  const double bound = kSpikeScales * std::max(scale, sigma);
  for (int t = 0; t < n; ++t) spike[t] = std::isfinite(d[t]) && std::abs(d[t]) > bound;
  // Again without the spikes found as neighbours: one the candidates missed
  // may have bent a good reading's parabola.
  for (int t = 0; t < n; ++t) candidate[t] = candidate[t] || spike[t];
  d = parabolaDeviations(x, at, candidate);
  for (int t = 0; t < n; ++t) spike[t] = std::isfinite(d[t]) && std::abs(d[t]) > bound;
  return spike;
}

SpikeScreen screenSpikes(const Observations& obs, const NoiseModel& seed) {
  SpikeScreen out;
  const std::vector<double> at = framePositions(obs.time, obs.num_frames);
  out.kept = obs;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  auto scalar = [&](RowMatrix* m, const std::vector<double>& sigma, SensorGroup g) {
    for (int c = 0; c < m->cols(); ++c) {
      const Eigen::VectorXd col = m->col(c);
      const std::vector<bool> spike = columnSpikes(col, sigma[c], at);
      for (int t = 0; t < m->rows(); ++t)
        if (spike[t]) (*m)(t, c) = nan, ++out.set_aside[static_cast<int>(g)];
    }
  };
  scalar(&out.kept.joint, seed.joint, SensorGroup::kJoint);
  scalar(&out.kept.tendon, seed.tendon, SensorGroup::kTendon);
  RowMatrix& markers = out.kept.marker;
  for (int m = 0; 3 * m < markers.cols(); ++m) {
    std::vector<bool> any(markers.rows(), false);
    for (int i = 0; i < 3; ++i) {
      const Eigen::VectorXd col = markers.col(3 * m + i);
      const std::vector<bool> spike = columnSpikes(col, seed.marker[m], at);
      for (int t = 0; t < markers.rows(); ++t) any[t] = any[t] || spike[t];
    }
    for (int t = 0; t < markers.rows(); ++t)
      if (any[t]) {
        markers.block(t, 3 * m, 1, 3).setConstant(nan);
        ++out.set_aside[static_cast<int>(SensorGroup::kMarker)];
      }
  }
  return out;
}

}  // namespace stac
