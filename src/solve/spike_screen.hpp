// Gross readings found by time before any fit: with a robust loss, a
// reading that stands far out of its neighbours in the log is set aside
// (missing) before the start.
//
// Why before the fit: a gross reading of a pot that dominates its joint's
// angle drags that frame's angle along and leaves no residual on the pot
// itself; neither the loss nor a residual test after the fit can see it,
// while the other sensors' θ absorb the wrong angle (the basin test's hand
// under 5% gross readings: every truth missed, flagged; removing exactly
// the gross readings let the same fit reach the truth). In a log of smooth
// motion, though, such a reading is 50-200 σ away from the median of its
// four nearest frames, where a good reading is within a few σ.
//
// Data-driven and conservative: per column, d_t = x_t − median of the
// readings of frames t±1, t±2 (at least 3 of them present); its scale is
// 1.4826 × the median |d_t| over the log, floored at the sensor's seed σ. A
// reading is set aside where |d_t| > kSpikeScales times that scale. A column
// is screened only where the log is smooth in time: its neighbour scale at
// most a tenth of the column's own robust spread, or at most 3 seed σ (a
// sensor that hardly moves), so that a log of independent static postures
// is left alone; and with at least kMinScreenedFrames frames to measure it
// on. Rows are taken in log order, spaced by the log's time where it has
// one. A marker reading (3 columns) is set aside whole when any of
// its coordinates is.
#pragma once

#include "stac/log.hpp"
#include "stac/measurement.hpp"

namespace stac {

constexpr double kSpikeScales = 10.0;
constexpr int kMinScreenedFrames = 50;

struct SpikeScreen {
  Observations kept;                          // obs with the spikes missing
  int set_aside[kNumSensorGroups] = {0, 0, 0};  // readings, per group
};

SpikeScreen screenSpikes(const Observations& obs, const NoiseModel& seed);

// Where each of n frames lies on the parabolas' axis: its time in units of
// the median frame interval where `time` (the log's; empty: none) is
// strictly increasing (a gap of dropped frames is then as wide as it was),
// else its index. Computed once per log.
std::vector<double> framePositions(const std::vector<double>& time, int n);

// The spikes of one column (NaN = missing): true where set aside;
// `positions` from framePositions (empty: the frame indices). Exposed for
// its tests.
std::vector<bool> columnSpikes(const Eigen::Ref<const Eigen::VectorXd>& x, double sigma,
                               const std::vector<double>& positions = {});

}  // namespace stac
