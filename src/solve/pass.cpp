#include "solve/pass.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "solve/noise_adaptation.hpp"
#include "solve/origin_prior.hpp"
#include "solve/parallel.hpp"

namespace stac {

void PassStats::add(const PassStats& s) {
  cost += s.cost;
  for (int g = 0; g < kNumSensorGroups; ++g) {
    sse[g] += s.sse[g];
    count[g] += s.count[g];
    wsse[g] += s.wsse[g];
    wdims[g] += s.wdims[g];
    leverage[g] += s.leverage[g];
    tapered_wsse[g] += s.tapered_wsse[g];
    tapered_rows[g] += s.tapered_rows[g];
    group_cost[g] += s.group_cost[g];
  }
}

namespace {

// Adds the readings of the last evaluation in w to st; returns their rows.
int addReadings(const FrameWorkspace& w, const NoiseModel& noise, const NoiseModel& seed_noise,
                PassStats* st) {
  int rows = 0;
  for (int i = 0; i < w.count; ++i) {
    const ReadingJacobian& rj = w.readings[i];
    const int g_idx = static_cast<int>(rj.group);
    const double sigma = noise.sigma(rj.group, rj.sensor);
    const double seed_sigma = seed_noise.sigma(rj.group, rj.sensor);
    st->sse[g_idx] += rj.s * sigma * sigma;
    st->count[g_idx] += 1;
    const double ratio = sigma / seed_sigma;
    st->wsse[g_idx] += rj.weight * rj.s * ratio * ratio;
    st->wdims[g_idx] += rj.weight * rj.rows;
    const double phi = scaleTaper(rj.rows).weight(rj.s);
    st->tapered_wsse[g_idx] += phi * rj.s * ratio * ratio;
    st->tapered_rows[g_idx] += phi * rj.rows;
    st->group_cost[g_idx] += 0.5 * rj.rho;
    rows += rj.rows;
  }
  return rows;
}

}  // namespace

PassStats costPass(const Problem& problem, const SensorParameters& theta, const NoiseModel& noise,
                   const RowMatrix& q, bool leverage, Workspaces* ws) {
  const Observations& obs = problem.obs;
  const int T = obs.num_frames;
  const int dof = problem.model.dof();
  std::vector<PassStats> chunk_stats(numChunks(T));
  FrameOptions eo;
  eo.jacobians = leverage;
  parallelFor(numChunks(T), problem.threads, [&](int chunk, int tid) {
    FrameWorkspace& w = (*ws)[tid];
    PassStats& st = chunk_stats[chunk];
    Eigen::VectorXd qt(dof), g(dof);
    Eigen::MatrixXd H(dof, dof), Linv(dof, dof);
    const int end = std::min(T, (chunk + 1) * kFramesPerChunk);
    for (int t = chunk * kFramesPerChunk; t < end; ++t) {
      qt = q.row(t).transpose();
      st.cost += evaluateFrame(problem.model, theta, noise, problem.loss, frameReadings(obs, t),
                               qt, eo, &w);
      const int rows = addReadings(w, noise, problem.seed_noise, &st);
      if (!leverage || rows == 0) continue;
      accumulateNormalEquations(w, &H, &g);
      addGroupLeverage(w, problem.bodies, &H, &Linv, st.leverage);
    }
  });
  PassStats total;
  for (const PassStats& s : chunk_stats) total.add(s);
  // The cost every step minimises is the posterior's (origin_prior.hpp).
  total.cost += originPriorCost(problem.model.thetaSpace(), theta);
  return total;
}

namespace {

// Every reading of every frame of problem.obs at q, without Jacobians, in
// parallel: visit(chunk, frame, reading) for each; chunks are numChunks(T)
// runs of kFramesPerChunk frames, so that a caller can gather per chunk
// and keep the frames' order.
template <typename Visit>
void forEachReading(const Problem& problem, const SensorParameters& theta, const NoiseModel& noise,
                    const RowMatrix& q, const Visit& visit) {
  const MeasurementModel& model = problem.model;
  Workspaces ws = makeWorkspaces(model, problem.threads);
  const int T = problem.obs.num_frames;
  FrameOptions eo;
  eo.jacobians = false;
  parallelFor(numChunks(T), problem.threads, [&](int chunk, int tid) {
    FrameWorkspace& w = ws[tid];
    Eigen::VectorXd qt(model.dof());
    const int end = std::min(T, (chunk + 1) * kFramesPerChunk);
    for (int t = chunk * kFramesPerChunk; t < end; ++t) {
      qt = q.row(t).transpose();
      evaluateFrame(model, theta, noise, problem.loss, frameReadings(problem.obs, t), qt, eo, &w);
      for (int i = 0; i < w.count; ++i) visit(chunk, t, w.readings[i]);
    }
  });
}

}  // namespace

std::vector<DownweightedReading> downweightedReadings(const Problem& problem,
                                                      const SensorParameters& theta,
                                                      const NoiseModel& noise, const RowMatrix& q,
                                                      int max_count) {
  std::vector<DownweightedReading> all;
  if (!problem.loss.enabled() || max_count <= 0) return all;
  const SensorSet& sensors = problem.model.sensors();
  std::vector<std::vector<DownweightedReading>> per_chunk(numChunks(problem.obs.num_frames));
  forEachReading(problem, theta, noise, q, [&](int chunk, int t, const ReadingJacobian& rj) {
    if (rj.weight < 0.999)
      per_chunk[chunk].push_back({t, sensors.sensorName(rj.group, rj.sensor), rj.weight});
  });
  for (auto& c : per_chunk) all.insert(all.end(), c.begin(), c.end());
  std::stable_sort(all.begin(), all.end(), [](const auto& a, const auto& b) {
    return a.weight < b.weight;
  });
  if (static_cast<int>(all.size()) > max_count) all.resize(max_count);
  return all;
}

Observations withoutGrossReadings(const Problem& problem, const SensorParameters& theta,
                                  const NoiseModel& noise, const RowMatrix& q, int* count) {
  struct Gross {
    int frame;
    SensorGroup group;
    int sensor;
  };
  std::vector<std::vector<Gross>> per_chunk(numChunks(problem.obs.num_frames));
  forEachReading(problem, theta, noise, q, [&](int chunk, int t, const ReadingJacobian& rj) {
    if (rj.s > scaleTaper(rj.rows).bound) per_chunk[chunk].push_back({t, rj.group, rj.sensor});
  });
  Observations kept = problem.obs;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  *count = 0;
  for (const auto& chunk : per_chunk)
    for (const Gross& g : chunk) {
      ++*count;
      if (g.group == SensorGroup::kMarker)
        kept.marker.block(g.frame, 3 * g.sensor, 1, 3).setConstant(nan);
      else if (g.group == SensorGroup::kJoint)
        kept.joint(g.frame, g.sensor) = nan;
      else
        kept.tendon(g.frame, g.sensor) = nan;
    }
  return kept;
}

IterationReport makeReport(int it, const PassStats& st, Clock::time_point start,
                           const std::string& stage, const SensorParameters* theta) {
  IterationReport r;
  r.theta = theta;
  r.iteration = it;
  r.cost = st.cost;
  for (int g = 0; g < kNumSensorGroups; ++g) {
    r.present[g] = st.count[g] > 0;
    r.rms[g] = st.rms(g);
  }
  r.elapsed = std::chrono::duration<double>(Clock::now() - start).count();
  r.stage = stage;
  return r;
}

}  // namespace stac
