// Sensors for a robot nobody wrote a sensors file for, as a user would log
// them without one (SPEC §3 "Without a sensors file"): a pot on every joint
// of q, named after the joint, and a marker on the root link and on every
// link a joint of q moves, named after the link.
#pragma once

#include <random>
#include <string>

#include "stac/robot_model.hpp"

namespace stac::test {

// A sensors file (YAML) with a random truth: gains of both signs (0.5-3;
// per stroke length for a prismatic joint),
// biases up to ±1 rad times the gain, markers up to 5 cm off their link's
// origin, a random mocap rotation and a translation of up to 2 m. With
// fix_gauges, the root marker and the markers of links no joint of q lies
// below are `fixed: true` (a user's CAD-known markers), which removes the
// gauge freedoms of SPEC §3.
std::string inferableTruthYaml(const RobotModel& robot, bool fix_gauges, std::mt19937_64& rng);

}  // namespace stac::test
