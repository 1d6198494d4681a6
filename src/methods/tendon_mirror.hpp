// Mirrors that only tendons see (internal; a move of the wide basin's sign
// re-check, wide_basin.hpp).
//
// A joint whose motion no marker sees is seen through the tendons spanning
// it alone. A path's length over a revolute joint is symmetric about the
// angle where the joint brings the path's anchors nearest or farthest
// apart: mirrored about it (q_j -> 2c - q_j) with its pot's sign flipped,
// the joint's motion fits its pot and those tendons (nearly) as well as
// before. The markers' exact mirror centres (mirror_centres.hpp) do not
// see it, and a flip about the motion's own mean (flipSign) lands a
// centre's distance from the mirror: an unseen planar two-joint arm whose
// second link carried no marker, partial swings, converged with that joint
// mirrored about a point 0.8 rad from its motion's mean, a tendon at 2.7x
// its σ, 0.4% above the truth's cost, and passed as ok.
#pragma once

#include <optional>

#include "stac/measurement.hpp"
#include "stac/log.hpp"

namespace stac {

// Whether some tendon's reading depends on q column j and no marker's does.
bool seenOnlyByTendons(const MeasurementModel& model, int j);

// The centre c about which column j's angles over the rows of q, mirrored
// (q_j -> 2c - q_j), change the lengths of the tendons spanning it least
// (θ's joint-origin corrections; the other columns as they are); for a revolute joint
// c is a mirror modulo half turns, and the one returned keeps the mirrored
// motion nearest the middle of the joint's limits. With `moved`, the
// mirrored frames are those of `moved` (q with other columns already
// moved by the same jump: a half turn above, another flip), column j set
// to 2c - q_j. nullopt where no tendon spans j or q has no rows.
std::optional<double> tendonMirrorCentre(const MeasurementModel& model,
                                         const SensorParameters& theta, const RowMatrix& q,
                                         int j, const RowMatrix* moved = nullptr);

// Whether some tendon's length depends on q column j.
bool seenByTendons(const MeasurementModel& model, int j);

}  // namespace stac
