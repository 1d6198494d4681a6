// Predict-and-compare: every available reading of every frame against its
// noise-free prediction at (θ, q_t), in raw units. The one loop behind the
// calibration's per-sensor residuals, the cross-sensor prediction errors
// (stac_eval) and the residual samples of the report.
#pragma once

#include <functional>

#include "stac/log.hpp"
#include "stac/measurement.hpp"

namespace stac {

// Sees one reading: its frame chunk (kFramesPerChunk frames, parallel.hpp),
// frame, group, sensor index and |prediction - reading| (a marker: the
// Euclidean distance). Called from worker threads, one call per chunk at a
// time, in frame order within a chunk.
using PredictionErrorVisitor =
    std::function<void(int chunk, int frame, SensorGroup group, int sensor, double error)>;

// q: obs.num_frames x dof. Missing readings (NaN) are skipped.
void visitPredictionErrors(const MeasurementModel& model, const SensorParameters& theta,
                           const Observations& obs, const RowMatrix& q, int threads,
                           const PredictionErrorVisitor& visit);

}  // namespace stac
