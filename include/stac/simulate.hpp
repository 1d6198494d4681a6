// Synthetic data from a known truth (SPEC §4 stac_simulate).
//
//   SimulationOptions options;                 // validated by isValid()
//   options.frames = 3000;
//   Simulation sim = simulate(model, truth, options);
//   // sim.q: the true joint angles, sim.log: the readings, sim.outliers: the
//   // readings replaced by gross errors.
//
// Determinism: every random number comes from std::mt19937_64 through our own
// uniform and Box–Muller transforms (std::*_distribution are
// implementation-defined), so one seed gives the same output with any
// standard library. Each reading consumes a fixed number of draws whatever
// the options, so
//   - the motion does not depend on --frames: N frames are a prefix of N+k;
//   - the noise realisation does not depend on dropout/outliers/noise-scale:
//     turning outliers on changes only the readings that become outliers.
// The library never prints.
#pragma once

#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "stac/log.hpp"
#include "stac/measurement.hpp"
#include "stac/robot_model.hpp"
#include "stac/sensors.hpp"

namespace stac {

// The interval a joint of q moves in: its limits (narrowed by the limits of
// the mimic followers it drives), or ±π (±0.1 m for a prismatic joint) where
// it has none. lower == upper for a joint that cannot move.
struct JointRange {
  double lower = 0.0, upper = 0.0;
};
std::vector<JointRange> motionRanges(const RobotModel& robot);

// Smooth random motion inside the joint limits, frames x dof. Each joint
// follows s(t) = Σ_k a_k sin(2π f_k t + φ_k) (three components in disjoint
// bands, Σ a_k = 1: 0.5 at 0.4–0.7 Hz, 0.3 at 0.9–1.5 Hz, 0.2 at 0.15–0.3 Hz,
// random phases), squashed smoothly into the central 90% of its range:
//   q(t) = mid + 0.9 * half * tanh(g s(t)) / tanh(g).
// t = frame / rate_hz. 300 frames at 100 Hz sweep >= 60% of every joint's
// range. Draws a fixed number of values per joint from rng (independent of
// frames). Throws std::invalid_argument if frames < 0 or
// rate_hz is not positive and finite.
RowMatrix simulateMotion(const RobotModel& robot, int frames, double rate_hz,
                         std::mt19937_64& rng);

struct SimulationOptions {
  int frames = 0;
  double rate_hz = 100.0;
  double noise_scale = 1.0;  // noise σ = sensor σ * noise_scale
  double dropout = 0.0;      // probability that a marker is missing in a frame
  double outliers = 0.0;     // probability that a present reading is gross
  std::uint64_t seed = 1;    // used by simulate()

  // frames >= 1, rate > 0, noise_scale >= 0, dropout and outliers in [0, 1],
  // all finite. On failure *error (if given) says which and why.
  bool isValid(std::string* error) const;
};

// A reading replaced by a gross error.
struct SimulatedOutlier {
  int frame = 0;
  SensorGroup group = SensorGroup::kJoint;
  int sensor = 0;      // index within its group
  std::string name;    // the sensor's (or marker's) name
};

struct SimulatedLog {
  Log log;
  std::vector<SimulatedOutlier> outliers;  // in frame, then column order
};

// Readings of every sensor at each row of q (frames x dof), predicted from
// `truth` and corrupted:
//   - Gaussian noise N(0, (σ * noise_scale)²) on every reading (each marker
//     coordinate with the marker's σ);
//   - with probability `dropout`, a marker is missing in a frame (x, y, z
//     all NaN);
//   - with probability `outliers`, a present reading is replaced by a gross
//     error: a scalar sensor gets ±(10 + 40u) σ max(1, noise_scale) added;
//     a marker (one reading, all three coordinates) is moved by
//     max(0.05 + 0.15u m, (10 + 40u) σ max(1, noise_scale)) in a random
//     direction.
// Columns follow SPEC §2: joint sensors, tendon sensors, then markers as
// <name>.x/.y/.z; the time column "time" holds frame / rate_hz. options.frames
// and options.seed are not used (q and rng decide). Throws
// std::invalid_argument if the options are invalid (other than frames) or q
// has the wrong number of columns.
SimulatedLog simulateLog(const MeasurementModel& model,
                         const SensorParameters& truth, const RowMatrix& q,
                         const SimulationOptions& options,
                         std::mt19937_64& rng);

struct Simulation {
  RowMatrix q;  // frames x dof, the true joint angles
  SimulatedLog data;
};

// simulateMotion then simulateLog, from one std::mt19937_64 seeded with
// options.seed. Throws std::invalid_argument if !options.isValid().
Simulation simulate(const MeasurementModel& model, const SensorParameters& truth,
                    const SimulationOptions& options);

// The joint angles as a Log for writeLog() (SPEC §4 --joint-angles): a "time"
// column when `time` is not empty, then one column per joint of q, named
// after the joint, in q order. Written by the same writer as the readings, so
// both files format numbers alike and read back exactly. Throws
// std::invalid_argument if q or time has the wrong size.
Log jointAnglesLog(const RobotModel& robot, const RowMatrix& q,
                   const std::vector<double>& time);

}  // namespace stac
