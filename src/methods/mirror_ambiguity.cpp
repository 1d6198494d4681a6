// Configurations the data cannot tell apart (see mirror_ambiguity.hpp).
#include "methods/mirror_ambiguity.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "methods/wide_basin.hpp"

namespace stac {
namespace {

// Joint names of the guesses listed, "a", "a and b", "a, b and c".
std::string jointList(const RobotModel& robot, const std::vector<PotGuess>& guesses,
                      const std::vector<int>& listed) {
  std::string out;
  for (size_t k = 0; k < listed.size(); ++k) {
    if (k > 0) out += k + 1 == listed.size() ? " and " : ", ";
    out += robot.qName(guesses[listed[k]].column);
  }
  return out;
}

// The parameters whose re-fitted values differ by more than 3 std (a
// change within them is the same answer, and 3 leaves a margin for the
// subsample's estimate of the change): the pots the jump mirrors and
// turns, the markers on the links in between, which move with them, and
// what a mirror made inexact by the chain's offsets moves too (an unseen
// Kinova Jaco's mocap rotation, 5 std).
// Named per entry (ThetaSpace::names), as summary.unidentifiable names them.
std::vector<std::string> movedParameters(const ThetaSpace& space, const SensorParameters& before,
                                         const SensorParameters& after,
                                         const Eigen::VectorXd& std) {
  const Eigen::VectorXd d = space.minus(after, before);
  std::vector<std::string> out;
  for (int i = 0; i < space.size(); ++i) {
    if (!space.free()[i] || !(std::abs(d[i]) > 3 * std[i])) continue;
    out.push_back(space.names()[i]);
  }
  return out;
}

// The sentence that explains an equivalent move and what pins it.
std::string mirrorReason(const RobotModel& robot, const std::vector<PotGuess>& guesses,
                         const MinimumMove& move) {
  if (move.world_turn)
    return "the readings fit as well with the mocap frame turned half a turn about " +
           jointList(robot, guesses, move.half_turn) +
           "'s axis and that joint half a turn away (no marker on the base off that axis, and "
           "no tendon or limit that tells the two apart), so the parameters listed have two "
           "equally good values; hold a marker on the base off that axis, or the mocap frame, "
           "at its known position";
  std::string what;
  if (!move.half_turn.empty())
    what = jointList(robot, guesses, move.half_turn) + " half a turn away";
  if (!move.flip.empty())
    what += (what.empty() ? "" : " with ") + jointList(robot, guesses, move.flip) + " mirrored";
  return "the readings fit as well with " + what +
         " (a mirror configuration: the markers on the links in between move with them), so "
         "the parameters listed have two equally good values; hold a marker on one of those "
         "links at its known position, or log poses near the joints' limits";
}

}  // namespace

bool mirrorsApply(const MeasurementModel& model, const RowMatrix& q) {
  return q.rows() > 0 && q.allFinite() && !model.sensors().joint_sensors.empty();
}

MirrorCandidates mirrorCandidates(const WideBasin& basin, const Estimate& est, Estimate* better,
                                  bool* moved) {
  MirrorCandidates out;
  std::vector<WideBasin::EquivalentMove> same;
  if (better) {
    *better = est;
    *moved = basin.jumpToBetterEquivalent(better, &same, &out.refitted).has_value();
  } else {
    same = basin.equivalentMoves(est, &out.refitted);
  }
  for (WideBasin::EquivalentMove& m : same)
    out.moves.emplace_back(mirrorReason(basin.robot(), basin.guesses(), m.move), std::move(m.theta));
  return out;
}

std::vector<UnidentifiableDirection> mirrorListing(const ThetaSpace& space,
                                                   const MirrorCandidates& candidates,
                                                   const Eigen::VectorXd& std) {
  std::vector<UnidentifiableDirection> out;
  if (std.size() != space.size()) return out;
  for (const auto& [reason, theta] : candidates.moves) {
    UnidentifiableDirection d;
    d.parameters = movedParameters(space, candidates.refitted, theta, std);
    if (d.parameters.empty()) continue;
    d.reason = reason;
    d.kind = Undetermined::kMirror;
    out.push_back(std::move(d));
  }
  return out;
}

std::vector<UnidentifiableDirection> mirrorAmbiguities(const Problem& problem,
                                                       const Observations& obs,
                                                       const SensorParameters& theta,
                                                       const NoiseModel& noise, const RowMatrix& q,
                                                       const Eigen::VectorXd& std) {
  const MeasurementModel& model = problem.model;
  if (!mirrorsApply(model, q) || std.size() != model.thetaSpace().size()) return {};
  Workspaces ws = makeWorkspaces(model, problem.threads);
  const WideBasin basin(model, obs, noise, problem.loss, problem.threads, &ws, theta, false);
  Estimate est;
  est.theta = theta;
  est.state.q = q;
  return mirrorListing(model.thetaSpace(), mirrorCandidates(basin, est), std);
}

}  // namespace stac
