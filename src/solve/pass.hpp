// One pass over the frames at a given (θ, σ, q): the cost, the raw residual
// statistics of each sensor group and, for the variance adaptation, the
// degrees of freedom the q_t took from each group. Every method reports its
// progress and its result from these, so "cost" and "RMS" mean one thing.
#pragma once

#include <chrono>
#include <string>
#include <vector>

#include "solve/problem.hpp"
#include "stac/calibrate.hpp"
#include "stac/calibration.hpp"

namespace stac {

struct PassStats {
  double cost = 0;  // ½ Σ ρ over the readings, plus the origin prior's cost
  double sse[kNumSensorGroups] = {0, 0, 0};      // raw units²
  double count[kNumSensorGroups] = {0, 0, 0};    // readings
  double wsse[kNumSensorGroups] = {0, 0, 0};     // Σ w s (seed-whitened)
  double wdims[kNumSensorGroups] = {0, 0, 0};    // Σ w rows
  double leverage[kNumSensorGroups] = {0, 0, 0};
  // The same with each reading's scaleTaper at the current σ
  // (noise_adaptation.hpp): a robust loss's σ estimate.
  double tapered_wsse[kNumSensorGroups] = {0, 0, 0};  // Σ φ s (seed-whitened)
  double tapered_rows[kNumSensorGroups] = {0, 0, 0};  // Σ φ rows
  double group_cost[kNumSensorGroups] = {0, 0, 0};  // ½ Σ ρ per group

  // RMS raw residual of group g (0 without readings): the one definition of
  // the summary's and the progress reports' RMS.
  double rms(int g) const { return count[g] > 0 ? std::sqrt(sse[g] / count[g]) : 0.0; }
  void add(const PassStats& other);
};

// Every frame of problem.obs at q; with `leverage`, also the leverage Σ
// tr(J_g H⁻¹ J_gᵀ) of each group.
PassStats costPass(const Problem& problem, const SensorParameters& theta, const NoiseModel& noise,
                   const RowMatrix& q, bool leverage, Workspaces* ws);

// The readings the robust loss trusted least (weight < 0.999), at most
// max_count, lowest weight first.
std::vector<DownweightedReading> downweightedReadings(const Problem& problem,
                                                      const SensorParameters& theta,
                                                      const NoiseModel& noise, const RowMatrix& q,
                                                      int max_count);

// problem.obs with every reading set aside (missing) whose whitened squared
// residual at (theta, q, noise) lies beyond the σ taper's bound
// (noise_adaptation.hpp scaleTaper: 4 times its χ² 99% quantile, 5.2 σ for
// a scalar, which Gaussian noise passes once in 4 million); *count: how
// many were.
Observations withoutGrossReadings(const Problem& problem, const SensorParameters& theta,
                                  const NoiseModel& noise, const RowMatrix& q, int* count);

// A progress report from a pass.
using Clock = std::chrono::steady_clock;
IterationReport makeReport(int iteration, const PassStats& st, Clock::time_point start,
                           const std::string& stage, const SensorParameters* theta = nullptr);

}  // namespace stac
