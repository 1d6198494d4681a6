#include "methods/mirror_centres.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

#include "solve/lm_damping.hpp"
#include "stac/kinematics.hpp"

namespace stac {

namespace {

// A flip matches where the bottom link's pose does, on kSamples spread
// configurations: three generic ones leave no centres exact by accident.
constexpr int kSamples = 3;
// Exact enough: every coordinate of the pose (metres, and rotation-matrix entries)
// within this. An inexact flip misses by the links' offsets, centimetres
// (a Jaco's shoulder: 1.6 and 11 mm offsets), yet a URDF's rounding and a
// sub-millimetre offset leave a mirror that the markers' noise hides (an
// unseen Hextilt flying arm's wrist, its next link turned by "1.5708" and
// offset by 0.25 mm: 0.5 mm off at its best centres). Those are as good a
// start for the jump, which refines from there, as an exact one.
constexpr double kMirrorTolerance = 1e-3;
// Exact but for rounding: no other start can do better.
constexpr double kRounding = 1e-8;
// Columns from which the centres' starts (below) are the two uniform ones
// only, not every combination.
constexpr int kMaxCombinedStarts = 4;

// The movable joint a column drives (its master; mimic followers move with it).
int movableOf(const RobotModel& robot, int column) { return robot.qJoints()[column]; }

// The column among `moved` whose link has every other moved column's joint
// on its path to the root, or -1.
int deepest(const RobotModel& robot, const std::vector<int>& moved) {
  for (int j : moved) {
    const int link = robot.movableJoints()[movableOf(robot, j)].child_link;
    const std::vector<int>& support = robot.supportingJoints(link);
    const bool below_all = std::all_of(moved.begin(), moved.end(), [&](int other) {
      return std::find(support.begin(), support.end(), movableOf(robot, other)) != support.end();
    });
    if (below_all) return j;
  }
  return -1;
}

// Configuration s of kSamples: every joint at a fixed, irregular share of
// its limits (of a turn where it has none).
Eigen::VectorXd sampleConfiguration(const RobotModel& robot, int s) {
  Eigen::VectorXd q(robot.dof());
  for (int j = 0; j < robot.dof(); ++j) {
    const double share = std::fmod(0.31 + 0.7548776662 * (s + 1) + 0.5698402910 * (j + 1), 1.0);
    double lo = robot.lowerLimits()[j], hi = robot.upperLimits()[j];
    if (!std::isfinite(lo) || !std::isfinite(hi)) lo = -M_PI, hi = M_PI;
    q[j] = lo + share * (hi - lo);
  }
  return q;
}

// How far the flip about centres c moves `link` on each sample: position
// and rotation-matrix differences, 12 per sample.
class FlipMismatch {
 public:
  FlipMismatch(const RobotModel& robot, std::vector<int> flip, std::vector<int> half_turn,
               int link)
      : robot_(robot), flip_(std::move(flip)), half_turn_(std::move(half_turn)), link_(link),
        ws_(robot) {
    for (int s = 0; s < kSamples; ++s) {
      samples_.push_back(sampleConfiguration(robot, s));
      forwardKinematics(robot, samples_.back(), &ws_);
      poses_.push_back(ws_.link_pose[link_]);
    }
  }
  int size() const { return 12 * kSamples; }

  Eigen::VectorXd operator()(const Eigen::VectorXd& c) {
    Eigen::VectorXd r(size());
    for (int s = 0; s < kSamples; ++s) {
      Eigen::VectorXd q = samples_[s];
      for (size_t i = 0; i < flip_.size(); ++i) q[flip_[i]] = 2 * c[i] - q[flip_[i]];
      for (int j : half_turn_) q[j] += M_PI;
      forwardKinematics(robot_, q, &ws_);
      const Eigen::Isometry3d& moved = ws_.link_pose[link_];
      r.segment<3>(12 * s) = moved.translation() - poses_[s].translation();
      const Eigen::Matrix3d dr = moved.linear() - poses_[s].linear();
      r.segment<9>(12 * s + 3) = Eigen::Map<const Eigen::Matrix<double, 9, 1>>(dr.data());
    }
    return r;
  }

