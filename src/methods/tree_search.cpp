// The tree-order search of the pots' initial maps (see tree_search.hpp).
#include "methods/tree_search.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "methods/regression.hpp"
#include "methods/world_turn.hpp"
#include "stac/kinematics.hpp"
#include "solve/theta_phase.hpp"

namespace stac {
namespace {

// σ of the readings a stage leaves out: their weight is 1e-12 of a
// millimetre-σ marker's, nothing, while the model and θ keep their layout.
constexpr double kLeftOut = 1e6;
// Fits kept from one stage to the next.
constexpr int kBeam = 3;
// Coverage scales of a start: the guess's (80% of the range), half, a
// quarter. (Where the limits span more than a turn, starts of a one-turn
// guess instead or as well were tried: an unseen Solo 12's basin truth 5,
// its knee's every start swept 2.5x too far, was then reached, but ur5
// basin truths that had been reached went to wrong minima, plain log truth
// 17 with the one-turn scales alone, partial-swing truth 4 with both.)
constexpr double kStartScales[] = {1.0, 0.5, 0.25};
// Levenberg-Marquardt iterations of one start: a start in the right basin
// is close after a few; the rest only need to be told apart.
constexpr int kStartIterations = 15;
constexpr int kSearchFrames = 80;
constexpr int kMinFrames = 20;
// One stage: the guesses whose maps it searches, and the markers in its fit.
struct Stage {
  std::vector<int> guesses;
  std::vector<bool> in_fit;  // per marker
};

// The stages, from the root outward: a joint joins the first stage in
// whose fit some marker it moves appears. Joints below which no marker is
// ever seen join none (their guesses stand).
std::vector<Stage> planStages(const MeasurementModel& model, const std::vector<int>& guess_of,
                              const std::vector<int>& order) {
  const int M = static_cast<int>(model.sensors().markers.size());
  std::vector<bool> processed(model.dof(), false), in_fit(M, false);
  auto seen = [&](int m) {
    for (int c : model.markerColumns(m))
      if (!processed[c]) return false;
    return true;
  };
  for (int m = 0; m < M; ++m) in_fit[m] = seen(m);
  std::vector<Stage> stages;
  std::vector<int> pending;
  for (int j : order) {
    processed[j] = true;
    pending.push_back(guess_of[j]);
    bool new_marker = false;
    for (int m = 0; m < M; ++m)
      if (!in_fit[m] && seen(m)) in_fit[m] = new_marker = true;
    if (!new_marker) continue;
    stages.push_back({pending, in_fit});
    pending.clear();
  }
  return stages;
}

// The sensors of a stage's fit: the markers it sees, the defining pots of
// the joints processed so far (the others held at their maps), nothing
// else (left out: held, with σ kLeftOut).
SensorSet stageSensors(const SensorSet& all, const JointSources& sources,
                       const std::vector<bool>& in_fit, const std::vector<bool>& searched) {
  SensorSet s = all;
  s.joint_origins.clear();
  for (size_t m = 0; m < s.markers.size(); ++m)
    if (!in_fit[m]) s.markers[m].fixed = true, s.markers[m].sigma = kLeftOut;
  for (size_t j = 0; j < s.joint_sensors.size(); ++j) {
    if (sources.defining[j] && searched[j]) continue;
    s.joint_sensors[j].fixed = FixedGainBias::both(true);
    if (!sources.defining[j]) s.joint_sensors[j].sigma = kLeftOut;
  }
  for (TendonSensorConfig& t : s.tendon_sensors) {
    t.fixed = FixedGainBias::both(true);
    t.sigma = kLeftOut;
  }
  return s;
}

InverseMap toInverse(const PotGuess& g, const PotMap& m) {
  return {m.alpha, m.mid - m.alpha * g.pivot};
}

PotMap toPotMap(const PotGuess& g, const InverseMap& im) {
  return {im.a, im.a * g.pivot + im.c};
}

// The starts of guess g: every sign, scale and offset its held parts leave
// free.
std::vector<PotMap> startMaps(const RobotModel& robot, const PotGuess& g) {
  if (g.fixed && g.bias_held) return {g.map};
  const std::vector<double> signs = g.fixed ? std::vector<double>{1.0}
                                            : std::vector<double>{1.0, -1.0};
  const std::vector<double> scales = g.fixed ? std::vector<double>{1.0}
                                             : std::vector<double>(std::begin(kStartScales),
                                                                   std::end(kStartScales));
  const std::vector<double> mids = g.bias_held ? std::vector<double>{g.map.mid}
                                               : startOffsets(robot, g.column);
  std::vector<PotMap> out;
  for (double sign : signs)
    for (double scale : scales)
      for (double mid : mids) out.push_back({sign * scale * g.map.alpha, mid});
  return out;
}

double wrapAngle(double a) { return a - 2 * M_PI * std::round(a / (2 * M_PI)); }

struct Fit {
  ClassicalParameters p;
  double cost = std::numeric_limits<double>::infinity();
};

// Two fits alike: every searched map with the same sign, and either the
// same cost (to 0.1%: a gauge, e.g. the first joint's offset against the
// mocap frame's turn about its axis, moves maps without changing the fit)
// or each map's scale within 2% and offset within 0.05 (radians, modulo a
// turn). Mirror images, which a later stage may tell apart, stay distinct.
bool sameFit(const Fit& a, const Fit& b, const std::vector<PotGuess>& guesses,
             const std::vector<bool>& done) {
  bool maps_alike = true;
  for (size_t i = 0; i < guesses.size(); ++i) {
    if (!done[i]) continue;
    const PotMap ma = toPotMap(guesses[i], a.p.inverse[guesses[i].sensor]);
    const PotMap mb = toPotMap(guesses[i], b.p.inverse[guesses[i].sensor]);
    if (ma.alpha * mb.alpha <= 0) return false;
    maps_alike &=
        std::abs(ma.alpha - mb.alpha) <= 0.02 * std::max(std::abs(ma.alpha), std::abs(mb.alpha)) &&
        std::abs(wrapAngle(ma.mid - mb.mid)) <= 0.05;
  }
  return maps_alike || std::abs(a.cost - b.cost) <= 1e-3 * std::max(a.cost, b.cost);
}

// One stage's fitting: the regression restricted to the stage's sensors.
class StageFit {
 public:
  StageFit(const RobotModel& robot, const JointSources& sources, SensorSet sensors,
           const Observations& frames, const RobustLoss& loss, int threads)
      : sensors_(std::move(sensors)),
        stage_(robot, sensors_),
        sources_(sources),
        frames_(frames),
        noise_(NoiseModel::fromSeeds(sensors_)),
        threads_(threads),
        reg_(stage_, sources_, frames_, loss, threads) {
    for (int i = 0; i < threads; ++i) ws_.emplace_back(stage_);
    options_.max_iterations = kStartIterations;
    options_.tolerance = 1e-5;
  }

