// The world's half turn with a limb's first joint (internal; jumps of
// WideBasin::jumpToBetterMinimum and its mirror listing, wide_basin.hpp),
// and the base geometry it shares with the tree-order search's open half
// turn (tree_search.hpp): the base's markers, the limbs' roots, lines.
//
// Turn the mocap frame half a turn about a limb's first joint's axis and
// that joint half a turn back: every link below the joint stays where it
// was. Where no base marker sits off that axis and every other limb is
// rooted on it, the markers then read exactly as before; only the tendons
// from the base across the joint (and the joint's limits) tell the two
// apart. A start can land on the wrong one of the pair, and the plain half
// turn of the joint, with the frame kept, refines far off: an unseen Bravo 7
// on a BlueVolta ROV, no marker on the ROV, its first joint continuous,
// random sensor layouts 5 and 6 (40 truths each): 7 converged there, one
// flagged and 6 with verdict ok, a tendon at 1.35-2x its σ (which the
// adapted σ absorbed, 0.1% of the cost).
#pragma once

#include <vector>

#include "methods/wide_basin.hpp"
#include "stac/kinematics.hpp"
#include "stac/measurement.hpp"

namespace stac {

// Points closer than this (m) to a line lie on it: a base marker a
// centimetre off the line moves by two under the half turn about it, ten
// times a marker's typical noise, and so pins the turn (the tree-order
// search's open half turn, tree_search.cpp, and worldTurnColumns).
constexpr double kLineSpan = 0.01;
// The distance of x from the line through p with unit direction d.
double distanceFromLine(const Eigen::Vector3d& x, const Eigen::Vector3d& p,
                        const Eigen::Vector3d& d);

// The base's markers (on links no joint moves), in the base's frame, at
// θ's positions; `ws` holds forward kinematics at any pose.
std::vector<Eigen::Vector3d> baseMarkerPoints(const MeasurementModel& model,
                                              const SensorParameters& theta,
                                              const KinematicsWorkspace& ws);
// The q columns of the limbs' first joints (no joint above them).
std::vector<int> limbRoots(const RobotModel& robot);

// The q columns of the limbs' first joints about
// whose axes the world's half turn leaves every marker where it was (θ's
// marker positions on the base); none where part of the mocap frame is
// held.
std::vector<int> worldTurnColumns(const MeasurementModel& model, const SensorParameters& theta);

// Each guess on such a column, half a turn with the mocap frame re-fitted
// in closed form to the turned motion (MinimumMove::world_turn).
std::vector<MinimumMove> worldTurnMoves(const MeasurementModel& model,
                                        const std::vector<PotGuess>& guesses,
                                        const SensorParameters& theta);

}  // namespace stac
