// The pots' initial maps by a multi-start search in tree order (internal;
// one of the wide basin's candidate searches, wide_basin.hpp).
//
// The greedy sweeps of the wide basin start from maps that assume each
// joint swings about the middle of its range; a log that moves a joint over
// a fifth of its range, anywhere in it, leaves them in a mirror image. This
// search assumes nothing about where or how far a joint moves. It solves
// the small θ-only problem of the classical regression (every joint angle
// read off its pot's inverse map, regression.hpp) on a subsample, one stage
// of the kinematic tree at a time, from the root outward (in two orders,
// depth first and breadth first, where they differ; the better final fit
// is kept):
//  - a stage adds the next joint (and any joint above it that no marker
//    has seen yet) and the markers that only these and earlier joints move;
//    the markers further out are left out of the stage's fit;
//  - the new joint's map is started from every combination of sign, a few
//    coverage scales and offsets spread over one turn (or its range), each
//    start refined by Levenberg-Marquardt over everything the stage fits
//    (the earlier joints' maps, the mocap frame, the markers seen so far);
//  - the best few fits are kept (a beam), since the first stages can leave
//    a mirror the later ones resolve.
// The discrete ambiguities are thus settled where the data first decide
// them, each by an exhaustive search of a handful of starts rather than a
// greedy move of the whole candidate.
#pragma once

#include <optional>
#include <vector>

#include "methods/wide_basin.hpp"

namespace stac {

// The maps of `guesses` found by the search on the frames of `sub`, or
// nullopt where it does not apply: a joint of q without a guess of its own
// (a tendon-only joint, say), no free marker group, or fewer than 20 frames
// with every pot's reading.
std::optional<Candidate> treeOrderMaps(const MeasurementModel& model, const Observations& sub,
                                       const RobustLoss& loss,
                                       const std::vector<PotGuess>& guesses,
                                       const SensorParameters& seed, int threads);

// A line in the base's frame: a point on it and its unit direction.
struct TurnLine {
  Eigen::Vector3d point;
  Eigen::Vector3d direction;
};

// The line about which the base's markers (at the seed's positions) leave
// the world's half turn open: through them and the limbs' roots, where
// there is one base marker, or several on that line, and every limb is
// rooted on it; nullopt where they pin the turn, or the seed holds the
// mocap frame.
std::optional<TurnLine> openHalfTurn(const MeasurementModel& model, const SensorParameters& seed);

// The mocap frames the search starts from: the seed's, and where
// openHalfTurn finds a line, the seed's frame turned half a turn about it.
std::vector<SensorParameters> seedFrames(const MeasurementModel& model,
                                         const SensorParameters& seed);

// The q columns in a search order: each after every joint above it, depth
// first (one limb to its end before the next) or breadth first (by the
// number of joints above).
std::vector<int> treeOrder(const RobotModel& robot, bool depth_first);

// The offsets a map's start tries for q column j: eight, spread over one
// turn about the middle of the joint's range where the range spans a turn
// or more (or the joint has no limits), else over the range.
std::vector<double> startOffsets(const RobotModel& robot, int j);

}  // namespace stac