  // From p: the mocap frame and markers in closed form for p's angles, then
  // Levenberg-Marquardt.
  Fit refine(ClassicalParameters p) {
    QState angles;
    angles.q = anglesOfEveryFrame(stage_.robot(), stage_.sensors(), sources_, p, frames_);
    initialiseMarkerGroup(stage_, frames_, angles, 2, threads_, &ws_, &p.theta);
    bool converged = false;
    reg_.solve(noise_, noise_, options_, Clock::now(), 0, &p, &converged);
    Fit f;
    f.cost = reg_.pass(p, noise_, noise_, false).cost;
    f.p = std::move(p);
    return f;
  }

 private:
  const SensorSet sensors_;  // the stage's model points into it
  const MeasurementModel stage_;
  const JointSources& sources_;
  const Observations& frames_;
  const NoiseModel noise_;
  const int threads_;
  Regression reg_;
  std::vector<FrameWorkspace> ws_;
  CalibrationOptions options_;
};

// The frames of `sub` with every defining reading, at most kSearchFrames.
Observations usableSubsample(const Observations& sub, const JointSources& sources) {
  const std::vector<int> usable = framesWithEveryDefiningReading(sub, sources);
  std::vector<int> picked;
  for (int i : spreadFrames(static_cast<int>(usable.size()), kSearchFrames))
    picked.push_back(usable[i]);
  return selectFrames(sub, picked);
}

// Keeps the kBeam best of fits, one of each alike group.
std::vector<Fit> bestDistinct(std::vector<Fit> fits, const std::vector<PotGuess>& guesses,
                              const std::vector<bool>& done) {
  std::sort(fits.begin(), fits.end(), [](const Fit& a, const Fit& b) { return a.cost < b.cost; });
  std::vector<Fit> kept;
  for (Fit& f : fits) {
    if (!std::isfinite(f.cost)) break;
    bool alike = false;
    for (const Fit& k : kept) alike |= sameFit(f, k, guesses, done);
    if (!alike) kept.push_back(std::move(f));
    if (static_cast<int>(kept.size()) == kBeam) break;
  }
  return kept;
}

// The search through `stages`: the best fit of the last stage's beam, or
// none where a stage kept no finite fit.
std::optional<Fit> searchInOrder(const MeasurementModel& model, const Observations& frames,
                                 const RobustLoss& loss, const std::vector<PotGuess>& guesses,
                                 const SensorParameters& seed, int threads,
                                 const JointSources& sources, const std::vector<Stage>& stages) {
  const RobotModel& robot = model.robot();
  const SensorSet& sensors = model.sensors();
  Fit first;
  first.p.theta = seed;
  first.p.theta.joint_origin.clear();
  first.p.inverse.resize(sensors.joint_sensors.size());
  for (const PotGuess& g : guesses) first.p.inverse[g.sensor] = toInverse(g, g.map);
  std::vector<Fit> beam = {first};
  std::vector<bool> done(guesses.size(), false), searched(sensors.joint_sensors.size(), false);
  for (const Stage& stage : stages) {
    for (int i : stage.guesses) done[i] = true, searched[guesses[i].sensor] = true;
    StageFit fit(robot, sources, stageSensors(sensors, sources, stage.in_fit, searched), frames,
                 loss, threads);
    // Each of the stage's guesses in turn (one, unless joints above it saw
    // no marker of their own), every start from every fit of the beam.
    for (int i : stage.guesses) {
      std::vector<Fit> fits;
      for (const Fit& from : beam)
        for (const PotMap& start : startMaps(robot, guesses[i])) {
          ClassicalParameters p = from.p;
          p.inverse[guesses[i].sensor] = toInverse(guesses[i], start);
          fits.push_back(fit.refine(std::move(p)));
        }
      std::vector<Fit> kept = bestDistinct(std::move(fits), guesses, done);
      if (kept.empty()) return std::nullopt;
      beam = std::move(kept);
    }
  }
  return std::move(beam.front());
}

}  // namespace

// The mocap frames the search starts from: the seed's, and where the
// base's markers leave a turn of the world open, the seed's turned half a
// turn about that line. The first stages see the base's markers and those
// of the first links only; with one base marker (or several on one line)
// the fit cannot tell a world turned half a turn about the line through it
// and the limb's root, the first joints mirrored with it, from the truth,
// and every start is refined from the seed's frame: an unseen Bravo 7 on a
// Falcon ROV, its base's one marker 0.73 m from the arm's first joint,
// partial swings, ended in 3 of 10 truths with joints 1-3 mirrored, the
// mocap frame ~π off and the markers at 3.7x their σ, flagged; from the
// truth's frame all three reached the truth.
std::optional<TurnLine> openHalfTurn(const MeasurementModel& model,
                                     const SensorParameters& seed) {
  const RobotModel& robot = model.robot();
  const SensorSet& sensors = model.sensors();
  if (sensors.mocap_frame_fixed.any()) return std::nullopt;
  KinematicsWorkspace ws(robot);
  forwardKinematics(robot, Eigen::VectorXd::Zero(robot.dof()), &ws);
  const std::vector<Eigen::Vector3d> base = baseMarkerPoints(model, seed, ws);
  if (base.empty()) return std::nullopt;
  // The line: through two base markers far apart, else through the one and
  // the limbs' roots' middle.
  const Eigen::Vector3d p = base.front();
  Eigen::Vector3d d = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& b : base)
    if ((b - p).norm() > d.norm()) d = b - p;
  std::vector<Eigen::Vector3d> roots;  // the limbs' first joints
  for (int j : limbRoots(robot)) roots.push_back(ws.joint_origin[robot.qJoints()[j]]);
  if (d.norm() < kLineSpan) {
    if (roots.empty()) return std::nullopt;
    Eigen::Vector3d middle = Eigen::Vector3d::Zero();
    for (const Eigen::Vector3d& r : roots) middle += r / static_cast<double>(roots.size());
    d = middle - p;
    if (d.norm() < kLineSpan) return std::nullopt;
  }
  d.normalize();
  const auto offLine = [&](const Eigen::Vector3d& x) {
    return distanceFromLine(x, p, d) >= kLineSpan;
  };
  // Three base markers off the line pin the turn; so do limbs rooted off
  // it (a quadruped's hips about one base marker: turned, the legs land
  // elsewhere), and the search from that turn would be spent for nothing.
  if (std::any_of(base.begin(), base.end(), offLine) ||
      std::any_of(roots.begin(), roots.end(), offLine))
    return std::nullopt;
  return TurnLine{p, d};
}

