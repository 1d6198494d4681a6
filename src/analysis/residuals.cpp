// Per-reading residuals on spread frames (residuals.hpp).
#include "stac/residuals.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "model/prediction_errors.hpp"
#include "solve/parallel.hpp"
#include "solve/statistics.hpp"
#include "stac/calibrate.hpp"

namespace stac {

bool ResidualSampleOptions::isValid(std::string* error) const {
  auto fail = [&](const std::string& e) {
    if (error) *error = e;
    return false;
  };
  if (max_frames < 1) return fail("max_frames must be at least 1");
  if (threads < 0) return fail("threads must be >= 0 (0 = all cores)");
  if (!(loss_scale > 0) || !std::isfinite(loss_scale))
    return fail("loss scale must be positive and finite");
  return true;
}

double ResidualSample::rms(SensorGroup g) const {
  const std::vector<double>& v = magnitude[static_cast<int>(g)];
  double s = 0;
  for (double x : v) s += x * x;
  return v.empty() ? 0.0 : std::sqrt(s / v.size());
}

ResidualSample sampleResiduals(const RobotModel& robot, const SensorSet& sensors,
                               const SensorParameters& theta, const Observations& obs,
                               const RowMatrix* q, const ResidualSampleOptions& options) {
  std::string error;
  if (!options.isValid(&error)) throw std::invalid_argument("sampleResiduals: " + error);
  if (q && (q->rows() != obs.num_frames || q->cols() != robot.dof()))
    throw std::invalid_argument("sampleResiduals: q is not frames x dof");
  const MeasurementModel model(robot, sensors);
  const int threads = resolveThreads(options.threads);
  ResidualSample out;
  out.frames = spreadFrames(obs.num_frames, options.max_frames);
  const Observations sub = selectFrames(obs, out.frames);
  const int T = sub.num_frames;
  RowMatrix qs(T, robot.dof());
  if (q) {
    for (int k = 0; k < T; ++k) qs.row(k) = q->row(out.frames[k]);
  } else {
    // As calibrate() fits q to the seed for summary.before_rms.
    const NoiseModel seed = NoiseModel::fromSeeds(sensors);
    const RobustLoss loss(options.loss, options.loss_scale);
    const Problem problem{model, sub, seed, loss, threads};
    qs = fitAnglesToTheta(problem, theta, neutralPose(robot).transpose().replicate(T, 1));
  }
  // Per chunk, then joined in chunk order: the same output with any thread count.
  std::vector<ResidualSample> chunks(numChunks(T));
  visitPredictionErrors(model, theta, sub, qs, threads,
                        [&](int chunk, int, SensorGroup g, int sensor, double e) {
                          chunks[chunk].magnitude[static_cast<int>(g)].push_back(e);
                          chunks[chunk].sensor[static_cast<int>(g)].push_back(sensor);
                        });
  for (const ResidualSample& c : chunks)
    for (int g = 0; g < kNumSensorGroups; ++g) {
      out.magnitude[g].insert(out.magnitude[g].end(), c.magnitude[g].begin(), c.magnitude[g].end());
      out.sensor[g].insert(out.sensor[g].end(), c.sensor[g].begin(), c.sensor[g].end());
    }
  return out;
}

}  // namespace stac
