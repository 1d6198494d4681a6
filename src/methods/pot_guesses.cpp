// The wide-basin initialisation's pot guesses and candidate maps (see
// wide_basin.hpp): each one-joint sensor's readings mapped onto its joint,
// and the transforms the candidate search builds new maps with.
#include "methods/wide_basin.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <numeric>
#include <utility>

#include "stac/calibrate.hpp"
#include "stac/kinematics.hpp"
#include "methods/mirror_centres.hpp"
#include "methods/verdict.hpp"

namespace stac {

namespace {

// The value below which a share q of the sorted values lie (nearest rank).
double quantile(const std::vector<double>& sorted, double q) {
  const size_t i = static_cast<size_t>(std::lround(q * static_cast<double>(sorted.size() - 1)));
  return sorted[i];
}

}  // namespace

std::vector<PotGuess> makePotGuesses(const RobotModel& robot, const SensorSet& sensors,
                                     const SensorParameters& theta, const Observations& obs,
                                     bool gross_readings) {
  std::vector<PotGuess> out;
  std::vector<bool> covered(robot.dof(), false);
  for (size_t s = 0; s < sensors.joint_sensors.size(); ++s) {
    const JointSensorConfig& sc = sensors.joint_sensors[s];
    const MovableJoint& mj = robot.movableJoints()[sc.joint];
    if (mj.is_mimic || covered[mj.q_index]) continue;
    double lo = robot.lowerLimits()[mj.q_index], hi = robot.upperLimits()[mj.q_index];
    if (!std::isfinite(lo) || !std::isfinite(hi)) lo = -M_PI, hi = M_PI;
    std::vector<double> p;
    for (int t = 0; t < obs.num_frames; ++t)
      if (!std::isnan(obs.joint(t, s))) p.push_back(obs.joint(t, s));
    const int n = static_cast<int>(p.size());
    if (n < 2) continue;
    std::sort(p.begin(), p.end());
    const double pmin = gross_readings ? quantile(p, 0.05) : p.front();
    const double pmax = gross_readings ? quantile(p, 0.95) : p.back();
    const double centre =
        gross_readings ? quantile(p, 0.5) : std::accumulate(p.begin(), p.end(), 0.0) / n;
    const GainBias& gb = theta.joint_sensor[s];
    PotGuess g;
    g.sensor = static_cast<int>(s);
    g.column = mj.q_index;
    g.fixed = sc.fixed.gain;
    g.bias_held = sc.fixed.bias;
    // A held bias alone: q = alpha (p - bias), the sign and scale unknown.
    g.pivot = sc.fixed.bias && !sc.fixed.gain ? gb.bias : centre;
    g.map.mid = sc.fixed.bias && !sc.fixed.gain ? 0.0 : 0.5 * (lo + hi);
    if (sc.fixed.gain) {
      // A known scale: the exact inverse gain; with the bias held too, the
      // exact inverse (else the offset is guessed like any other).
      if (gb.gain == 0) continue;
      g.map.alpha = 1.0 / gb.gain;
      if (sc.fixed.bias) g.map.mid = (g.pivot - gb.bias) / gb.gain;
    } else {
      if (!(pmax > pmin)) continue;
      g.map.alpha = 0.8 * (hi - lo) / (pmax - pmin);
    }
    covered[mj.q_index] = true;
    out.push_back(g);
  }
  return out;
}

Candidate guessedMaps(const std::vector<PotGuess>& guesses) {
  Candidate c;
  for (const PotGuess& g : guesses) c.maps.push_back(g.map);
  return c;
}

void applyCandidate(const std::vector<PotGuess>& guesses, const Candidate& candidate,
                    const Observations& obs, RowMatrix* q) {
  for (size_t i = 0; i < guesses.size(); ++i) {
    const PotGuess& g = guesses[i];
    const PotMap& map = candidate.maps[i];
    double last = map.mid;
    for (int t = 0; t < obs.num_frames; ++t) {
      const double p = obs.joint(t, g.sensor);
      if (!std::isnan(p)) last = map.alpha * (p - g.pivot) + map.mid;
      (*q)(t, g.column) = last;
    }
  }
}

Candidate withSigns(const Candidate& c, const std::vector<PotGuess>& guesses,
                    const std::vector<bool>& flip) {
  Candidate out = c;
  for (size_t i = 0; i < guesses.size(); ++i)
    if (flip[i] && !guesses[i].fixed) out.maps[i].alpha = -out.maps[i].alpha;
  return out;
}

Candidate scaled(const Candidate& c, const std::vector<PotGuess>& guesses, double s) {
  Candidate out = c;
  for (size_t i = 0; i < guesses.size(); ++i)
    if (!guesses[i].fixed) out.maps[i].alpha *= s;
  return out;
}

Candidate seededMaps(const Candidate& c, const std::vector<PotGuess>& guesses,
                     const SensorParameters& seed) {
  // A fixed guess's map is this inverse already.
  Candidate out = c;
  for (size_t i = 0; i < guesses.size(); ++i) {
    const GainBias& gb = seed.joint_sensor[guesses[i].sensor];
    if (gb.gain == 0 || !std::isfinite(gb.gain)) continue;
    out.maps[i].alpha = 1.0 / gb.gain;
    out.maps[i].mid = (guesses[i].pivot - gb.bias) / gb.gain;
  }
  return out;
}

Candidate flipped(const Candidate& c, const std::vector<int>& move) {
  Candidate out = c;
  for (int i : move) out.maps[i].alpha = -out.maps[i].alpha;
  return out;
}

bool touchesFixed(const std::vector<PotGuess>& guesses, const std::vector<int>& move) {
  return std::any_of(move.begin(), move.end(), [&](int i) { return guesses[i].fixed; });
}

Candidate rescaled(const Candidate& c, int i, double s) {
  Candidate out = c;
  out.maps[i].alpha *= s;
  return out;
}

std::vector<std::vector<bool>> mirrorPatterns(const RobotModel& robot,
                                              const std::vector<PotGuess>& guesses) {
  KinematicsWorkspace kin(robot);
  forwardKinematics(robot, neutralPose(robot), &kin);
  std::vector<std::vector<bool>> patterns(4, std::vector<bool>(guesses.size(), true));
  for (size_t i = 0; i < guesses.size(); ++i) {
    const Eigen::Vector3d u = kin.joint_axis[robot.qJoints()[guesses[i].column]].normalized();
    for (int a = 0; a < 3; ++a) patterns[1 + a][i] = std::abs(u[a]) < 0.7;
  }
  return patterns;
}

namespace {
// The guess on the nearest joint above guess i's in the tree that has one
// (-1: none).
int guessAbove(const RobotModel& robot, const std::vector<PotGuess>& guesses, int i) {
  std::vector<int> guess_of_q(robot.dof(), -1);
  for (size_t g = 0; g < guesses.size(); ++g) guess_of_q[guesses[g].column] = static_cast<int>(g);
  const int movable = robot.qJoints()[guesses[i].column];
  const std::vector<int>& chain = robot.supportingJoints(robot.movableJoints()[movable].child_link);
  for (int k = static_cast<int>(chain.size()) - 2; k >= 0; --k) {
    const MovableJoint& above = robot.movableJoints()[chain[k]];
    if (!above.is_mimic && guess_of_q[above.q_index] >= 0) return guess_of_q[above.q_index];
  }
  return -1;
}
}  // namespace

// Two wrong signs in a row (e.g. a wrist's pitch and roll) can each look
// right alone, since flipping either one by itself moves the markers
// farther: hence the pairs.
std::vector<std::vector<int>> signMoves(const RobotModel& robot,
                                        const std::vector<PotGuess>& guesses) {
  std::vector<std::vector<int>> moves;
  for (size_t i = 0; i < guesses.size(); ++i) moves.push_back({static_cast<int>(i)});
  for (size_t i = 0; i < guesses.size(); ++i) {
    const int above = guessAbove(robot, guesses, static_cast<int>(i));
    if (above >= 0) moves.push_back({above, static_cast<int>(i)});
  }
  return moves;
}

// p = g q + b = (-g) (2c - q) + (b + 2 g c).
void mirrorAbout(const PotGuess& g, double c, SensorParameters* theta, RowMatrix* q) {
  q->col(g.column) = (2.0 * c - q->col(g.column).array()).matrix();
  GainBias& gb = theta->joint_sensor[g.sensor];
  gb.bias += 2.0 * gb.gain * c;
  gb.gain = -gb.gain;
}

// About c = 0 where the bias is held, so that it stays.
void flipSign(const PotGuess& g, SensorParameters* theta, RowMatrix* q) {
  mirrorAbout(g, g.bias_held ? 0.0 : q->col(g.column).mean(), theta, q);
}

namespace {
// p = g q + b = g (q + s k pi) + (b - g s k pi): k half turns toward the
// middle of the joint's limits.
void turn(const RobotModel& robot, const PotGuess& g, int half_turns, SensorParameters* theta,
          RowMatrix* q) {
  const double mid = 0.5 * (robot.lowerLimits()[g.column] + robot.upperLimits()[g.column]);
  const double s = std::isfinite(mid) && q->col(g.column).mean() > mid ? -1.0 : 1.0;
  q->col(g.column).array() += s * half_turns * M_PI;
  GainBias& gb = theta->joint_sensor[g.sensor];
  gb.bias -= gb.gain * s * half_turns * M_PI;
}
}  // namespace

void halfTurn(const RobotModel& robot, const PotGuess& g, SensorParameters* theta, RowMatrix* q) {
  turn(robot, g, 1, theta, q);
}

namespace {
// The guesses whose bias is free on a joint with finite limits, and
// whether each one's angles in q sit at or beyond them in most frames (a
// few frames dragged there by gross readings are no turn off).
struct LimitedGuess {
  int index;
  bool mostly_at_limit;
  bool mostly_beyond;  // beyond the URDF's limits (not only the widened ones)
};
std::vector<LimitedGuess> limitedGuesses(const RobotModel& robot,
                                         const std::vector<PotGuess>& guesses,
                                         const RowMatrix& q) {
  const std::vector<int> at_limit = jointsOftenAtLimit(robot, q, 0.5);
  const auto beyond = beyondLimits(robot, q);
  std::vector<LimitedGuess> out;
  for (int i = 0; i < static_cast<int>(guesses.size()); ++i) {
    const int j = guesses[i].column;
    if (guesses[i].bias_held || !std::isfinite(robot.upperLimits()[j] - robot.lowerLimits()[j]))
      continue;
    const double rows = static_cast<double>(q.rows());
    out.push_back({i, std::find(at_limit.begin(), at_limit.end(), j) != at_limit.end(),
                   often(static_cast<double>(beyond.col(j).count()), rows, 0.5)});
  }
  return out;
}

// Shifts guess g's joint's motion in q into its limits, its middle `place`
// of the way from the lowest middle that keeps it within them to the
// highest, and the pot's map with it (recentreMoves). A motion wider than
// the limits, which true angles never leave, has a wrong scale: it is
// shrunk about its middle to half their span (a free gain only) and
// centred (an unseen Z1 on partial swings, fresh seed 13 truth 0: its
// gripper's pot gain 24 times too small and mirrored, the motion 7.3 rad
// wide against limits 1.57 apart).
void recentre(const RobotModel& robot, const PotGuess& g, double place, SensorParameters* theta,
              RowMatrix* q) {
  const int j = g.column;
  const double lo = robot.lowerLimits()[j], hi = robot.upperLimits()[j];
  const double half = 0.5 * (q->col(j).maxCoeff() - q->col(j).minCoeff());
  const double was = 0.5 * (q->col(j).maxCoeff() + q->col(j).minCoeff());
  const bool wide = !(hi - lo > 2 * half);
  const double k = wide && !g.fixed && half > 0 ? 0.25 * (hi - lo) / half : 1.0;
  const double middle = wide ? 0.5 * (lo + hi) : lo + half + place * (hi - lo - 2 * half);
  // q' = middle + k (q - was); p = g q + b = (g / k) q' + b + g was - (g / k) middle.
  q->col(j) = (middle + k * (q->col(j).array() - was)).matrix();
  GainBias& gb = theta->joint_sensor[g.sensor];
  gb.bias += gb.gain * was - gb.gain / k * middle;
  gb.gain /= k;
}
}  // namespace

std::vector<MinimumMove> wholeTurnMoves(const RobotModel& robot,
                                        const std::vector<PotGuess>& guesses, const RowMatrix& q) {
  std::vector<MinimumMove> moves;
  MinimumMove all_at_limits;
  for (const LimitedGuess& g : limitedGuesses(robot, guesses, q)) {
    const int j = guesses[g.index].column;
    const bool revolute = robot.movableJoints()[robot.qJoints()[j]].type == JointType::kRevolute;
    if (revolute && (robot.upperLimits()[j] - robot.lowerLimits()[j] > 2 * M_PI || g.mostly_at_limit))
      moves.push_back({{}, {}, {g.index}});
    if (revolute && g.mostly_at_limit) all_at_limits.whole_turn.push_back(g.index);
  }
  if (all_at_limits.whole_turn.size() > 1) moves.insert(moves.begin(), all_at_limits);
  return moves;
}

std::vector<MinimumMove> recentreMoves(const RobotModel& robot,
                                       const std::vector<PotGuess>& guesses, const RowMatrix& q,
                                       const std::vector<int>& flagged) {
  std::vector<MinimumMove> moves;
  if (q.rows() == 0) return moves;
  const std::vector<LimitedGuess> limited = limitedGuesses(robot, guesses, q);
  // kPlacements of guess i's motion; one where it is wider than the limits
  // (recentre shrinks and centres it wherever `place` says).
  const auto placements = [&](MinimumMove move, int i) {
    const int j = guesses[i].column;
    const bool fits = robot.upperLimits()[j] - robot.lowerLimits()[j] >
                      q.col(j).maxCoeff() - q.col(j).minCoeff();
    move.recentre = {i};
    for (int k = 0; k < (fits ? kPlacements : 1); ++k) {
      move.place = fits ? k / (kPlacements - 1.0) : 0.5;
      moves.push_back(move);
    }
  };
  for (const LimitedGuess& g : limited) {
    const int j = guesses[g.index].column;
    if (!g.mostly_beyond && std::find(flagged.begin(), flagged.end(), j) == flagged.end())
      continue;
    placements({}, g.index);
    // The joint above, placed, with g's mirrored and centred in its limits.
    const int above = guessAbove(robot, guesses, g.index);
    const bool limited_above = std::any_of(limited.begin(), limited.end(),
                                           [&](const LimitedGuess& a) { return a.index == above; });
    if (!limited_above || touchesFixed(guesses, {g.index})) continue;
    MinimumMove mirrored;
    mirrored.flip = mirrored.recentre_below = {g.index};
    placements(mirrored, above);
  }
  return moves;
}

std::vector<MinimumMove> wrapMoves(const RobotModel& robot, const std::vector<PotGuess>& guesses,
                                   const RowMatrix& q) {
  std::vector<MinimumMove> moves;
  for (int i = 0; i < static_cast<int>(guesses.size()); ++i) {
    const int j = guesses[i].column;
    const bool revolute = robot.movableJoints()[robot.qJoints()[j]].type != JointType::kPrismatic;
    const double span = robot.upperLimits()[j] - robot.lowerLimits()[j];
    if (!revolute || !(span > 2 * M_PI) || q.rows() == 0) continue;
    if (q.col(j).maxCoeff() - q.col(j).minCoeff() <= 2 * M_PI) continue;
    MinimumMove move;
    move.wrap = {i};
    moves.push_back(std::move(move));
  }
  return moves;
}

namespace {
// Each angle of column g.column moved by whole turns into the one turn
// whose ends lie in the middle of the widest arc of the circle that no
// angle occupies. Where each angle is right modulo a turn (the markers fit
// every frame), that is the motion itself, if it spans less than a turn.
// (The turn about the angles' circular mean cut an unseen Solo 12's knee
// motion of 5.9 rad, most of it near one end, inside: the frames beyond the
// cut stayed a turn off, the pot's gain at 0.4 of the truth's, flagged.)
void wrapAngles(const PotGuess& g, RowMatrix* q) {
  const int T = static_cast<int>(q->rows());
  if (T == 0) return;
  std::vector<double> on_circle(T);
  for (int t = 0; t < T; ++t)
    on_circle[t] = (*q)(t, g.column) - 2 * M_PI * std::floor((*q)(t, g.column) / (2 * M_PI));
  std::sort(on_circle.begin(), on_circle.end());
  double widest = on_circle.front() + 2 * M_PI - on_circle.back();  // across 0
  double cut = on_circle.back() + 0.5 * widest;
  for (int t = 1; t < T; ++t)
    if (on_circle[t] - on_circle[t - 1] > widest) {
      widest = on_circle[t] - on_circle[t - 1];
      cut = on_circle[t - 1] + 0.5 * widest;
    }
  const double centre = std::remainder(cut + M_PI, 2 * M_PI);  // the turn's middle
  for (int t = 0; t < q->rows(); ++t) {
    double& a = (*q)(t, g.column);
    a -= 2 * M_PI * std::round((a - centre) / (2 * M_PI));
  }
}
}  // namespace

bool turnsAny(const std::vector<PotGuess>& guesses, const MinimumMove& move,
              const std::vector<bool>& joints) {
  for (const std::vector<int>* moved : {&move.flip, &move.half_turn})
    for (int i : *moved)
      if (joints[guesses[i].column]) return true;
  return false;
}

namespace {
// Each column's joint axis at the zero configuration (base frame). A joint
// and its nearest moving ancestor, with no joint between them, keep the
// same angle between their axes in every configuration, so the zero one
// tells whether a half turn about the ancestor's axis reverses the joint's.
std::vector<Eigen::Vector3d> axesAtZero(const RobotModel& robot) {
  KinematicsWorkspace ws(robot);
  forwardKinematics(robot, Eigen::VectorXd::Zero(robot.dof()), &ws);
  std::vector<Eigen::Vector3d> out;
  for (int j = 0; j < robot.dof(); ++j) out.push_back(ws.joint_axis[robot.qJoints()[j]]);
  return out;
}

// Chain flips: a joint half a turn and the k consecutive joints below it
// mirrored (1 <= k <= kMaxMirrored), closed by the joint below them half
// a turn or, where the mirrored ones end their chain, by nothing; the
// first mirrored one either about zero (−q) or over the top (π − q:
// R_a(π) R_b(π − q) = R_c(π) R_b(−q) for perpendicular axes a, b and
// c = a × b, the links below then passing through the same places turned
// half a turn about c). Their links pass through the same places, so the
// markers on or beyond them tell the two configurations apart barely or
// not at all. k = 1 closed is a serial chain's wrist flip; k = 2 closed
// its shoulder flip (an elbow's parallel axes: a Kinova Jaco's q1 + π,
// −q2, −q3, q4 + π about its limits' zeros; a random truth ended there,
// 0.06% above the truth's cost, silent); unseen robots on partial swings
// converged, flagged, in a Finger Edu's roll and two flexions over the
// top (q1 + π, π − q2, −q3; 2 of 10 truths, the roll beyond its limit in
// ~580 of 600 frames) and a Unitree Z1's yaw, three pitches and wrist
// over the top, closed by its last roll (q1 + π, π − q2, −q3..−q5,
// q6 + π; joint 1 beyond its limit in 341 of 600 frames), each found
// back by these moves about the joints' zeros.
// Beyond the wrist and shoulder flips about zero (k <= 2, closed), only
// through a joint `through` marks (all without it), and each only where
// the half-turned joint's axis is perpendicular to the first mirrored
// one's, which the identities need.
void addChainFlips(const RobotModel& robot, const std::vector<PotGuess>& guesses,
                   const std::vector<std::vector<int>>& pairs, const std::vector<bool>* through,
                   std::vector<MinimumMove>* out) {
  std::vector<MinimumMove>& moves = *out;
  auto turnable = [&](int i) { return !guesses[i].bias_held; };
  const bool long_chains =
      !through || std::find(through->begin(), through->end(), true) != through->end();
  const auto addLong = [&](MinimumMove move) {
    if (!through || turnsAny(guesses, move, *through)) moves.push_back(std::move(move));
  };
  const size_t kMaxMirrored = long_chains ? 4 : 2;
  std::vector<int> mirrored;
  const std::function<void(int, int, bool)> below = [&](int up, int mid, bool perpendicular) {
    mirrored.push_back(mid);
    const bool top = perpendicular && turnable(mirrored[0]);  // over the top
    bool end = true;
    for (const std::vector<int>& down : pairs) {
      if (down[0] != mid) continue;
      end = false;
      if (turnable(down[1])) {
        if (mirrored.size() <= 2) moves.push_back({mirrored, {up, down[1]}, {}});
        else if (perpendicular) addLong({mirrored, {up, down[1]}, {}});
        if (top) addLong({mirrored, {up, mirrored[0], down[1]}, {}});
      }
      if (mirrored.size() < kMaxMirrored) below(up, down[1], perpendicular);
    }
    if (end && top) addLong({mirrored, {up, mirrored[0]}, {}});
    mirrored.pop_back();
  };
  const std::vector<Eigen::Vector3d> axes =
      long_chains ? axesAtZero(robot) : std::vector<Eigen::Vector3d>();
  const auto perpendicularPair = [&](const std::vector<int>& pair) {
    return long_chains &&
           std::abs(axes[guesses[pair[0]].column].dot(axes[guesses[pair[1]].column])) < 1e-6;
  };
  for (const std::vector<int>& up : pairs)
    if (turnable(up[0])) below(up[0], up[1], perpendicularPair(up));
}
}  // namespace

std::vector<MinimumMove> minimumMoves(const RobotModel& robot, const std::vector<PotGuess>& guesses,
                                      const std::vector<std::vector<int>>& sign_moves,
                                      const std::vector<bool>* through) {
  std::vector<MinimumMove> moves;
  auto turnable = [&](int i) { return !guesses[i].bias_held; };
  std::vector<std::vector<int>> pairs;  // {above, below}
  for (const std::vector<int>& m : sign_moves) {
    if (touchesFixed(guesses, m)) continue;
    moves.push_back({m, {}, {}});
    if (m.size() == 1 && turnable(m[0])) moves.push_back({{}, m, {}});
    if (m.size() == 2 && turnable(m[0])) {  // m[0] is above m[1]
      moves.push_back({{m[1]}, {m[0]}, {}});
      if (turnable(m[1])) moves.push_back({{}, m, {}});
    }
    if (m.size() == 2) pairs.push_back(m);
  }
  addChainFlips(robot, guesses, pairs, through, &moves);
  // Every joint mirrored at once, the mocap frame's closed form turning
  // with them: where every joint's axis is perpendicular to one direction,
  // a half turn of the whole robot about it reverses every axis (Finger
  // Edu: axes −x, y, y; all three pots' signs flipped with the mocap frame
  // turned ~π about z fit within 0.3% of the truth's cost, its markers at
  // 1.7 σ, silent, in 2 of 10 partial-swing truths).
  std::vector<int> all;
  for (int i = 0; i < static_cast<int>(guesses.size()); ++i) all.push_back(i);
  if (all.size() >= 2 && !touchesFixed(guesses, all)) moves.push_back({all, {}, {}, true});
  return moves;
}

namespace {
// Mirrors column g.column about the nearest of centre + kπ that keeps the
// mirrored motion nearest the middle of the joint's limits (k = 0 without
// limits), and flips its pot's map to match. A revolute joint's
// kinematics repeat every turn, so a chain's mirror about a centre is one
// about every centre + kπ with k even, and about centre + π with k odd
// where the aligned axes meet there: the Kinova Jaco's wrist (joint 5
// limited to [0.52, 5.76], straight at π) flips to 2π − q5, which lies
// within them, where −q5 does not.
void flipAboutTurns(const RobotModel& robot, const PotGuess& g, double centre,
                    SensorParameters* theta, RowMatrix* q) {
  const double mid = 0.5 * (robot.lowerLimits()[g.column] + robot.upperLimits()[g.column]);
  const bool revolute =
      robot.movableJoints()[robot.qJoints()[g.column]].type != JointType::kPrismatic;
  double c = 0;
  if (revolute && !g.bias_held) {
    c = centre;
    if (std::isfinite(mid))
      c += M_PI * std::round((mid + q->col(g.column).mean() - 2 * centre) / (2 * M_PI));
  }
  mirrorAbout(g, c, theta, q);
}

// The centres flipAboutTurns mirrors a move's flips about: where the
// kinematics make the chain flip exact to a millimetre (exactMirrorCentres),
// else zero.
std::vector<double> flipCentres(const RobotModel& robot, const std::vector<PotGuess>& guesses,
                                const MinimumMove& move) {
  std::vector<int> flip, half_turn;
  for (int i : move.flip) flip.push_back(guesses[i].column);
  for (int i : move.half_turn) half_turn.push_back(guesses[i].column);
  return exactMirrorCentres(robot, flip, half_turn)
      .value_or(std::vector<double>(move.flip.size(), 0.0));
}
}  // namespace

void applyMove(const RobotModel& robot, const std::vector<PotGuess>& guesses,
               const MinimumMove& move, SensorParameters* theta, RowMatrix* q,
               bool mirror_about_zero) {
  const bool exact = mirror_about_zero || move.flip_about_zero;
  const std::vector<double> centres =
      exact ? flipCentres(robot, guesses, move) : std::vector<double>();
  for (size_t f = 0; f < move.flip.size(); ++f) {
    const PotGuess& g = guesses[move.flip[f]];
    if (!move.flip_centres.empty())
      mirrorAbout(g, move.flip_centres[f], theta, q);
    else if (exact)
      flipAboutTurns(robot, g, centres[f], theta, q);
    else
      flipSign(g, theta, q);
  }
  for (int i : move.half_turn) turn(robot, guesses[i], 1, theta, q);
  for (int i : move.whole_turn) turn(robot, guesses[i], 2, theta, q);
  for (int i : move.wrap) wrapAngles(guesses[i], q);
  for (int i : move.recentre) recentre(robot, guesses[i], move.place, theta, q);
  for (int i : move.recentre_below) recentre(robot, guesses[i], 0.5, theta, q);
}

}  // namespace stac
