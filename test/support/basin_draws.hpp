// The wide-basin test's draws (issue 13): a robot with the sensors a user
// would log, random truths as the paper's seeding must reach them, the
// paper's seed, the logs of each variant, and the "reached" test. Shared by
// the long basin test and by the regressions it found.
#pragma once

#include <random>
#include <string>
#include <vector>

#include "stac/calibrate.hpp"
#include "stac/sensors_file.hpp"
#include "stac/simulate.hpp"

namespace stac::test {

struct Robot {
  std::string name;
  RobotModel model;
  SensorsFile truth;
  int frames;
};

// A public robot with the sensors a user would log without a sensors file,
// the gauges removed by CAD-known markers (external_sensors.hpp); with a
// layout_seed, the sensors laid out at random as an independent generator
// would (randomLayoutTruthYaml) instead.
Robot externalRobot(RobotModel m, int frames, unsigned layout_seed = 0);

// A bundled robot (data/<name>.urdf): the seed file's fixed parameters
// (the gauges), the truth file's values for them.
Robot bundledRobot(const std::string& name, int frames);

// A random truth around `base`: a random mocap frame, gains of both signs
// over 0.3-3 per radian (a prismatic joint's per its stroke), biases up to
// ±1 rad-equivalent, free markers within 5 cm of their link origins; fixed
// markers keep their position.
SensorParameters randomTruth(const RobotModel& robot, const SensorSet& s,
                             const SensorParameters& base, std::mt19937_64& rng);

// The paper's seeding: gains 1, biases 0, free markers at their link
// origins, the mocap frame identity; fixed parameters as in `truth`.
SensorParameters paperSeed(const SensorSet& s, const SensorParameters& truth);

// The criterion: every estimated parameter within k (4) of its
// reported standard deviations of the truth (a wrong local minimum is off
// by tens or hundreds; a parameter the result reports undetermined has an
// infinite std, and passes). z: each finite std's error in it.
bool withinReportedStd(const SensorSet& s, const SensorParameters& truth,
                       const CalibrationResult& r, std::string* why,
                       std::vector<double>* z = nullptr, double k = 4.0);
// The truth itself, as a regression test wants it: within the reported std
// and nothing reported undetermined (the seeds remove the gauges) but a
// bias known only modulo a turn (turn_ambiguity.hpp).
bool closeToTruth(const SensorSet& s, const SensorParameters& truth, const CalibrationResult& r,
                  std::string* why, std::vector<double>* z = nullptr);

// The variants of the issue: how the log is made and solved.
enum class Variant { kPlain, kOutliers, kPartialSwings, kPostures };

const char* variantName(Variant v);

// Static postures per log: a real recording's size (TIAGo: 37), enough for
// the bundled hand's 24 joints.
constexpr int kPostures = 80;

// The log of one variant for `truth`, its motion and noise drawn from
// `seed`: smooth motion, partial off-centre swings or static postures;
// the outlier variant with 30% marker dropout and 5% gross readings.
Simulation simulateVariant(const Robot& robot, const MeasurementModel& model,
                           const SensorParameters& truth, Variant v, int frames, int seed);

// The seed of the basin test's log for truth `index` in its noise draw
// `draw` (STAC_BASIN_NOISE_SEED; 0: the default draw).
inline int basinLogSeed(int index, int draw) { return 1000 + index + 7919 * draw; }

// The basin test's truth `index` of `robot` in variant `v` again (its draw
// of truths from one generator, the log of `robot.frames` frames from
// basinLogSeed(index, noise_draw)), calibrated from the paper's seed on 2
// threads (the outlier variant under `outlier_loss`), with `options` where
// given (its loss and threads still set as said): a miss the basin found,
// replayed as a regression test.
struct BasinReplay {
  SensorParameters truth;
  CalibrationResult result;
};
BasinReplay replayBasinTruth(const Robot& robot, Variant v, int index,
                             LossKind outlier_loss = LossKind::kHuber,
                             CalibrationOptions options = CalibrationOptions(),
                             int noise_draw = 0, unsigned truth_seed = 2024);

}  // namespace stac::test
