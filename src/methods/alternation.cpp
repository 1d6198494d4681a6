// Wide basin. Real seeds are poor (any mocap rotation, gains of either sign,
// unknown biases, markers at link origins), so before alternating on
// everything we let the markers, whose model has no unknown scale, lead
// (wide_basin.hpp); then the full alternation with per-group variance
// adaptation, which keeps badly fitting groups from dominating while they
// are still wrong.
#include "methods/alternation.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <optional>

#include "stac/error.hpp"
#include "solve/statistics.hpp"
#include "solve/origin_phase.hpp"
#include "solve/origin_prior.hpp"
#include "solve/parallel.hpp"
#include "solve/schur.hpp"
#include "solve/theta_phase.hpp"
#include "methods/redescending_check.hpp"
#include "methods/settled_run.hpp"
#include "methods/tree_search.hpp"
#include "methods/verdict.hpp"
#include "methods/wide_basin.hpp"
#include "methods/world_turn.hpp"

namespace stac {
namespace {

// Outer iterations at most on the initial subsample of a long log.
constexpr int kPresolveIterations = 40;

// Re-estimates each group's σ scale from a pass (noise_adaptation.hpp), the
// degrees of freedom being the readings' rows less the q_t's leverage and
// the free θ entries of the group.
double adaptNoise(const Problem& problem, const PassStats& st, GroupScales* scales,
                  NoiseModel* noise) {
  GroupResiduals residuals;
  const ThetaSpace& space = problem.model.thetaSpace();
  const bool robust = problem.loss.enabled();  // tapered (noise_adaptation.hpp)
  for (int g = 0; g < kNumSensorGroups; ++g) {
    residuals.wsse[g] = robust ? st.tapered_wsse[g] / scaleTaper(kReadingRows[g]).mean_share
                               : st.wsse[g];
    residuals.dofs[g] =
        st.count[g] == 0 ? 0.0
                         : (robust ? st.tapered_rows[g] : st.wdims[g]) - st.leverage[g] -
                               space.freeInGroup(static_cast<SensorGroup>(g));
  }
  const double change = updateScales(residuals, true, scales);
  *noise = scaledNoise(problem.seed_noise, *scales);
  return change;
}

}  // namespace

double adaptAndRescore(const Problem& problem, State* s, Workspaces* ws, PassStats* st) {
  const GroupScales before = s->scales;
  const double change = adaptNoise(problem, *st, &s->scales, &s->noise);
  if (problem.loss.enabled()) {
    *st = costPass(problem, s->theta, s->noise, s->q.q, false, ws);
    return change;
  }
  // Without a robust loss each group's whitened squares scale by
  // (κ_old / κ_new)², so no pass over the frames is needed.
  st->cost = originPriorCost(problem.model.thetaSpace(), s->theta);
  for (int g = 0; g < kNumSensorGroups; ++g) {
    const double r = before.kappa[g] / s->scales.kappa[g];
    st->group_cost[g] *= r * r;
    st->cost += st->group_cost[g];
    st->leverage[g] = 0;
  }
  return change;
}

PassStats adaptedPass(const Problem& problem, State* s, bool adapt, Workspaces* ws) {
  PassStats st = costPass(problem, s->theta, s->noise, s->q.q, adapt, ws);
  if (adapt) adaptAndRescore(problem, s, ws, &st);
  return st;
}

namespace {

// A coupled step whose pass at the start also measures the dof the q_t take
// for the variance adaptation, which saves a pass with Jacobians; at the
// fixed point start and end coincide.
PassStats coupledIteration(const Problem& problem, bool adapt, double* lambda, State* s,
                           Workspaces* ws) {
  std::vector<std::array<double, kNumSensorGroups>> lev(kReductionBlocks, {0, 0, 0});
  std::vector<Eigen::MatrixXd> H(kReductionBlocks), Linv(kReductionBlocks);  // scratch
  const FrameVisitor visit = [&](int block, const FrameWorkspace& w, const Eigen::MatrixXd& Hqq) {
    H[block] = Hqq;
    Linv[block].resize(Hqq.rows(), Hqq.cols());
    addGroupLeverage(w, problem.bodies, &H[block], &Linv[block], lev[block].data());
  };
  CoupledStepOptions step;
  step.refit_rejected = true;
  step.inverse_charts = true;
  if (adapt) step.visit = visit;
  coupledStep(problem.model, s->noise, problem.loss, problem.obs, problem.threads, ws, lambda,
              &s->theta, &s->q, step);
  PassStats st = costPass(problem, s->theta, s->noise, s->q.q, false, ws);
  for (const auto& block : lev)
    for (int g = 0; g < kNumSensorGroups; ++g) st.leverage[g] += block[g];
  return st;
}

// One alternation: q-phase, θ-phase, a pass (with leverage when adapting).
PassStats alternatingIteration(const Problem& problem, const CalibrationOptions& options,
                               State* s, Workspaces* ws) {
  QPhaseOptions qo;
  qo.method = options.stac.q_phase;
  qo.threads = problem.threads;
  qo.whole_turns = true;
  ThetaPhaseOptions to;
  to.threads = problem.threads;
  qPhase(problem.model, s->theta, s->noise, problem.loss, problem.obs, qo, ws, &s->q);
  thetaPhase(problem.model, s->noise, problem.loss, problem.obs, s->q, to, ws, &s->theta);
  // Joint-origin corrections: no closed form (origin_phase.hpp).
  originPhase(problem.model, s->noise, problem.loss, problem.obs, s->q.q, 3, problem.threads, ws,
              &s->origin_lambda, &s->theta);
  return costPass(problem, s->theta, s->noise, s->q.q, options.adapt_variance, ws);
}

// Coupled steps take over once the alternation has slowed down: its
// relative decrease is below 1%, or it is below 10% and shrinks by less than
// a fifth per iteration. The alternation converges linearly, at a rate set
// by how strongly q and θ are coupled; at a rate above 0.8 it needs 10 or
// more iterations per decade, where Gauss-Newton steps on (q, θ) converge
// quadratically. Small logs with many θ (a real TIAGo arm, 30 static
// postures, 4 points of one tracked body and joint origins) decreased by
// 1-3% per iteration for 27 iterations before the 1% rule switched; with
// the rate they switch after 5 and converge in at most 16 instead of 38.
bool alternationSlowed(double rel, double prev_rel) {
  return rel < 1e-2 || (rel < 0.1 && prev_rel > 0 && rel > 0.8 * prev_rel);
}

}  // namespace

LoopOutcome stacIterations(const Problem& problem, const CalibrationOptions& options,
                           bool coupled, PassStats st, State* s, Workspaces* ws,
                           const std::function<void(int, const PassStats&)>& report,
                           const std::function<bool(int)>& pause) {
  double cost = st.cost;
  double lambda = 1e-4;
  double prev_rel = 0;  // the previous iteration's relative decrease
  LoopOutcome out;
  out.limit = options.max_iterations;
  for (int it = 1; it <= options.max_iterations; ++it) {
    // Also polled here: the presolve on the subsample reports nothing.
    if (options.should_stop && options.should_stop()) throw Cancelled();
    st = coupled ? coupledIteration(problem, options.adapt_variance, &lambda, s, ws)
                 : alternatingIteration(problem, options, s, ws);
    const double rel = (cost - st.cost) / std::max(cost, 1e-300);
    if (options.stac.coupled_steps && alternationSlowed(rel, prev_rel)) coupled = true;
    prev_rel = rel;
    out.iterations = it;
    double change = 0;
    if (report) report(it, st);
    if (options.adapt_variance) {
      change = adaptAndRescore(problem, s, ws, &st);
      // The first update of a run also absorbs the change of data or start
      // point: not a step of the geometric trend the extrapolation assumes.
      if (it == 1) std::fill(s->scales.last_step, s->scales.last_step + kNumSensorGroups, 0.0);
    }
    cost = st.cost;
    out.scale_change = change;
    if (std::abs(rel) < options.tolerance && change < 1e-3) {
      out.converged = true;
      break;
    }
    if (pause && pause(it)) {
      out.paused = true;
      break;
    }
  }
  out.st = st;
  return out;
}

namespace {

// The q_t of the frames `at` (ascending) from those of the initialised
// frames `from`: linearly in between; the nearer one where a joint jumps,
// e.g. a continuous joint a turn apart.
RowMatrix interpolateAngles(const std::vector<int>& from, const RowMatrix& from_q,
                            const std::vector<int>& at) {
  RowMatrix q(static_cast<Eigen::Index>(at.size()), from_q.cols());
  size_t k = 0;
  for (size_t i = 0; i < at.size(); ++i) {
    const int t = at[i];
    while (k + 1 < from.size() && from[k + 1] <= t) ++k;
    const bool between = t > from[k] && k + 1 < from.size();
    const double f = between ? static_cast<double>(t - from[k]) / (from[k + 1] - from[k]) : 0.0;
    for (Eigen::Index j = 0; j < q.cols(); ++j) {
      const double a = from_q(static_cast<Eigen::Index>(k), j);
      const double b = between ? from_q(static_cast<Eigen::Index>(k + 1), j) : a;
      q(static_cast<Eigen::Index>(i), j) = std::abs(b - a) < 0.5 ? a + f * (b - a) : (f < 0.5 ? a : b);
    }
  }
  return q;
}

// Interpolation is a good start for a frame's LM only while its
// neighbouring solved frames are close in time: across a wider gap a limb
// may have swept most of its range, and a few LM steps from the straight
// line between them leave it far off (on a 250,000-frame log, a gap of 250
// frames left the marker RMS at twice its noise and the coupled steps
// crawling for dozens of iterations). So the solved frames are densified
// tenfold at a time until the gap is at most this.
constexpr int kInterpolationGap = 25;

// Every frame's q_t from the subsample's (`sub`, `sub_q`), θ held: each
// level interpolated from the previous one and polished by a few LM steps.
void fillAngles(const Problem& problem, const State& s, std::vector<int> sub, RowMatrix sub_q,
                Workspaces* ws, QState* q) {
  const int T = problem.obs.num_frames;
  QPhaseOptions qo;
  qo.method = QPhaseMethod::kLmBatch;
  qo.max_steps = 3;
  qo.threads = problem.threads;
  for (;;) {
    const bool last = static_cast<long>(T) <= static_cast<long>(sub.size()) * kInterpolationGap;
    const std::vector<int> next =
        spreadFrames(T, last ? T : static_cast<int>(sub.size()) * 10);
    QState level;
    level.q = interpolateAngles(sub, sub_q, next);
    qPhase(problem.model, s.theta, s.noise, problem.loss,
           last ? problem.obs : selectFrames(problem.obs, next), qo, ws, &level);
    if (last) {
      *q = std::move(level);
      return;
    }
    sub = next;
    sub_q = std::move(level.q);
  }
}

// The wide-basin initialisation on at most kInitFrames frames spread over
// the log (wide_basin.hpp), solved there first with `presolve` (θ and σ:
// each iteration there costs a fraction of one on the whole log, which then
// needs only the last few coupled steps); then every frame's q_t from the
// initialised frames (fillAngles). With `tree_order` the initialisation's
// tree-order start alone (WideBasin::runTreeOrder). Returns whether the
// subsample converged; none (start untouched) where the tree-order start
// does not apply.
std::optional<bool> initialise(const MethodInput& in, bool presolve, bool tree_order,
                               Start* start, Workspaces* ws) {
  const Problem& problem = in.problem;
  const CalibrationOptions& options = in.options;
  State& s = start->state;
  const std::vector<int> sub = spreadFrames(problem.obs.num_frames, kInitFrames);
  const Observations sub_obs = selectFrames(problem.obs, sub);
  const Problem sub_problem = problem.on(sub_obs);
  State sub_state = s;
  sub_state.q = QState();
  sub_state.q.q = neutralPose(problem.model.robot()).transpose().replicate(sub_obs.num_frames, 1);
  if (tree_order) {
    const WideBasin basin(problem.model, sub_obs, s.noise, problem.loss, problem.threads, ws,
                          s.theta, options.stac.coupled_steps);
    std::optional<SensorParameters> theta = basin.runTreeOrder(&sub_state.q);
    if (!theta) return std::nullopt;
    sub_state.theta = std::move(*theta);
  } else {
    sub_state.theta =
        wideBasinInitialisation(problem.model, sub_obs, s.noise, problem.loss, problem.threads, ws,
                                s.theta, &sub_state.q, options.stac.coupled_steps);
  }
  bool converged = false;
  const bool presolved = presolve && sub_obs.num_frames < problem.obs.num_frames;
  if (presolved) {
    const PassStats sub_st = adaptedPass(sub_problem, &sub_state, options.adapt_variance, ws);
    // Only a start: a subsample that does not settle within
    // kPresolveIterations hands over what it has.
    CalibrationOptions sub_options = options;
    sub_options.max_iterations = std::min(options.max_iterations, kPresolveIterations);
    // (Without coupled steps to hand over to, the subsample is left as the
    // wide basin made it, as before the refactor.)
    converged = options.stac.coupled_steps &&
                stacIterations(sub_problem, sub_options, false, sub_st, &sub_state, ws, nullptr)
                    .converged;
  }
  s.theta = sub_state.theta;
  s.noise = sub_state.noise;
  s.scales = sub_state.scales;
  fillAngles(problem, s, sub, sub_state.q.q, ws, &s.q);
  // σ was adapted on the subsample when it was solved first; else here.
  start->st = adaptedPass(problem, &s, options.adapt_variance && !presolved, ws);
  return converged;
}

}  // namespace

Start startRun(const MethodInput& in, bool presolve, Workspaces* ws) {
  const Problem& problem = in.problem;
  const RobotModel& robot = problem.model.robot();
  Start start;
  State& s = start.state;
  s.theta = in.seed;
  s.noise = problem.seed_noise;
  if (in.q0) {
    if (in.q0->rows() != problem.obs.num_frames || in.q0->cols() != robot.dof())
      throw std::invalid_argument("initial joint angles have the wrong shape");
    s.q.q = *in.q0;
  } else {
    s.q.q = neutralPose(robot).transpose().replicate(problem.obs.num_frames, 1);
  }
  fittedResidualRms(problem, s.theta, s.q.q, start.before_rms);
  start.st = costPass(problem, s.theta, s.noise, s.q.q, false, ws);
  start.initial_cost = start.st.cost;
  const bool has_markers = !problem.model.sensors().markers.empty();
  const bool wide = in.options.stac.wide_basin_init && has_markers && !in.q0;
  if (wide)
    start.coupled =
        initialise(in, presolve, false, &start, ws).value_or(false) && in.options.stac.coupled_steps;
  if (in.options.progress)
    in.options.progress(makeReport(0, start.st, in.start, wide ? "init" : "seed", &s.theta));
  return start;
}

namespace {

// A converged run is checked for a wrong minimum where some sensor's
// median error is above this many times what its seed σ gives (a right one
// fits at about 1; the wrist flips of the basin test's misses at 1.6-4).
constexpr double kEscapeMisfit = 1.4;

// Jumps to a better minimum at most: each takes one move, and a log can
// need several (panda/partial basin truth 8: two pots' maps a whole turn
// off, and a third jump; with 2 it ended flagged, j5 at its limit in every
// frame). Only a run a jump kept, still misfitting, goes on to the next.
constexpr int kEscapes = 4;

// The alternation on from `st` (a pass at *s) for at most `budget`
// iterations beyond the `done` already run; reported and counted on from
// there.
LoopOutcome goOn(const Problem& problem, const MethodInput& in, int done, int budget,
                 const PassStats& st, State* s, Workspaces* ws,
                 const std::function<void(int, const PassStats&)>& report,
                 const std::function<bool(int)>& pause = nullptr) {
  CalibrationOptions rest = in.options;
  rest.max_iterations = budget;
  LoopOutcome more = stacIterations(
      problem, rest, in.options.stac.coupled_steps, st, s, ws,
      [&](int it, const PassStats& pass) { if (report) report(done + it, pass); },
      pause ? std::function<bool(int)>([&](int it) { return pause(done + it); }) : nullptr);
  more.iterations += done;
  more.limit += done;
  return more;
}

// A cost lower by less than this share is the same minimum reached again,
// by rounding: humanoid38 from a free seed (biases traded off against
// markers, their joints wherever the gauge puts them) took three jump
// rounds, 70 s each, that each ended where it began but 3e-9 lower.
constexpr double kRoundingShare = 1e-7;

// The alternation on from `moved` (a state s was moved to from `before`,
// the state `loop` ended in); its end is kept if it fits better at the σ
// the run had (the adapted σ would hide the difference), or as well with
// fewer frames at the joints' limits. Returns the kept run's outcome,
// iterations counted on from `loop`'s; none (*s = before) if not kept.
// The run from the move is a descent of its own, with the iteration
// limit's budget anew: the limit is there to stop a run that does not
// converge, not one that a late jump restarted (the bundled hand on
// partial swings, fresh truth 2: a crawl converged after 190 iterations,
// its jump's run, 15 iterations from the truth's fit, was stopped after
// 10, "not converged"). No jump is tried once a run is past the limit
// (openToJumps), so at most one such budget is spent beyond it.
std::optional<LoopOutcome> goOnIfBetter(const MethodInput& in, const LoopOutcome& loop,
                                        State before, State* s, Workspaces* ws,
                                        const std::function<void(int, const PassStats&)>& report,
                                        const std::function<bool(int)>& pause = nullptr) {
  const Problem& problem = in.problem;
  LoopOutcome again =
      goOn(problem, in, loop.iterations, in.options.max_iterations,
           costPass(problem, s->theta, s->noise, s->q.q, false, ws), s, ws, report, pause);
  const double was = costPass(problem, before.theta, before.noise, before.q.q, false, ws).cost;
  const double now = costPass(problem, s->theta, before.noise, s->q.q, false, ws).cost;
  const RobotModel& robot = problem.model.robot();
  const bool within = atWidenedLimit(robot, s->q.q).count() < atWidenedLimit(robot, before.q.q).count();
  // (As well, but not better: only a converged end. A joint swung over its
  // whole range, ±0.01 with 0.001 of noise, took three such jumps by noise,
  // the last stopped by the iteration limit: "not converged", a false alarm.)
  const bool better = now < (1 - kRoundingShare) * was ||
                      (within && again.converged && now <= (1 + kSameFit) * was);
  // From a stalled run (below) only a converged end: the stalled run, had
  // it gone on, would have fitted better than where it paused.
  if (!better || (loop.paused && !again.converged)) {
    *s = std::move(before);
    return std::nullopt;
  }
  return again;
}

// A converged run whose sensor still misfits by more than this many times
// its seed σ's noise (median error) once no jump helps is restarted from the
// initialisation's tree-order start (below). A right calibration fits at
// about 1x; the initialisation itself takes that start only beyond
// kRestartMisfit (4x), where a right start not yet converged can fit 2-3x.
constexpr double kTreeRestartMisfit = 2.0;

// Whether some sensor of s misfits by `factor` (kTreeRestartMisfit unless
// given) at the seed σ.
bool misfitsForRestart(const Problem& problem, const State& s,
                       double factor = kTreeRestartMisfit) {
  return someSensorMisfits(problem.model, s.theta, problem.seed_noise, problem.obs, s.q.q,
                           factor, factor);
}

// The alternation on from a jump's estimate `est` (*s the state before
// it), kept as goOnIfBetter says.
std::optional<LoopOutcome> goOnFromJump(const MethodInput& in, const LoopOutcome& loop,
                                        Estimate est, State* s, Workspaces* ws,
                                        const std::function<void(int, const PassStats&)>& report) {
  State before = *s;
  s->theta = std::move(est.theta);
  s->q = std::move(est.state);
  // One alternation (q, then θ) on the whole log before the coupled steps
  // go on: the start the jump was scored from (WideBasin::refinedCost).
  // Left as moved, with the markers between the moved joints where they
  // were, a first coupled step took panda/partial basin truth 6 to a cost
  // of 8e7 and its wrist a whole turn beyond the limits in every frame;
  // θ re-fitted to the moved angles alone (markers re-placed in the moved
  // links first) took humanoid38/partial basin truth 13's ankle flip to
  // another folded minimum, unconverged after 200 iterations.
  alternatingIteration(in.problem, in.options, s, ws);
  return goOnIfBetter(in, loop, std::move(before), s, ws, report);
}

// Where the base's markers leave the world's half turn open (openHalfTurn:
// one base marker or several on a line, every limb rooted on it), a run can
// converge with the world turned and the limb mirrored with it, a minimum
// that no jump reaches (the jumps move joints, not the world) and that
// fits only a little worse: an unseen Borinot flying arm (two joints, one
// base marker) on partial swings, fresh seed 13's truth 1, its markers at
// 1.6-1.9x their seed σ, verdict ok with the mocap frame 3.0 rad off. The
// tree-order search starts from both turns, so there the restart is tried
// from the jumps' own mark (kEscapeMisfit); it reached the truth.
double treeRestartMisfit(const MethodInput& in) {
  return openHalfTurn(in.problem.model, in.seed) ? kEscapeMisfit : kTreeRestartMisfit;
}

// The initialisation's tree-order start (tree_search.hpp), as a new run's
// start from in's seed, and the alternation on from there; its end is kept
// as goOnIfBetter says, if it converged. An unseen planar double pendulum (continuous
// joints) on partial swings converged in a mirror image of its motion, its
// markers at 2.7x their seed σ and one at 3.9x: the sweeps' start assumes
// swings about a range's middle, and the jumps from the converged state
// reached no better minimum; the tree-order start reaches the truth.
std::optional<LoopOutcome> restartInTreeOrder(
    const MethodInput& in, const LoopOutcome& loop, State* s, Workspaces* ws,
    const std::function<void(int, const PassStats&)>& report) {
  const Problem& problem = in.problem;
  Start alt;
  alt.state.theta = in.seed;
  alt.state.noise = problem.seed_noise;
  alt.state.q.q =
      neutralPose(problem.model.robot()).transpose().replicate(problem.obs.num_frames, 1);
  if (!initialise(in, true, true, &alt, ws)) return std::nullopt;
  State before = *s;
  *s = std::move(alt.state);
  std::optional<LoopOutcome> again = goOnIfBetter(in, loop, before, s, ws, report);
  // Only a converged end: one the iteration limit stopped would turn a
  // converged result into an unconverged one (an unseen Solo 12 with gross
  // readings: kept at the limit, "not converged").
  if (again && !again->converged) {
    *s = std::move(before);
    return std::nullopt;
  }
  return again;
}

// Jumps are tried only from a converged run (an unconverged one is
// reported so), and within its iteration limit.
bool openToJumps(const MethodInput& in, const LoopOutcome& loop) {
  return (loop.converged || loop.paused) && loop.iterations < in.options.max_iterations;
}

// The initialisation's searches can leave a minimum whose pots' maps are a
// discrete jump from the right ones (a wrist flip, a sign, a whole turn)
// that fits a little worse. From a converged run where a sensor misfits or
// a joint often sits at its limit or beyond it (verdict.hpp), the jumps
// (WideBasin::jumpToBetterMinimum) are tried, and the alternation goes on
// from a clearly better one (goOnIfBetter), at most kEscapes times, while
// openToJumps; with `limits_only`, only where a joint is at or beyond its
// limits. After a kept jump the next round looks again whatever the misfit:
// a run that had left one wrong minimum can be in another that fits within
// kEscapeMisfit (an unseen Finger Edu on partial swings, fresh truth 4: a
// half turn of its last joint took the misfit away and left the whole
// mirror image, the mocap frame 3.05 rad off, fitting 0.2% worse than the
// truth, verdict ok; the next round's whole mirror reaches the truth).
// Returns whether a sensor misfit at the last check.
bool jumpRounds(const MethodInput& in, bool limits_only, LoopOutcome* loop, State* s,
                Workspaces* ws, const std::function<void(int, const PassStats&)>& report) {
  const Problem& problem = in.problem;
  bool misfit = false;  // at the last check, at kEscapeMisfit
  bool jumped = false;  // the last round's jump was kept
  for (int round = 0; round < kEscapes && openToJumps(in, *loop); ++round) {
    misfit = someSensorMisfits(problem.model, s->theta, problem.seed_noise, problem.obs, s->q.q,
                               kEscapeMisfit, kEscapeMisfit);
    std::vector<int> at_limits =
        jointsOftenAtLimit(problem.model.robot(), s->q.q, kEscapeShareAtLimit);
    for (int j : jointsOftenBeyondLimits(problem.model, s->theta, s->noise, problem.loss,
                                         problem.obs, s->q.q, kEscapeShareAtLimit))
      at_limits.push_back(j);
    if (at_limits.empty() && limits_only) break;
    // Where nothing misfits, the first round tries the world's half turns
    // alone (world_turn.hpp): the markers read the same after them, and a
    // tendon's misfit can be below kEscapeMisfit (an unseen Bravo 7 on a
    // BlueVolta ROV on partial swings: 1.35x, verdict ok, in 4 of 10
    // truths of a random layout).
    const bool quiet = at_limits.empty() && !(misfit || jumped);
    if (quiet && (round > 0 || worldTurnColumns(problem.model, s->theta).empty())) break;
    Estimate est{s->theta, s->q};
    {
      const WideBasin basin(problem.model, problem.obs, s->noise, problem.loss, problem.threads,
                            ws, s->theta, in.options.stac.coupled_steps);
      if (!basin.jumpToBetterMinimum(&est, at_limits, quiet)) break;
    }
    std::optional<LoopOutcome> again = goOnFromJump(in, *loop, std::move(est), s, ws, report);
    if (!again) break;
    *loop = std::move(*again);
    misfit = jumped = true;  // misfit: not checked since the jump
  }
  return misfit;
}

// The jumps; where a sensor still misfits by treeRestartMisfit, the
// restart in tree order (above), and the jumps again from its end.
LoopOutcome escapeWrongMinimum(const MethodInput& in, LoopOutcome loop, State* s, Workspaces* ws,
                               const std::function<void(int, const PassStats&)>& report) {
  const Problem& problem = in.problem;
  const bool misfit = jumpRounds(in, false, &loop, s, ws, report);
  if (!misfit || !openToJumps(in, loop) || !misfitsForRestart(problem, *s, treeRestartMisfit(in)))
    return loop;
  if (std::optional<LoopOutcome> again = restartInTreeOrder(in, loop, s, ws, report)) {
    loop = std::move(*again);
    // The restarted run's end is checked for a joint at or beyond its
    // limits: an unseen Unitree Z1 on partial swings, restarted from a
    // misfit, converged in its arm's mirror (q1 + π, π − q2, −q3..−q5,
    // q6 + π) with joint 1 beyond its limit in 341 of 600 frames, and the
    // jump back was never tried. Not for a misfit alone: the jumps from the
    // first end found none.
    jumpRounds(in, true, &loop, s, ws, report);
  }
  return loop;
}

// Of the configurations the result will list as fitting as well (the
// mirrors, mirror_ambiguity.hpp), the one that fits better is taken
// (WideBasin::jumpToBetterEquivalent), once, and kept as goOnIfBetter
// says: of two minima the data hardly tell apart, the likelier one is
// reported, the other listed. The jumps (above) take none of them: they
// are within kSameFit, and where nothing misfits no jump is tried.
// Where none is taken, `mirrors` gets the candidates found at *s, which
// the result lists (finding them again cost the bundled hand 15% of its
// calibration).
LoopOutcome takeBetterEquivalent(const MethodInput& in, LoopOutcome loop, State* s,
                                 Workspaces* ws,
                                 const std::function<void(int, const PassStats&)>& report,
                                 std::optional<MirrorCandidates>* mirrors) {
  const Problem& problem = in.problem;
  if (!openToJumps(in, loop) || !mirrorsApply(problem.model, s->q.q)) return loop;
  Estimate est{s->theta, s->q}, better;
  bool moved = false;
  {
    // As the result's listing builds it (mirrorAmbiguities).
    const WideBasin basin(problem.model, problem.obs, s->noise, problem.loss, problem.threads, ws,
                          s->theta, false);
    *mirrors = mirrorCandidates(basin, est, &better, &moved);
  }
  if (!moved) return loop;
  mirrors->reset();  // found at the state left
  std::optional<LoopOutcome> again = goOnFromJump(in, loop, std::move(better), s, ws, report);
  return again ? std::move(*again) : loop;
}

// A pot's map p = g q + b can change its sign only through g = ∞, its
// joint held still: a pot whose map starts with the wrong sign on a joint
// that few other readings pin (a finger's last joint swung over a third of
// its range) drifts along that path, its gain growing geometrically while
// the fit shrinks its joint's motion (×7 in 40 iterations, ×1000 in 200 on
// the basin test's hand), and never converges. A run still unconverged
// after kDivergenceCheck iterations with a free gain grown beyond
// kDivergedGain times its start's is paused once; those pots restart from
// their start's maps mirrored, their joints' motion with them
// (flipSign), and the run goes on from there if that ends better.
// A run may also converge on that path: under Cauchy's loss the markers
// that would pull the joint back misfit, and so weigh almost nothing, once
// the pot holds it still (an unseen Go1 and A1 with 5% gross readings: a
// calf pot's gain -31,000 from a start of -3.4 (the truth's +2.9), the
// joint frozen, its nearby marker at twice its σ, converged in 17
// iterations, and no check of the verdict fails). A converged run with
// such a gain gets the same restart.
constexpr int kDivergenceCheck = 30;
// A run still unconverged after this many iterations with a sensor misfit
// by kTreeRestartMisfit is paused once, and the escapes tried from there;
// one that converges later still misfitting is suspect (slowConvergence).
constexpr int kStallCheck = 60;
constexpr double kDivergedGain = 4.0;

// The guesses whose pot's gain in `now` has grown beyond kDivergedGain
// times its magnitude in `from`.
std::vector<int> divergedPots(const std::vector<PotGuess>& guesses, const SensorParameters& from,
                              const SensorParameters& now) {
  std::vector<int> out;
  for (size_t i = 0; i < guesses.size(); ++i) {
    const int j = guesses[i].sensor;
    if (std::abs(now.joint_sensor[j].gain) > kDivergedGain * std::abs(from.joint_sensor[j].gain))
      out.push_back(static_cast<int>(i));
  }
  return out;
}

// The alternation from the start, paused where a pot's gain diverges
// (above), then on to its end; or paused where it stalls in a misfit
// (kStallCheck), for the escapes to be tried from there.
LoopOutcome iterateFromStart(const MethodInput& in, const Start& start, State* s, Workspaces* ws,
                             const std::function<void(int, const PassStats&)>& report) {
  const Problem& problem = in.problem;
  const State first = *s;
  const std::vector<PotGuess> guesses =
      makePotGuesses(problem.model.robot(), problem.model.sensors(), s->theta, problem.obs);
  const auto stalled = [&](int it) {
    return it == kStallCheck && it < in.options.max_iterations && misfitsForRestart(problem, *s);
  };
  LoopOutcome loop = stacIterations(
      problem, in.options, start.coupled, start.st, s, ws, report, [&](int it) {
        return (it >= kDivergenceCheck && it < in.options.max_iterations &&
                !divergedPots(guesses, first.theta, s->theta).empty()) ||
               stalled(it);
      });
  const std::vector<int> diverged = divergedPots(guesses, first.theta, s->theta);
  const bool converged_diverged = loop.converged && !diverged.empty() &&
                                  loop.iterations < in.options.max_iterations;
  const bool paused_diverged = loop.paused && !diverged.empty();  // not a stall
  if (!paused_diverged && !converged_diverged) return loop;
  State before = *s;
  for (int i : diverged) {
    const PotGuess& g = guesses[i];
    s->theta.joint_sensor[g.sensor] = first.theta.joint_sensor[g.sensor];
    s->q.q.col(g.column) = first.q.q.col(g.column);
    flipSign(g, &s->theta, &s->q.q);
  }
  LoopOutcome flipped = loop;
  flipped.paused = false;  // the flip's end is compared as any jump's
  if (std::optional<LoopOutcome> again =
          goOnIfBetter(in, flipped, std::move(before), s, ws, report, stalled))
    return *again;
  return loop.paused ? goOn(problem, in, loop.iterations, loop.limit - loop.iterations, loop.st, s,
                            ws, report, stalled)
                     : loop;
}

// Under Huber's loss a gross reading still pulls with a constant force: on
// a joint that few markers see, a pot's gross error drags its frame's angle
// along (a third of the way, on the basin test's arms), and the error left
// correlates with that angle, which biases the gain by 1-2 std however the
// errors' signs fall (5% gross readings: errors 1.15-1.3 std in RMS, and
// silent misses). A redescending loss lets go of them; Huber's convex start
// does not need to. So once the Huber run has converged, the readings
// beyond the σ taper's bound (pass.hpp withoutGrossReadings) are set aside
// and the run goes on without them, within its iteration limit. `kept`
// holds the readings kept; returns the problem the result was fitted on.
Problem setGrossReadingsAside(const MethodInput& in, LoopOutcome* loop, State* s, Workspaces* ws,
                              const std::function<void(int, const PassStats&)>& report,
                              Observations* kept) {
  const Problem& problem = in.problem;
  if (problem.loss.kind() != LossKind::kHuber || !loop->converged || loop->iterations >= loop->limit)
    return problem;
  int gross = 0;
  *kept = withoutGrossReadings(problem, s->theta, s->noise, s->q.q, &gross);
  if (gross == 0) return problem;
  const Problem without = problem.on(*kept);
  *loop = goOn(without, in, loop->iterations, loop->limit - loop->iterations,
               costPass(without, s->theta, s->noise, s->q.q, false, ws), s, ws, report);
  return without;
}

// A run that converged only after kStallCheck iterations, still misfitting
// by kTreeRestartMisfit: a crawl that no escape fitted better. The bundled
// hand on partial swings (basin truth 10), let run to 1500 iterations,
// converged after 768 in a wrong minimum of its thumb (two pots' signs
// flipped, the MCP pot's gain 7.0 where the truth's is -2.8), its thumb's
// markers and pots at 1.4-2.5x their σ:
// under the verdict's bound for a σ that is merely too small (4x), so it
// passed as ok. A right calibration converges quickly and fits at about
// 1x; a crawl that ends still misfitting is a wrong minimum's mark. (Judged
// by the iteration count, not by whether the kept run itself stalled: that
// crawl was a jump's run, kept because it fitted better, which nothing
// watched for a stall.) Returns the verdict reason, or empty.
// A run the iteration limit stopped, settled (converged only so), is held
// to kSettledMisfit: no escape ran from its end, which a converged run gets
// from kEscapeMisfit (hand24 partial, fresh seed 13 truth 10: a jump's run
// crawled to its limit, a middle-finger marker's median error at 1.76x,
// the finger's trade-off listed undetermined where the truth's own fit
// determines it, verdict ok; the bundled hand's right settled crawl,
// SettledRun's, has a thumb pot at 1.41x).
constexpr double kSettledMisfit = 1.6;
std::string slowConvergence(const Problem& problem, const Outcome& out, bool settled_at_limit) {
  if (!out.converged || out.iterations <= kStallCheck) return "";
  const SensorMisfit worst = worstMisfit(problem.model, out.theta, problem.seed_noise,
                                         problem.obs, out.q);
  if (!(worst.ratio > (settled_at_limit ? kSettledMisfit : kTreeRestartMisfit))) return "";
  char ratio[32];
  std::snprintf(ratio, sizeof ratio, "%.3g", worst.ratio);
  return "converged only after " + std::to_string(out.iterations) +
         " iterations, no jump or restart fitting better, to a fit where sensor " +
         problem.model.sensors().sensorName(worst.group, worst.sensor) + "'s median error is " +
         ratio + " times what its seed sigma gives: likely a wrong minimum (a sign or mirror "
         "of the joints near it); try another seed or a log with more varied motion";
}

}  // namespace

Outcome stacRun(const MethodInput& in, bool* set_aside) {
  const Problem& problem = in.problem;
  Workspaces ws = makeWorkspaces(problem.model, problem.threads);
  Start start = startRun(in, true, &ws);
  State& s = start.state;
  const auto report = [&](int it, const PassStats& st) {
    if (in.options.progress) in.options.progress(makeReport(it, st, in.start, "stac", &s.theta));
  };
  LoopOutcome loop = iterateFromStart(in, start, &s, &ws, report);
  loop = escapeWrongMinimum(in, std::move(loop), &s, &ws, report);
  if (loop.paused)
    loop = goOn(problem, in, loop.iterations, loop.limit - loop.iterations, loop.st, &s, &ws,
                report);
  std::optional<MirrorCandidates> mirrors;
  loop = takeBetterEquivalent(in, std::move(loop), &s, &ws, report, &mirrors);
  Observations kept;
  const Problem fitted = setGrossReadingsAside(in, &loop, &s, &ws, report, &kept);
  Outcome out = finishRun(fitted, &start, loop.st, &ws);
  // Found at the end's state unless readings were set aside since.
  if (&fitted.obs == &problem.obs) out.mirrors = std::move(mirrors);
  out.iterations = loop.iterations;
  out.converged = loop.converged || (loop.iterations >= loop.limit &&
                                     settled(out.uncertainty.decrement, loop.scale_change));
  out.slow_convergence = slowConvergence(fitted, out, !loop.converged);
  *set_aside = &fitted.obs != &problem.obs;
  return out;
}

Outcome runStac(const MethodInput& in) {
  bool set_aside = false;
  Outcome out = stacRun(in, &set_aside);
  return set_aside ? crossCheckWithCauchy(in, std::move(out)) : out;
}

Outcome finishRun(const Problem& problem, Start* start, const PassStats& final_pass,
                  Workspaces* ws) {
  State& s = start->state;
  Outcome out;
  out.initial_cost = start->initial_cost;
  std::copy(start->before_rms, start->before_rms + kNumSensorGroups, out.before_rms);
  out.final_cost = final_pass.cost;
  for (int g = 0; g < kNumSensorGroups; ++g) out.after_rms[g] = final_pass.rms(g);
  // Uncertainty at the optimum, with the final σ.
  out.uncertainty = estimateUncertainty(problem.model, s.theta, s.noise, problem.loss,
                                        problem.obs, s.q.q, problem.threads, ws);
  out.theta = std::move(s.theta);
  out.noise = std::move(s.noise);
  out.marker_scale = s.scales.kappa[0];
  out.q = std::move(s.q.q);
  return out;
}

}  // namespace stac
