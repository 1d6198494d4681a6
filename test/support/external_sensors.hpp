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

// Sensors laid out as an independent generator lays them (issue 13's
// TALOS case), not as sensor inference names them: a pot on every joint of
// q; markers 1-5 cm from the origin of a random link of a random rigid
// group (a link with the links fixed to it), about one for every one or two
// moving groups, so some groups carry two and some none; two random markers
// fixed; three path tendons from a link to one 1-3 joints below it, each
// anchored 2-5 cm off its links' origins (σ 1 mm). The layout is drawn from
// `rng`; the values are a truth to be redrawn (basin_draws.hpp).
std::string randomLayoutTruthYaml(const RobotModel& robot, std::mt19937_64& rng);

}  // namespace stac::test
