// The summary's numbers that every method reports the same way: per-sensor
// residual statistics, the "before" RMS, the per-group σ.
#pragma once

#include <vector>

#include "solve/problem.hpp"
#include "stac/calibration.hpp"

namespace stac {

// Per-sensor residual statistics in raw units at (θ, q) over obs.
void residualStatistics(const MeasurementModel& model, const SensorParameters& theta,
                        const Observations& obs, const RowMatrix& q, int threads,
                        CalibrationResult* result);

// The median of |N(0, σ²)| (a scalar reading) and of the Euclidean norm of
// N(0, σ² I₃) (a marker), in σ: what a sensor's median error is if it fits
// at its noise.
constexpr double kMedianErrorInSigma[kNumSensorGroups] = {1.5382, 0.6745, 0.6745};

// The share of a sensor's errors below `upper` (MedianError), and that
// quantile of |N(0, σ²)| and of the norm of N(0, σ² I₃), in σ.
constexpr double kUpperShare = 0.8;
constexpr double kUpperErrorInSigma[kNumSensorGroups] = {2.1544, 1.2816, 1.2816};

// Per group and sensor (SensorSet order): the median prediction error over
// the frames of obs at (θ, q), in raw units (a marker: Euclidean), and how
// many readings it is over (median NaN without any). Medians, so that gross
// outliers barely move them: a wrong sign or minimum shows in every frame.
// `upper`: the error below which kUpperShare of them lie, which gross
// readings move only where they are more than 1 - kUpperShare of the
// sensor's (a wrong minimum that fits most frames and leaves the rest far
// off, which a redescending loss then ignores).
struct MedianError {
  double median = 0.0;
  double upper = 0.0;
  int count = 0;
};
std::vector<std::vector<MedianError>> medianErrors(const MeasurementModel& model,
                                                   const SensorParameters& theta,
                                                   const Observations& obs, const RowMatrix& q,
                                                   int threads);

// Every frame's q_t fitted to θ at the seed σ: ten LM steps per frame from
// q_start (frames x dof), as the summary's "before" does.
RowMatrix fitAnglesToTheta(const Problem& problem, const SensorParameters& theta,
                           const RowMatrix& q_start);

// RMS residual per group in raw units with θ held fixed and each q_t fitted
// to it (ten LM steps from q_start, frames x dof), on at most 1000 frames
// spread over the log: the summary's "before".
void fittedResidualRms(const Problem& problem, const SensorParameters& theta,
                       const RowMatrix& q_start, double rms[kNumSensorGroups]);

// The summary's per-group σ (RMS over the group's sensors; in the joint
// group, over those with !(*skip_joint)[i] when skip_joint is given, 0 if
// none) and which groups the sensors have.
void summariseGroupNoise(const SensorSet& sensors, const NoiseModel& noise,
                         CalibrationSummary* summary,
                         const std::vector<bool>* skip_joint = nullptr);

}  // namespace stac