// The turn about the line through p with direction d:
// x -> R_d(π) (x - p) + p, composed before the frame's own map.
std::vector<SensorParameters> seedFrames(const MeasurementModel& model,
                                         const SensorParameters& seed) {
  std::vector<SensorParameters> out = {seed};
  const std::optional<TurnLine> line = openHalfTurn(model, seed);
  if (!line) return out;
  const Eigen::Vector3d& p = line->point;
  const Eigen::Vector3d& d = line->direction;
  const Eigen::Matrix3d turn = 2 * d * d.transpose() - Eigen::Matrix3d::Identity();
  SensorParameters turned = seed;
  const Eigen::Matrix3d R = seed.mocap.rotation.toRotationMatrix();
  turned.mocap.rotation = Eigen::Quaterniond(R * turn).normalized();
  turned.mocap.translation = seed.mocap.translation + R * (p - turn * p);
  out.push_back(std::move(turned));
  return out;
}

// Depth first (each limb to its end before the next; among siblings, in
// movable-joint order), the beam's few fits are spent on one limb's
// ambiguities at a time: breadth first (every hip, then every knee, ...),
// a quadruped's four legs shared one beam, and a hip's right map, which its
// own markers cannot place (a marker on its link turns with the offset),
// was pruned by the other legs' stages before its knee could tell (an
// unseen Solo 12 on partial swings: three legs' maps off; 6 of 10 basin
// truths reached breadth first, 9 depth first; ANYmal 6 -> 10). Breadth
// first settles a hand's finger bases together against the palm first:
// depth first, hand24's partial-swing basin truth 7 ended with a finger's
// abduction beyond its limits, breadth first at the truth.
std::vector<int> treeOrder(const RobotModel& robot, bool depth_first) {
  // A joint's path from the root (movable joints, root first): sorted
  // lexicographically, a prefix comes first (depth first); by length,
  // breadth first.
  auto path = [&](int j) -> const std::vector<int>& {
    return robot.supportingJoints(robot.movableJoints()[robot.qJoints()[j]].child_link);
  };
  std::vector<int> order(robot.dof());
  for (int j = 0; j < robot.dof(); ++j) order[j] = j;
  if (depth_first)
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return path(a) < path(b); });
  else
    std::stable_sort(order.begin(), order.end(),
                     [&](int a, int b) { return path(a).size() < path(b).size(); });
  return order;
}

