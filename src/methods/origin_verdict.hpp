// The verdict's check of the joint-origin corrections (SPEC §3 summary.verdict):
// machining and assembly leave millimetres and tenths of a degree, so a
// correction many prior std (or, without a prior, centimetres or degrees)
// from the URDF is a wrong minimum or a wrong URDF, not a calibration.
#pragma once

#include <string>
#include <vector>

#include "stac/calibration.hpp"

namespace stac {

// A correction component beyond this many prior std is suspect.
constexpr double kSuspectOriginPriorStd = 5.0;
// Without a prior: a translation (m) or rotation (rad) beyond these.
constexpr double kSuspectOriginXyz = 0.05;
constexpr double kSuspectOriginRpy = 0.2;

// Appends one reason per joint whose correction is suspect.
void checkJointOrigins(const SensorSet& sensors, const SensorParameters& theta,
                       std::vector<std::string>* why);

}  // namespace stac
