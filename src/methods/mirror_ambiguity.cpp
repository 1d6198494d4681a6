// Configurations the data cannot tell apart (see mirror_ambiguity.hpp).
#include "methods/mirror_ambiguity.hpp"

#include <algorithm>
#include <cmath>

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

// Whether the move changes some pot's gain or bias by more than 4 std
// (a change within them is the same answer).
bool changesBeyondStd(const GainBias& before, const GainBias& after, const GainBias& sd) {
  return std::abs(after.gain - before.gain) > 4 * sd.gain ||
         std::abs(after.bias - before.bias) > 4 * sd.bias;
}

}  // namespace

std::vector<UnidentifiableDirection> mirrorAmbiguities(const Problem& problem,
                                                       const Observations& obs,
                                                       const SensorParameters& theta,
                                                       const NoiseModel& noise, const RowMatrix& q,
                                                       const ParameterStd& std) {
  std::vector<UnidentifiableDirection> out;
  const MeasurementModel& model = problem.model;
  if (q.rows() == 0 || !q.allFinite() || model.sensors().joint_sensors.empty()) return out;
  Workspaces ws = makeWorkspaces(model, problem.threads);
  const WideBasin basin(model, obs, noise, problem.loss, problem.threads, &ws, theta, false);
  Estimate est;
  est.theta = theta;
  est.state.q = q;
  const std::vector<PotGuess>& guesses = basin.guesses();
  const SensorSet& sensors = model.sensors();
  for (const MinimumMove& move : basin.equivalentMoves(est)) {
    SensorParameters moved = theta;
    RowMatrix moved_q = q;
    applyMove(model.robot(), guesses, move, &moved, &moved_q, true);
    UnidentifiableDirection d;
    bool changes = false;
    for (const std::vector<int>* part : {&move.flip, &move.half_turn})
      for (int i : *part) {
        const int s = guesses[i].sensor;
        changes |= changesBeyondStd(theta.joint_sensor[s], moved.joint_sensor[s],
                                    std.joint_sensor[s]);
        const std::string name = "joint_sensors." + sensors.joint_sensors[s].name;
        if (part == &move.flip) d.parameters.push_back(name + ".gain");
        // (A joint both mirrored and turned, the roll flip's pitch: once.)
        if (std::find(d.parameters.begin(), d.parameters.end(), name + ".bias") ==
            d.parameters.end())
          d.parameters.push_back(name + ".bias");
      }
    if (!changes) continue;
    std::string what;
    if (!move.half_turn.empty())
      what = jointList(model.robot(), guesses, move.half_turn) + " half a turn away";
    if (!move.flip.empty())
      what += (what.empty() ? "" : " with ") + jointList(model.robot(), guesses, move.flip) +
              " mirrored";
    d.reason = "the readings fit as well with " + what +
               " (a mirror configuration: the markers on the links in between move with them), "
               "so the pots' gains and biases listed have two equally good values; hold a "
               "marker on one of those links at its known position, or log poses near the "
               "joints' limits";
    out.push_back(std::move(d));
  }
  return out;
}

}  // namespace stac