std::vector<double> startOffsets(const RobotModel& robot, int j) {
  const double lo = robot.lowerLimits()[j], hi = robot.upperLimits()[j];
  const bool revolute = robot.movableJoints()[robot.qJoints()[j]].type != JointType::kPrismatic;
  std::vector<double> out;
  if (!std::isfinite(lo) || !std::isfinite(hi)) {
    if (!revolute) return {0.0};
    for (int i = 0; i < 8; ++i) out.push_back(-M_PI + (i + 0.5) * M_PI / 4);
    return out;
  }
  const double width = hi - lo, centre = 0.5 * (lo + hi);
  if (revolute && width >= 2 * M_PI) {
    for (int i = 0; i < 8; ++i) out.push_back(centre + (i - 3.5) * M_PI / 4);
    return out;
  }
  for (int i = 0; i < 8; ++i) out.push_back(lo + (i + 0.5) * width / 8);
  return out;
}

std::optional<Candidate> treeOrderMaps(const MeasurementModel& model, const Observations& sub,
                                       const RobustLoss& loss,
                                       const std::vector<PotGuess>& guesses,
                                       const SensorParameters& seed, int threads) {
  const RobotModel& robot = model.robot();
  const SensorSet& sensors = model.sensors();
  if (sensors.markers.empty()) return std::nullopt;
  const JointSources sources = findJointSources(robot, sensors);
  std::vector<int> guess_of(robot.dof(), -1);
  for (size_t i = 0; i < guesses.size(); ++i)
    if (sources.sensor[guesses[i].column] == guesses[i].sensor)
      guess_of[guesses[i].column] = static_cast<int>(i);
  if (std::count(guess_of.begin(), guess_of.end(), -1) > 0) return std::nullopt;
  const Observations frames = usableSubsample(sub, sources);
  if (frames.num_frames < kMinFrames) return std::nullopt;

  // Neither order is best everywhere (treeOrder): where they differ, both
  // are searched and the better final fit kept (the same frames, markers
  // and pots in the last stage's fit: comparable costs).
  // So are the seed's mocap frame and its turn (seedFrames).
  const std::vector<int> depth_first = treeOrder(robot, true);
  const std::vector<int> breadth_first = treeOrder(robot, false);
  std::vector<std::vector<Stage>> plans = {planStages(model, guess_of, depth_first)};
  if (breadth_first != depth_first) plans.push_back(planStages(model, guess_of, breadth_first));
  std::optional<Fit> best;
  for (const SensorParameters& from : seedFrames(model, seed))
    for (const std::vector<Stage>& stages : plans)
      if (std::optional<Fit> fit =
              searchInOrder(model, frames, loss, guesses, from, threads, sources, stages))
        if (!best || fit->cost < best->cost) best = std::move(fit);
  if (!best) return std::nullopt;
  Candidate out;
  for (const PotGuess& g : guesses) out.maps.push_back(toPotMap(g, best->p.inverse[g.sensor]));
  return out;
}

}  // namespace stac
