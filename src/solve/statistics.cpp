#include "solve/statistics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "model/prediction_errors.hpp"
#include "solve/pass.hpp"
#include "solve/parallel.hpp"

namespace stac {

std::vector<std::vector<MedianError>> medianErrors(const MeasurementModel& model,
                                                   const SensorParameters& theta,
                                                   const Observations& obs, const RowMatrix& q,
                                                   int threads) {
  const SensorSet& s = model.sensors();
  // Per chunk (one thread at a time each), then per sensor in chunk order.
  struct Error {
    int group, sensor;
    double value;
  };
  std::vector<std::vector<Error>> chunks(numChunks(obs.num_frames));
  visitPredictionErrors(model, theta, obs, q, threads,
                        [&](int chunk, int, SensorGroup g, int sensor, double e) {
                          chunks[chunk].push_back({static_cast<int>(g), sensor, e});
                        });
  std::vector<std::vector<std::vector<double>>> errors(kNumSensorGroups);
  for (int g = 0; g < kNumSensorGroups; ++g) errors[g].resize(s.groupSize(static_cast<SensorGroup>(g)));
  for (const auto& chunk : chunks)
    for (const Error& e : chunk) errors[e.group][e.sensor].push_back(e.value);
  std::vector<std::vector<MedianError>> out(kNumSensorGroups);
  for (int g = 0; g < kNumSensorGroups; ++g)
    for (std::vector<double>& e : errors[g]) {
      MedianError m;
      m.count = static_cast<int>(e.size());
      m.median = m.upper = std::numeric_limits<double>::quiet_NaN();
      if (!e.empty()) {
        const size_t mid = e.size() / 2;
        std::nth_element(e.begin(), e.begin() + mid, e.end());
        m.median = e[mid];
        // Above the median's place every error is at least the median: the
        // upper quantile is found among those alone.
        const size_t upper = std::max(
            mid, static_cast<size_t>(kUpperShare * static_cast<double>(e.size() - 1)));
        std::nth_element(e.begin() + mid, e.begin() + upper, e.end());
        m.upper = e[upper];
      }
      out[g].push_back(m);
    }
  return out;
}

void residualStatistics(const MeasurementModel& model, const SensorParameters& theta,
                        const Observations& obs, const RowMatrix& q, int threads,
                        CalibrationResult* result) {
  const SensorSet& s = model.sensors();
  const int M = static_cast<int>(s.markers.size());
  const int J = static_cast<int>(s.joint_sensors.size());
  const int N = static_cast<int>(s.tendon_sensors.size());
  const int offset[kNumSensorGroups] = {0, M, M + J};
  // Per chunk: for each sensor Σ e², Σ |e|, count (summed in chunk order).
  const int n = M + J + N;
  std::vector<Eigen::MatrixXd> acc(numChunks(obs.num_frames), Eigen::MatrixXd::Zero(n, 3));
  visitPredictionErrors(model, theta, obs, q, threads,
                        [&](int chunk, int, SensorGroup g, int sensor, double e) {
                          const int i = offset[static_cast<int>(g)] + sensor;
                          acc[chunk](i, 0) += e * e;
                          acc[chunk](i, 1) += e;
                          acc[chunk](i, 2) += 1;
                        });
  Eigen::MatrixXd total = Eigen::MatrixXd::Zero(n, 3);
  for (const auto& a : acc) total += a;
  auto stats = [&](int i) {
    ResidualStats r;
    r.count = static_cast<int>(total(i, 2));
    if (r.count > 0) {
      r.rms = std::sqrt(total(i, 0) / r.count);
      r.mae = total(i, 1) / r.count;
    }
    return r;
  };
  result->marker_residual.clear();
  result->joint_residual.clear();
  result->tendon_residual.clear();
  for (int m = 0; m < M; ++m) result->marker_residual.push_back(stats(m));
  for (int j = 0; j < J; ++j) result->joint_residual.push_back(stats(M + j));
  for (int k = 0; k < N; ++k) result->tendon_residual.push_back(stats(M + J + k));
}

RowMatrix fitAnglesToTheta(const Problem& problem, const SensorParameters& theta,
                           const RowMatrix& q_start) {
  Workspaces ws = makeWorkspaces(problem.model, problem.threads);
  QState state;
  state.q = q_start;
  QPhaseOptions qo;
  qo.method = QPhaseMethod::kLmBatch;
  qo.max_steps = 10;
  qo.threads = problem.threads;
  qPhase(problem.model, theta, problem.seed_noise, problem.loss, problem.obs, qo, &ws, &state);
  return state.q;
}

void fittedResidualRms(const Problem& problem, const SensorParameters& theta,
                       const RowMatrix& q_start, double rms[kNumSensorGroups]) {
  const std::vector<int> sub = spreadFrames(problem.obs.num_frames, 1000);
  const Observations sub_obs = selectFrames(problem.obs, sub);
  RowMatrix sub_q(sub_obs.num_frames, problem.model.dof());
  for (int k = 0; k < sub_obs.num_frames; ++k) sub_q.row(k) = q_start.row(sub[k]);
  const Problem sub_problem = problem.on(sub_obs);
  // At the seed σ, whatever the caller has adapted.
  const RowMatrix q = fitAnglesToTheta(sub_problem, theta, sub_q);
  Workspaces ws = makeWorkspaces(problem.model, problem.threads);
  const PassStats before = costPass(sub_problem, theta, problem.seed_noise, q, false, &ws);
  for (int g = 0; g < kNumSensorGroups; ++g) rms[g] = before.rms(g);
}

void summariseGroupNoise(const SensorSet& sensors, const NoiseModel& noise,
                         CalibrationSummary* summary, const std::vector<bool>* skip_joint) {
  auto rms = [](const std::vector<double>& v, const std::vector<bool>* skip) {
    double s = 0;
    int n = 0;
    for (size_t i = 0; i < v.size(); ++i)
      if (!skip || !(*skip)[i]) s += v[i] * v[i], ++n;
    return n == 0 ? 0.0 : std::sqrt(s / n);
  };
  summary->group_present[0] = !sensors.markers.empty();
  summary->group_present[1] = !sensors.joint_sensors.empty();
  summary->group_present[2] = !sensors.tendon_sensors.empty();
  summary->group_sigma[0] = rms(noise.marker, nullptr);
  summary->group_sigma[1] = rms(noise.joint, skip_joint);
  summary->group_sigma[2] = rms(noise.tendon, nullptr);
}

}  // namespace stac
