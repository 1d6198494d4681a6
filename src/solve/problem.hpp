// What every solver of one calibration reads and never changes (the
// measurement model, the readings, the seed σ's, the robust loss, the
// thread count), kept apart from what it changes (State) and from the
// per-thread scratch (Workspaces), as RobotModel is from KinematicsWorkspace.
#pragma once

#include <vector>

#include "stac/log.hpp"
#include "stac/measurement.hpp"
#include "solve/marker_bodies.hpp"
#include "solve/q_phase.hpp"
#include "solve/noise_adaptation.hpp"

namespace stac {

struct Problem {
  const MeasurementModel& model;
  const Observations& obs;
  const NoiseModel& seed_noise;
  const RobustLoss& loss;
  int threads = 1;  // resolved: at least 1
  // The markers that are virtual points of one tracked body, found in the
  // whole log (a subsample's bodies are the same).
  MarkerBodies bodies = {};

  // The same problem on other readings (a subsample of obs, say).
  Problem on(const Observations& other) const {
    return {model, other, seed_noise, loss, threads, bodies};
  }
};

// Everything a method moves: θ, σ (as group scales on the seed σ's) and the
// per-frame joint angles with their solver state.
struct State {
  SensorParameters theta;
  NoiseModel noise;
  GroupScales scales;
  QState q;
  double origin_lambda = 1e-4;  // the origin phase's damping, carried on
};

// One FrameWorkspace per thread.
using Workspaces = std::vector<FrameWorkspace>;
inline Workspaces makeWorkspaces(const MeasurementModel& model, int threads) {
  Workspaces ws;
  for (int i = 0; i < threads; ++i) ws.emplace_back(model);
  return ws;
}

}  // namespace stac