 private:
  const RobotModel& robot_;
  std::vector<int> flip_, half_turn_;
  int link_;
  KinematicsWorkspace ws_;
  std::vector<Eigen::VectorXd> samples_;
  std::vector<Eigen::Isometry3d> poses_;
};

// Centres and how far their flip misses (the largest coordinate).
struct Centres {
  Eigen::VectorXd c;
  double mismatch;
};

// Levenberg-Marquardt on the centres from `c` (the frames' damping
// policy, lm_damping.hpp: a handful of angles, as a frame's), with a
// forward-difference Jacobian: the mismatch is smooth and periodic.
Centres leastMismatch(FlipMismatch& mismatch, Eigen::VectorXd c) {
  constexpr int kMaxSteps = 60;
  constexpr double kDelta = 1e-7;  // the difference step, radians
  const int n = static_cast<int>(c.size());
  Eigen::VectorXd r = mismatch(c);
  double lambda = 1e-3;
  for (int it = 0; it < kMaxSteps && r.squaredNorm() > 0; ++it) {
    Eigen::MatrixXd J(r.size(), n);
    for (int i = 0; i < n; ++i) {
      Eigen::VectorXd ci = c;
      ci[i] += kDelta;
      J.col(i) = (mismatch(ci) - r) / kDelta;
    }
    const Eigen::MatrixXd H = J.transpose() * J;
    const Eigen::VectorXd g = J.transpose() * r;
    for (;;) {
      Eigen::MatrixXd A = H;
      addDamping(lambda, H, &A);
      const Eigen::VectorXd next = c - A.ldlt().solve(g);
      const Eigen::VectorXd rn = mismatch(next);
      if (rn.squaredNorm() < r.squaredNorm()) {
        c = next, r = rn, lambda = acceptedStep(kFrameSchedule, lambda);
        break;
      }
      if (lambda >= kFrameSchedule.max)  // no step helps: a minimum
        return {c, r.lpNorm<Eigen::Infinity>()};
      lambda = rejectedStep(kFrameSchedule, lambda);
    }
  }
  return {c, r.lpNorm<Eigen::Infinity>()};
}

// The starts of the search: each centre at 0 or π/2, in every combination
// for a few columns (two uniform starts beyond). One start is not enough:
// the mismatch is periodic in each centre, and where a link is turned a
// quarter turn in the URDF its exact centre is π/2 and zero its worst,
// where the gradient vanishes (the Hextilt's wrist, above).
std::vector<Eigen::VectorXd> centreStarts(int n) {
  std::vector<Eigen::VectorXd> starts;
  if (n > kMaxCombinedStarts) {
    starts.push_back(Eigen::VectorXd::Zero(n));
    starts.push_back(Eigen::VectorXd::Constant(n, M_PI / 2));
    return starts;
  }
  for (int mask = 0; mask < (1 << n); ++mask) {
    Eigen::VectorXd c(n);
    for (int i = 0; i < n; ++i) c[i] = ((mask >> i) & 1) ? M_PI / 2 : 0.0;
    starts.push_back(c);
  }
  return starts;
}

}  // namespace

std::optional<std::vector<double>> exactMirrorCentres(const RobotModel& robot,
                                                      const std::vector<int>& flip,
                                                      const std::vector<int>& half_turn) {
  if (flip.empty() || half_turn.empty()) return std::nullopt;
  std::vector<int> moved = flip;
  moved.insert(moved.end(), half_turn.begin(), half_turn.end());
  const int bottom = deepest(robot, moved);
  if (bottom < 0 || std::find(half_turn.begin(), half_turn.end(), bottom) == half_turn.end())
    return std::nullopt;
  for (int j : moved)
    if (robot.movableJoints()[movableOf(robot, j)].type == JointType::kPrismatic)
      return std::nullopt;
  FlipMismatch mismatch(robot, flip, half_turn,
                        robot.movableJoints()[movableOf(robot, bottom)].child_link);
  // The start whose search ends nearest exact, from zero first, and the
  // first one that ends exact to rounding: a start can stop in a local
  // minimum within the tolerance where another reaches the exact centres.
  std::optional<Centres> best;
  for (const Eigen::VectorXd& start : centreStarts(static_cast<int>(flip.size()))) {
    Centres found = leastMismatch(mismatch, start);
    if (!(found.mismatch <= (best ? best->mismatch : kMirrorTolerance))) continue;
    best = std::move(found);
    if (best->mismatch <= kRounding) break;
  }
  if (!best) return std::nullopt;
  const Eigen::VectorXd& c = best->c;
  std::vector<double> out;
  for (int i = 0; i < c.size(); ++i) out.push_back(c[i] - M_PI * std::round(c[i] / M_PI));
  return out;
}

}  // namespace stac
