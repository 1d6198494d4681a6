// Mirrors that only tendons see (see tendon_mirror.hpp).
#include "methods/tendon_mirror.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "stac/kinematics.hpp"
#include "stac/sensor_models.hpp"

namespace stac {
namespace {

// Grid points of the centre's search over its span, then golden-section
// steps about the best (to 1e-5 of two grid steps);
// rows of q it uses at most,
// spread over them (a symmetry holds in every frame, and the listing tries
// the centres of every flip a tendon spans: hand24's took 2.5x the
// calibration's time over every row of the subsample).
constexpr int kCentreGrid = 16;
constexpr int kGoldenSteps = 24;
constexpr int kCentreRows = 10;

bool spans(const std::vector<int>& columns, int j) {
  return std::find(columns.begin(), columns.end(), j) != columns.end();
}

// Whether column j moves `link` (through a joint of q or a mimic of it).
bool moves(const RobotModel& robot, int j, int link) {
  for (int mj : robot.supportingJoints(link))
    if (robot.movableJoints()[mj].q_index == j) return true;
  return false;
}

// The tendons whose length depends on column j: a coupling over it, or a
// path with anchors on both sides of it (a joint above every anchor turns
// the whole path, its length with none).
std::vector<int> tendonsOver(const MeasurementModel& model, int j) {
  std::vector<int> out;
  const RobotModel& robot = model.robot();
  const auto& tendons = model.sensors().tendon_sensors;
  for (int s = 0; s < static_cast<int>(tendons.size()); ++s) {
    if (!spans(model.tendonColumns(s), j)) continue;
    if (tendons[s].kind == TendonSensorConfig::Kind::kCoupling) {
      out.push_back(s);
      continue;
    }
    size_t moved = 0;
    for (const PathAnchor& a : tendons[s].path) moved += moves(robot, j, a.link);
    if (moved > 0 && moved < tendons[s].path.size()) out.push_back(s);
  }
  return out;
}

// Σ over the rows of q and the tendons of (L(q) - L(q mirrored about c))²:
// lengths, not readings, so that a map the fit has not placed yet (a gain
// still at its seed, or near zero) moves no centre.
class MirrorMismatch {
 public:
  MirrorMismatch(const MeasurementModel& model, const SensorParameters& theta, const RowMatrix& q,
                 const RowMatrix& moved, int j)
      : model_(model), q_(q), moved_(moved), j_(j), tendons_(tendonsOver(model, j)),
        ws_(model.robot()) {
    applyJointOrigins(model, theta, &ws_);
    const int n = static_cast<int>(q.rows());
    for (int k = 0; k < std::min(n, kCentreRows); ++k)
      rows_.push_back(n <= kCentreRows ? k : static_cast<int>((k + 0.5) * n / kCentreRows));
    before_.resize(q.rows() * tendons_.size());
    for (int t : rows_) {
      const std::vector<double> r = readings(q.row(t).transpose());
      std::copy(r.begin(), r.end(), before_.begin() + t * tendons_.size());
    }
  }
  bool empty() const { return tendons_.empty() || q_.rows() == 0; }
  double operator()(double c) {
    double sum = 0;
    for (int t : rows_) {
      Eigen::VectorXd qt = moved_.row(t).transpose();
      qt[j_] = 2 * c - q_(t, j_);
      const std::vector<double> r = readings(qt);
      for (size_t k = 0; k < r.size(); ++k) {
        const double d = r[k] - before_[t * tendons_.size() + k];
        sum += d * d;
      }
    }
    return sum;
  }

 private:
  std::vector<double> readings(const Eigen::VectorXd& q) {
    forwardKinematics(model_.robot(), q, &ws_);
    std::vector<double> out;
    for (int s : tendons_)
      out.push_back(tendon_sensor::length(model_.robot(), model_.sensors().tendon_sensors[s], ws_));
    return out;
  }
  const MeasurementModel& model_;
  const RowMatrix& q_;
  const RowMatrix& moved_;
  const int j_;
  const std::vector<int> tendons_;
  std::vector<int> rows_;  // the rows of q the mismatch sums over
  KinematicsWorkspace ws_;
  std::vector<double> before_;
};

}  // namespace

bool seenByTendons(const MeasurementModel& model, int j) { return !tendonsOver(model, j).empty(); }

bool seenOnlyByTendons(const MeasurementModel& model, int j) {
  for (int m = 0; m < static_cast<int>(model.sensors().markers.size()); ++m)
    if (spans(model.markerColumns(m), j)) return false;
  return !tendonsOver(model, j).empty();
}

std::optional<double> tendonMirrorCentre(const MeasurementModel& model,
                                         const SensorParameters& theta, const RowMatrix& q,
                                         int j, const RowMatrix* moved) {
  if (moved && (moved->rows() != q.rows() || moved->cols() != q.cols())) return std::nullopt;
  MirrorMismatch mismatch(model, theta, q, moved ? *moved : q, j);
  if (mismatch.empty()) return std::nullopt;
  const RobotModel& robot = model.robot();
  const bool revolute = robot.movableJoints()[robot.qJoints()[j]].type != JointType::kPrismatic;
  const double lo = robot.lowerLimits()[j], hi = robot.upperLimits()[j];
  const double mean = q.col(j).mean();
  // A revolute joint's mirrors about c and c + π are one (a whole turn
  // apart): half a turn of centres about the motion's mean covers them.
  // A prismatic joint's centre lies within its limits (or 1 m of its mean).
  double from = mean - M_PI / 2, to = mean + M_PI / 2;
  if (!revolute) {
    from = std::isfinite(lo) ? lo : mean - 1.0;
    to = std::isfinite(hi) ? hi : mean + 1.0;
  }
  const double step = (to - from) / kCentreGrid;
  double best = from, best_cost = std::numeric_limits<double>::infinity();
  for (int k = 0; k < kCentreGrid; ++k) {
    const double c = from + (k + 0.5) * step;
    const double e = mismatch(c);
    if (e < best_cost) best_cost = e, best = c;
  }
  // Golden-section search within a grid step either side.
  const double g = 0.5 * (std::sqrt(5.0) - 1);
  double a = best - step, b = best + step;
  double x1 = b - g * (b - a), x2 = a + g * (b - a), f1 = mismatch(x1), f2 = mismatch(x2);
  for (int it = 0; it < kGoldenSteps; ++it) {
    if (f1 < f2) {
      b = x2, x2 = x1, f2 = f1, x1 = b - g * (b - a), f1 = mismatch(x1);
    } else {
      a = x1, x1 = x2, f1 = f2, x2 = a + g * (b - a), f2 = mismatch(x2);
    }
  }
  double c = 0.5 * (a + b);
  // Of c + kπ, the one whose mirrored motion (mean 2c - mean) lies
  // nearest the middle of the limits.
  const double mid = 0.5 * (lo + hi);
  if (revolute && std::isfinite(mid)) c += M_PI * std::round((mid + mean - 2 * c) / (2 * M_PI));
  return c;
}

}  // namespace stac
