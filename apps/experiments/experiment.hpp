// Shared pieces of the paper's experiments re-run on the bundled robots
// (stac_experiment; EXPERIMENTS.md): loading a robot with its truth,
// simulated data, seeds perturbed from the truth, and how far an estimate is
// from the truth.
#pragma once

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "stac/log.hpp"
#include "stac/robot_model.hpp"
#include "stac/sensors.hpp"
#include "stac/sensors_file.hpp"

namespace stac::experiments {

// Where the experiments read and write, and how big they are.
struct Context {
  std::string data_dir;   // the bundled robots (data/)
  std::string out_dir;    // CSV and SVG go here
  bool smoke = false;     // a few seconds instead of minutes
  int threads = 0;
  std::uint64_t seed = 1;
};

// A bundled robot: its URDF, the simulation truth and the paper's seed.
struct BundledRobot {
  std::string name;
  RobotModel robot;
  SensorsFile truth;
  SensorsFile seed;
};
// data/<name>.urdf, data/<name>_truth.yaml, data/<name>_seed.yaml.
BundledRobot loadBundledRobot(const std::string& data_dir, const std::string& name);

// The readings as the solvers see them.
Observations toObservations(const Log& log, const SensorSet& sensors);

// Frames of joint angles drawn uniformly and independently inside the
// joint ranges (random poses rather than smooth motion).
RowMatrix randomPoses(const RobotModel& robot, int frames, std::mt19937_64& rng);

// How far an estimate θ is from the truth, over the free parameters.
//   relative error of one parameter block:
//     gain: |g - g*| / |g*|;  bias: |b - b*| / |g*| (radians or metres of the
//     measured quantity) relative to 1;  marker position: |d - d*| relative
//     to max(|d*|, 1 cm);  mocap translation: |t - t*| relative to
//     max(|t*|, 10 cm);  mocap rotation: the angle of R R*ᵀ relative to 1 rad.
//   diverged: gain off by > 10%, a joint sensor's bias by > 0.1 rad of the
//     joint, a tendon sensor's bias by > 5 mm of tendon, a marker or the
//     mocap translation by > 2 cm, the mocap rotation by > 0.1 rad.
struct ParameterScore {
  double mean_relative_error = 0.0;
  int diverged = 0;
  int count = 0;  // parameter blocks compared
};
ParameterScore scoreParameters(const SensorSet& sensors, const SensorParameters& estimate,
                               const SensorParameters& truth);

// The fraction of space-time joint angles q_t,j (every frame, every joint)
// farther than `threshold` (rad, or m for a prismatic joint) from the truth.
double divergedAngleFraction(const RowMatrix& q_estimate, const RowMatrix& q_truth,
                             double threshold);

// The truth with every free parameter perturbed by `level` times a typical
// seeding error: gain x (1 + 0.3 level N(0,1)), bias + 0.3 level |g| N(0,1)
// rad (tendons: 5 mm), markers and mocap translation + 3 cm level N(0,I),
// mocap rotation by 0.3 level N(0,I) rad.
SensorParameters perturbedSeed(const SensorSet& sensors, const SensorParameters& truth,
                               double level, std::mt19937_64& rng);

// A small CSV table, also printable as Markdown.
struct Table {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  std::string csv() const;
  std::string markdown() const;
};
std::string fmt(double v, const char* format = "%.4g");

// Writes <out_dir>/<name> (temporary file and rename).
void writeResult(const Context& context, const std::string& name, const std::string& content);

}  // namespace stac::experiments
