// chain4: a serial chain built in code whose axes 1 and 3 (about z) align
// at q2 = 0, so that it passes through the same places with q1 + π, −q2,
// q3 + π (the Panda's mirror configuration), and whose joints 1 and 3 span
// more than a turn (±4 rad, a UR arm's wrists): for tests of the discrete
// ambiguities a calibration must find or report (mirror_ambiguity,
// joint limits). A pot on every joint; markers on every link, the base's
// and one of link 4's held (the two gauges), link 2's held or free.
#pragma once

#include <random>
#include <string>
#include <utility>
#include <vector>

#include "stac/log.hpp"
#include "stac/measurement.hpp"
#include "stac/robot_model.hpp"
#include "stac/sensors_file.hpp"

namespace stac::test {

// The chain's URDF; j3's limits ±j3_limit.
std::string chainUrdf(double j3_limit = 4.0);
// Its true sensors file; `l2_held`: link 2's marker held at its position.
std::string chainTruthYaml(bool l2_held);

// One column of the simulated motion rescaled onto [lo, hi].
struct ColumnRange {
  int column;
  double lo, hi;
};

// A log of 400 frames simulated (seed `seed`) on the chain with j3 limits
// ±4, its columns `ranges` rescaled; calibrated with the URDF whose j3
// limits are ±urdf_j3_limit. Holds references among its members: built in
// place, never copied.
struct ChainLog {
  ChainLog(bool l2_held, unsigned seed, const std::vector<ColumnRange>& ranges,
           double urdf_j3_limit = 4.0);
  ChainLog(const ChainLog&) = delete;
  ChainLog& operator=(const ChainLog&) = delete;

  RobotModel robot;  // what calibrates
  SensorsFile truth;
  MeasurementModel model;
  RowMatrix q;  // the true angles
  Observations obs;
};

}  // namespace stac::test
