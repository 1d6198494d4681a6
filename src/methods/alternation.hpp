// The STAC alternation (paper §II-C, §III-D, §III-E) with per-group variance
// adaptation, and the start every alternating or monolithic run shares.
#pragma once

#include <functional>

#include "methods/method.hpp"
#include "solve/pass.hpp"

namespace stac {

// adaptNoise on a pass, then the pass scored again at the new σ; returns the
// largest relative change of a group's σ.
double adaptAndRescore(const Problem& problem, State* s, Workspaces* ws, PassStats* st);

// A pass at the current σ; with `adapt`, σ re-estimated from it and the pass
// re-scored at the new σ.
PassStats adaptedPass(const Problem& problem, State* s, bool adapt, Workspaces* ws);

struct LoopOutcome {
  PassStats st;
  int iterations = 0;
  bool converged = false;
  bool paused = false;  // `pause` asked to stop
  double scale_change = 0;  // the last iteration's relative σ step (0: not adapted)
  int limit = 0;  // the iteration count at which this run's budget ran out
};

// The alternation from `st` (the last pass at the current σ) until the
// relative cost decrease is below options.tolerance and σ has settled. Once
// it stalls (or from the start with `coupled`), coupled Gauss-Newton steps
// (every q_t eliminated per frame, schur.hpp), which converge fast where q
// and θ are strongly coupled and the alternation would crawl. `report` sees
// every iteration; `pause` (may be empty), asked after every unconverged
// one, stops the loop where it returns true.
LoopOutcome stacIterations(const Problem& problem, const CalibrationOptions& options,
                           bool coupled, PassStats st, State* s, Workspaces* ws,
                           const std::function<void(int, const PassStats&)>& report,
                           const std::function<bool(int)>& pause = nullptr);

// The start of a run: the seed, or the wide-basin initialisation on a
// subsample (solved there first when `presolve`), every frame's q_t from
// its initialised neighbours; progress reported as iteration 0.
struct Start {
  State state;
  PassStats st;               // the last pass at the start's σ
  bool coupled = false;       // the subsample converged: go straight to coupled steps
  double initial_cost = 0;    // at the seed
  double before_rms[kNumSensorGroups] = {0, 0, 0};
};
Start startRun(const MethodInput& in, bool presolve, Workspaces* ws);

// One STAC run from in's seed: the start, the alternation, the jumps out of
// a wrong minimum, and under Huber's loss the gross readings set aside
// (*set_aside: whether any were). runStac() is this and, after a set-aside,
// the cross-check with Cauchy's loss (redescending_check.hpp).
Outcome stacRun(const MethodInput& in, bool* set_aside);

// The outcome of a run from `start` whose state ended at final_pass
// (iterations and convergence left to the caller); moves start->state.
Outcome finishRun(const Problem& problem, Start* start, const PassStats& final_pass,
                  Workspaces* ws);

}  // namespace stac
