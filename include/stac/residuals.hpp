// Per-reading residuals on a sample of frames: what residual histograms and
// other diagnostics need (the summary's RMS values say how large, not how
// they are distributed).
//
//   ResidualSampleOptions o;                    // at most 1000 frames
//   ResidualSample before = sampleResiduals(robot, sensors, seed, obs, nullptr, o);
//   ResidualSample after = sampleResiduals(robot, sensors, result.theta, obs, &q, o);
//
// With q == nullptr each sampled frame's q is first fitted to θ (LM from the
// neutral pose), exactly as calibrate() does for summary.before_rms, so the
// RMS of `before` is that number.
#pragma once

#include <vector>

#include "stac/log.hpp"
#include "stac/measurement.hpp"
#include "stac/robot_model.hpp"
#include "stac/sensors.hpp"

namespace stac {

struct ResidualSampleOptions {
  int max_frames = 1000;  // frames spread evenly over the log
  int threads = 0;        // 0: all cores
  // For fitting q when none is given (the loss calibrate() used).
  LossKind loss = LossKind::kNone;
  double loss_scale = 3.0;

  bool isValid(std::string* error) const;  // max_frames >= 1, threads >= 0, scale > 0
};

struct ResidualSample {
  std::vector<int> frames;  // the sampled frames (indices into obs), increasing
  // One entry per available reading of a sampled frame, in frame order:
  // |prediction - reading| in raw units (a marker: Euclidean distance, m).
  std::vector<double> magnitude[kNumSensorGroups];
  std::vector<int> sensor[kNumSensorGroups];  // the reading's sensor index

  // sqrt(mean(magnitude²)) of a group; 0 if it has no readings.
  double rms(SensorGroup g) const;
};

// q: joint angles of every frame of obs (obs.num_frames x dof), or nullptr.
// Throws std::invalid_argument on invalid options or shapes.
ResidualSample sampleResiduals(const RobotModel& robot, const SensorSet& sensors,
                               const SensorParameters& theta, const Observations& obs,
                               const RowMatrix* q, const ResidualSampleOptions& options);

}  // namespace stac
