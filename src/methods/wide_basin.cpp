// Wide-basin initialisation (see calibrate.cpp's header comment): pots'
// readings mapped onto their joint ranges with signs chosen by the markers,
// closed-form mocap frame and markers, then a marker-led alternation.
#include "methods/wide_basin.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "methods/tendon_mirror.hpp"
#include "methods/world_turn.hpp"
#include "methods/tree_search.hpp"
#include "methods/turn_ambiguity.hpp"
#include "methods/verdict.hpp"
#include "stac/calibrate.hpp"
#include "stac/kinematics.hpp"
#include "solve/schur.hpp"
#include "solve/statistics.hpp"
#include "solve/theta_phase.hpp"

namespace stac {
namespace {

// The initialisation's coupled steps: over `groups`, every q_t kept within
// its joints' widened limits (schur.hpp CoupledStepOptions).
CoupledStepOptions withinLimits(const FrameOptions& groups) {
  CoupledStepOptions o;
  o.groups = groups;
  o.within_limits = true;
  return o;
}

// Global scales of the guessed maps below: the log covers 80%, 40%, 20% or
// 10% of the joints' ranges.
constexpr double kCoverageScales[] = {1.0, 0.5, 0.25, 0.125};
// The pots' weight in the first marker-led alternation (σ x 10): their
// guessed maps' scales are rough, so the markers lead q and the pots'
// θ-phase fits gains to marker-driven angles rather than to themselves.
constexpr double kInitPotWeight = 0.01;
// The tree-order restart: only where a sensor's median error is above this
// many times its noise's (mirror images fit 5-20x; a right estimate not yet
// converged can fit 2-3x), and its estimate replaces the first below this
// share of the first's cost.
constexpr double kRestartMisfit = 4.0;
// The sign re-check's threshold for a tendon: at the start the angles are
// fitted without the tendons, and a tendon's length sums the errors of
// every joint it spans (humanoid38's sat above 2x with every sign right,
// and the re-check then doubled the start's time), while a pot's wrong
// sign shows at 8-10x in the tendons spanning its joint.
constexpr double kStartTendonMisfit = 4.0;
constexpr double kClearlyBetter = 0.8;
// Frames of the candidate search and of the coupled re-check.
constexpr int kSearchFrames = 150;

bool hasFreeMarkerGroup(const SensorSet& sensors) {
  return !sensors.markers.empty() &&
         (!sensors.mocap_frame_fixed.all() ||
          std::any_of(sensors.markers.begin(), sensors.markers.end(),
                      [](const MarkerConfig& m) { return !m.fixed; }));
}

// Some marker or part of the mocap frame held (the gauge removed).
bool gaugeHeld(const SensorSet& sensors) {
  return sensors.mocap_frame_fixed.any() ||
         std::any_of(sensors.markers.begin(), sensors.markers.end(),
                     [](const MarkerConfig& m) { return m.fixed; });
}

// The search scores by the markers alone.
FrameOptions markersOnly() {
  FrameOptions eval;
  eval.group_weight[1] = eval.group_weight[2] = 0.0;
  return eval;
}

}  // namespace

// Misfit: a median residual over the frames more than `factor` times what
// Gaussian noise of the sensor's σ gives (statistics.hpp). Medians, so that gross
// outliers do not count: a sign chosen wrong shows in every frame. The
// tendons against their own factor (0: not checked): a pot's sign chosen
// wrong on a joint that moves its markers little (a finger's last joint)
// shows only in the tendons that span it.
SensorMisfit worstMisfit(const MeasurementModel& model, const SensorParameters& theta,
                         const NoiseModel& noise, const Observations& obs, const RowMatrix& q,
                         double tendon_factor) {
  const auto errors = medianErrors(model, theta, obs, q, 1);
  SensorMisfit worst;
  for (SensorGroup g : {SensorGroup::kMarker, SensorGroup::kJoint, SensorGroup::kTendon}) {
    const int gi = static_cast<int>(g);
    const double k = g == SensorGroup::kTendon ? tendon_factor : 1.0;
    if (k <= 0) continue;
    for (size_t i = 0; i < errors[gi].size(); ++i) {
      if (errors[gi][i].count == 0) continue;
      const double ratio =
          errors[gi][i].median / (kMedianErrorInSigma[gi] * noise.sigma(g, static_cast<int>(i))) / k;
      if (ratio > worst.ratio) worst = {g, static_cast<int>(i), ratio};
    }
  }
  return worst;
}

bool someSensorMisfits(const MeasurementModel& model, const SensorParameters& theta,
                       const NoiseModel& noise, const Observations& obs, const RowMatrix& q,
                       double factor, double tendon_factor) {
  return worstMisfit(model, theta, noise, obs, q, tendon_factor / factor).ratio > factor;
}

// ---- WideBasin ----

WideBasin::WideBasin(const MeasurementModel& model, const Observations& obs,
                     const NoiseModel& noise, const RobustLoss& loss, int threads,
                     std::vector<FrameWorkspace>* ws, const SensorParameters& seed,
                     bool coupled_steps)
    : model_(model),
      obs_(obs),
      noise_(noise),
      loss_(loss),
      threads_(threads),
      ws_(ws),
      seed_(seed),
      coupled_steps_(coupled_steps),
      marker_group_free_(hasFreeMarkerGroup(model.sensors())),
      guesses_(makePotGuesses(model.robot(), model.sensors(), seed, obs, loss.enabled())),
      moves_(signMoves(model.robot(), guesses_)),
      sub_frames_(spreadFrames(obs.num_frames, kSearchFrames)),
      sub_(selectFrames(obs, sub_frames_)) {
  free_only_.method = QPhaseMethod::kLmBatch;
  free_only_.max_steps = 4;
  free_only_.step_tolerance = 1e-6;  // a score, not a fit
  free_only_.threads = threads;
  free_only_.eval = markersOnly();
  free_only_.frozen.assign(model.dof(), false);
  for (const PotGuess& g : guesses_) free_only_.frozen[g.column] = true;
  for (int j = 0; j < model.dof(); ++j) any_free_ |= !free_only_.frozen[j];
}

// The joints no pot covers (gimbals driven by linear pots, say) follow the
// markers by a few LM steps from where the search's best left them.
ScoredCandidate WideBasin::score(const Candidate& c, const SearchState& from) const {
  ScoredCandidate out;
  QState& ss = out.state;
  ss.q = from.warm_q;
  ss.lambda = from.damping;
  applyCandidate(guesses_, c, sub_, &ss.q);
  SensorParameters th = seed_;
  if (marker_group_free_) {
    ThetaPhaseOptions to;
    to.threads = threads_;
    to.update[1] = to.update[2] = false;
    initialiseMarkerGroup(model_, sub_, ss, 2, threads_, ws_, &th);
    thetaPhase(model_, noise_, loss_, sub_, ss, to, ws_, &th);
  }
  if (any_free_) qPhase(model_, th, noise_, loss_, sub_, free_only_, ws_, &ss);
  out.cost = totalCost(model_, th, noise_, loss_, sub_, free_only_.eval, threads_, ws_, &ss);
  return out;
}

SearchState WideBasin::startSearch(const Candidate& c) const {
  SearchState s;
  s.warm_q = neutralPose(model_.robot()).transpose().replicate(sub_.num_frames, 1);
  ScoredCandidate first = score(c, s);
  s.best = c;
  s.cost = first.cost;
  s.warm_q = std::move(first.state.q);
  s.damping = std::move(first.state.lambda);
  return s;
}

bool WideBasin::offer(const Candidate& c, double factor, SearchState* s) const {
  ScoredCandidate trial = score(c, *s);
  s->damping = std::move(trial.state.lambda);
  if (!(trial.cost < factor * s->cost)) return false;
  s->best = c;
  s->cost = trial.cost;
  s->warm_q = std::move(trial.state.q);
  return true;
}

// Tried before the greedy single-sign sweeps. The 80%-coverage scale is a
// guess too: a log that moves each joint through a fifth of a ±2π range (a
// UR arm's) needs a map 4x narrower, so each pattern is scored at a few
// common scales.
void WideBasin::mirrorSweep(SearchState* s) const {
  const std::vector<std::vector<bool>> patterns = mirrorPatterns(model_.robot(), guesses_);
  const Candidate base = s->best;
  for (double scale : kCoverageScales) {
    const Candidate at_scale = scaled(base, guesses_, scale);
    offer(at_scale, 1.0, s);
    for (const std::vector<bool>& pattern : patterns)
      offer(withSigns(at_scale, guesses_, pattern), 1.0, s);
  }
}

// A user's rough calibration (or a previous one) must not lose to the
// guesses.
void WideBasin::seedCheck(SearchState* s) const {
  offer(seededMaps(s->best, guesses_, seed_), 1.0, s);
}

bool WideBasin::signSweeps(SearchState* s) const {
  bool any = false;
  for (int sweep = 0; sweep < 3; ++sweep) {
    bool changed = false;
    for (const std::vector<int>& move : moves_) {
      if (touchesFixed(guesses_, move)) continue;
      // Two signs at once only for a clear gain: with outliers in the data
      // a double mirror can score marginally better by chance.
      changed |= offer(flipped(s->best, move), move.size() > 1 ? 0.95 : 1.0, s);
    }
    any |= changed;
    if (!changed) break;
  }
  return any;
}

// Joints of one log rarely cover their ranges alike.
bool WideBasin::rescaleSweep(SearchState* s) const {
  bool changed = false;
  for (size_t i = 0; i < guesses_.size(); ++i) {
    if (guesses_[i].fixed) continue;
    for (double f : {0.5, 2.0})
      for (int step = 0; step < 3; ++step) {
        if (!offer(rescaled(s->best, static_cast<int>(i), f), 0.98, s)) break;
        changed = true;
      }
  }
  return changed;
}

Candidate WideBasin::searchPotMaps() const {
  SearchState s = startSearch(guessedMaps(guesses_));
  mirrorSweep(&s);
  seedCheck(&s);
  // Signs first (with wrong signs a narrower map always fits better), then
  // each guess's own scale, then signs again if a scale changed.
  signSweeps(&s);
  if (rescaleSweep(&s)) signSweeps(&s);
  return s.best;
}

void WideBasin::adoptPotMaps(const Candidate& c, Estimate* est) const {
  RowMatrix& q = est->state.q;
  applyCandidate(guesses_, c, obs_, &q);
  for (size_t i = 0; i < guesses_.size(); ++i) {
    const PotGuess& g = guesses_[i];
    // The searches fit the markers, which see a revolute joint alike a
    // turn apart; its limits decide (an unseen ANYmal with gross readings:
    // a knee's map a turn off put its motion 5 rad beyond the knee's limit
    // at -3π; the q-phase held those frames at the box and they crawled
    // back 0.013 rad an iteration, unconverged after 200).
    const double turn = 2 * M_PI * turnsIntoLimits(model_, g.column, q.col(g.column));
    q.col(g.column).array() += turn;
    GainBias& gb = est->theta.joint_sensor[g.sensor];
    if (!g.fixed) gb.gain = 1.0 / c.maps[i].alpha;
    if (!g.bias_held) gb.bias = g.pivot - (c.maps[i].mid + turn) / c.maps[i].alpha;
  }
}

void WideBasin::alternate(double pot_weight, double tol, Estimate* est) const {
  QPhaseOptions qo;
  qo.method = QPhaseMethod::kLmIter;
  qo.threads = threads_;
  qo.eval.group_weight[1] = pot_weight;
  qo.eval.group_weight[2] = 0.0;
  ThetaPhaseOptions to;
  to.threads = threads_;
  to.update[1] = !guesses_.empty();  // pots carry their guessed maps
  to.update[2] = false;
  double prev = -1;
  for (int it = 0; it < 30; ++it) {
    double c = 0;
    if (it < 2 && guesses_.empty()) {
      // No pot to guess from: track through time from the neutral pose
      // (twice: the second time with the mocap frame and markers the
      // first pass allowed).
      QPhaseOptions tr = qo;
      tr.method = QPhaseMethod::kLmBatch;
      tr.max_steps = 20;
      c = trackingPass(model_, est->theta, noise_, loss_, obs_, tr, neutralPose(model_.robot()),
                       32, ws_, &est->state);
    } else {
      c = qPhase(model_, est->theta, noise_, loss_, obs_, qo, ws_, &est->state);
    }
    if (marker_group_free_ || !guesses_.empty())
      thetaPhase(model_, noise_, loss_, obs_, est->state, to, ws_, &est->theta);
    // Coupled steps once the alternation stalls (they cost more).
    if (coupled_steps_ && prev > 0 && prev - c < 1e-2 * prev)
      c = coupledStep(model_, noise_, loss_, obs_, threads_, ws_, &est->coupled_lambda,
                      &est->theta, &est->state, withinLimits(qo.eval));
    if (prev > 0 && std::abs(prev - c) <= tol * prev) break;
    prev = c;
  }
}

// A candidate's worth: the cost after a few alternations on the subsample.
double WideBasin::refine(SensorParameters* theta, QState* state, PotSteps pots) const {
  SensorParameters& th = *theta;
  QState& st = *state;
  QPhaseOptions qo;
  qo.method = QPhaseMethod::kLmIter;
  qo.threads = threads_;
  ThetaPhaseOptions to;
  to.threads = threads_;
  double c = 0;
  for (int it = 0; it < 2; ++it) {
    c = qPhase(model_, th, noise_, loss_, sub_, qo, ws_, &st);
    thetaPhase(model_, noise_, loss_, sub_, st, to, ws_, &th);
  }
  // Coupled steps converge in a few iterations where the alternation crawls.
  double lambda = 1e-3;
  CoupledStepOptions step = withinLimits(qo.eval);
  step.inverse_charts = pots == PotSteps::kInverseCharts;
  for (int it = 0; it < 5; ++it)
    c = coupledStep(model_, noise_, loss_, sub_, threads_, ws_, &lambda, &th, &st, step);
  return c;
}

// After the initial alternation: if a sensor still fits far worse than its
// noise (the tendons fitted to the angles first), the likeliest cause is a
// pot whose sign the marker-only scoring above got wrong (a joint that
// moves its markers little, e.g. a wrist with markers close to its axes,
// or a finger's last joint, which only the tendons spanning it see). Each
// sign move, tried from the current estimate and refined by a few
// alternations on the subsample, is kept if it lowers the cost clearly.
std::optional<MinimumMove> WideBasin::tendonCentred(const MinimumMove& move,
                                                    const SensorParameters& theta,
                                                    const RowMatrix& q, bool only_tendons) const {
  if (move.flip.empty() || !move.wrap.empty() || !move.recentre.empty()) return std::nullopt;
  bool spanned = false;
  for (int i : move.flip) {
    if (guesses_[i].bias_held) return std::nullopt;  // its mirror is about its held zero
    const int j = guesses_[i].column;
    spanned |= only_tendons ? seenOnlyByTendons(model_, j) : seenByTendons(model_, j);
  }
  if (!spanned) return std::nullopt;
  // A flipped joint's own half turn is absorbed in its centre.
  MinimumMove centred = move;
  centred.flip_about_zero = false;
  centred.half_turn.clear();
  for (int i : move.half_turn)
    if (std::find(move.flip.begin(), move.flip.end(), i) == move.flip.end())
      centred.half_turn.push_back(i);
  // The frames with the jump's turns, then each flip about its centre in turn.
  MinimumMove turns = centred;
  turns.flip.clear();
  SensorParameters scratch = theta;
  RowMatrix moved = q;
  applyMove(model_.robot(), guesses_, turns, &scratch, &moved);
  for (int i : move.flip) {
    const int j = guesses_[i].column;
    const double c =
        tendonMirrorCentre(model_, theta, q, j, &moved).value_or(q.col(j).mean());
    centred.flip_centres.push_back(c);
    moved.col(j) = (2 * c - q.col(j).array()).matrix();
  }
  return centred;
}

std::vector<Estimate> WideBasin::signMoved(const Estimate& est,
                                           const std::vector<int>& move) const {
  std::vector<Estimate> out(1, est);
  for (int i : move) flipSign(guesses_[i], &out[0].theta, &out[0].state.q);
  // A joint only tendons see: also mirrored about where they are symmetric.
  if (std::optional<MinimumMove> centred =
          tendonCentred({move, {}, {}}, est.theta, subsampleAngles(est.state.q), true)) {
    out.push_back(est);
    applyMove(model_.robot(), guesses_, *centred, &out[1].theta, &out[1].state.q);
  }
  return out;
}

bool WideBasin::recheckSigns(Estimate* est) const {
  QState ss;
  ss.q = subsampleAngles(est->state.q);
  if (!someSensorMisfits(model_, withTendonsFitted(est->theta, sub_, ss), noise_, sub_, ss.q, 2.0,
                         kStartTendonMisfit))
    return false;
  bool flipped_any = false;
  double base = refinedCost(est->theta, ss);
  for (int sweep = 0; sweep < 2; ++sweep) {
    bool changed = false;
    for (const std::vector<int>& move : moves_) {
      if (touchesFixed(guesses_, move)) continue;
      // Moved on every frame, then scored on the subsample: a mirror is
      // about its column's mean, which the subsample's would shift (by
      // 0.05 rad on the basin test's hand, the refined costs then 4163
      // and 17170), so what is scored is what would be kept.
      for (Estimate& moved : signMoved(*est, move)) {
        QState st;
        st.q = subsampleAngles(moved.state.q);
        const double cost = refinedCost(moved.theta, st);
        if (!(cost < 0.8 * base)) continue;
        // Clearly better: keep it.
        *est = std::move(moved);
        base = cost;
        changed = flipped_any = true;
        break;
      }
    }
    if (!changed) break;
  }
  return flipped_any;
}

namespace {
// Per frame and joint of a motion: at the widened bound, beyond the URDF's limits.
struct LimitFrames {
  Eigen::Matrix<bool, Eigen::Dynamic, Eigen::Dynamic> at, beyond;
};

// Whether `move`, which took a motion with limit frames `before` to the
// angles `moved`, relieves the limits of the joints it turns (true angles
// never leave them): a whole turn or a recentring that leaves fewer frames
// at the widened bound, or a mirror image whose motion the URDF limits
// hold where a joint it turns left them in more than kEscapeShareAtLimit
// of the frames (panda/partial basin truth 6: the shoulder's mirror, joint
// 3 down to -3.25 against its -2.90, fitted as well as the truth, and
// reported ambiguous). Not a mirror that only shaves frames off a motion
// that noise carries past the limits.
bool relievesLimits(const RobotModel& robot, const std::vector<PotGuess>& guesses,
                    const MinimumMove& move, const LimitFrames& before, const RowMatrix& moved) {
  if (!move.whole_turn.empty() || !move.recentre.empty()) {
    const auto moved_at_limit = atWidenedLimit(robot, moved);
    for (const std::vector<int>* shifted : {&move.whole_turn, &move.recentre, &move.recentre_below})
      for (int i : *shifted) {
        const int j = guesses[i].column;
        if (moved_at_limit.col(j).count() < before.at.col(j).count()) return true;
      }
  }
  if (move.flip.empty() && move.half_turn.empty()) return false;
  const auto moved_beyond = beyondLimits(robot, moved);
  bool left = false, inside = true;
  for (const std::vector<int>* turned : {&move.flip, &move.half_turn})
    for (int i : *turned) {
      const int j = guesses[i].column;
      left |= often(static_cast<double>(before.beyond.col(j).count()),
                    static_cast<double>(moved.rows()), kEscapeShareAtLimit);
      inside &= moved_beyond.col(j).count() == 0;
    }
  return left && inside;
}
}  // namespace

void JumpChoice::consider(int index, double cost, double start, bool relieves) {
  if (cost < kBetterMinimum * base_) {
    better_.push_back({index, cost, start});
  } else if (relieves && cost <= (1 + as_well_) * base_) {
    within_.push_back({index, cost, start});
  }
}

int JumpChoice::chosen() const { return better_.empty() ? pick(within_) : pick(better_); }

int JumpChoice::pick(const std::vector<Scored>& jumps) {
  if (jumps.empty()) return -1;
  double lowest = jumps.front().cost;
  for (const Scored& j : jumps) lowest = std::min(lowest, j.cost);
  // Alike: within kSameRefinedFit of the lowest, so that no chain of jumps
  // each alike to the last drifts above it.
  const auto alike = [&](const Scored& j) { return j.cost <= (1 + kSameRefinedFit) * lowest; };
  double nearest = std::numeric_limits<double>::infinity();
  for (const Scored& j : jumps)
    if (alike(j)) nearest = std::min(nearest, j.start);  // a NaN start never counts
  for (const Scored& j : jumps)
    if (alike(j) && (j.start <= (1 + kSameStart) * nearest || !std::isfinite(nearest)))
      return j.index;
  return -1;  // unreachable: the lowest is alike
}

std::optional<MinimumMove> WideBasin::jumpToBetterMinimum(
    Estimate* est, const std::vector<int>& at_limits, bool world_turns_only) const {
  QState sub;
  sub.q = subsampleAngles(est->state.q);
  const double base = refinedCost(est->theta, sub, PotSteps::kInverseCharts);
  const RobotModel& robot = model_.robot();
  const LimitFrames limits{atWidenedLimit(robot, sub.q), beyondLimits(robot, sub.q)};
  // The joints whose motion the verdict would flag beyond their limits.
  const std::vector<int> flagged = jointsOftenBeyondLimits(
      model_, est->theta, noise_, loss_, sub_, sub.q, kSuspectShareAtLimit);
  JumpChoice choice(base, flagged.empty() ? kSameFit : kFlaggedSameFit);
  std::vector<MinimumMove> moves;  // those considered, in order
  const auto consider = [&](MinimumMove move) {
    SensorParameters theta = est->theta;
    QState moved = sub;
    moveTo(move, false, sub_, &theta, &moved);
    const bool relieves = relievesLimits(robot, guesses_, move, limits, moved.q);
    const double start =
        totalCost(model_, theta, noise_, loss_, sub_, FrameOptions(), threads_, ws_, &moved);
    const double cost = refinedCost(std::move(theta), std::move(moved), PotSteps::kInverseCharts);
    moves.push_back(std::move(move));
    choice.consider(static_cast<int>(moves.size()) - 1, cost, start, relieves);
    return cost;
  };
  std::vector<bool> through(model_.dof(), false);
  for (int j : at_limits) through[j] = true;
  std::vector<MinimumMove> listed;
  if (!world_turns_only) {
    listed = minimumMoves(robot, guesses_, moves_, &through);
    for (MinimumMove& move : wholeTurnMoves(robot, guesses_, sub.q)) listed.push_back(std::move(move));
    for (MinimumMove& move : wrapMoves(robot, guesses_, sub.q)) listed.push_back(std::move(move));
    // A jump that flips a joint only tendons see, also about where they are
    // symmetric (tendonCentred).
    for (size_t m = 0, n = listed.size(); m < n; ++m)
      if (std::optional<MinimumMove> centred = tendonCentred(listed[m], est->theta, sub.q, true))
        listed.push_back(std::move(*centred));
    // Placed back wherever the verdict would flag the motion beyond the limits.
    for (MinimumMove& move : recentreMoves(robot, guesses_, sub.q, flagged))
      listed.push_back(std::move(move));
  }
  if (marker_group_free_)
    for (MinimumMove& move : worldTurnMoves(model_, guesses_, est->theta))
      listed.push_back(std::move(move));
  std::vector<double> cost(listed.size());
  for (size_t m = 0; m < listed.size(); ++m) cost[m] = consider(listed[m]);
  // A wrist or shoulder flip is exact about the mirrored joints' zeros (or
  // kπ, flipAboutTurns); its sign move about the motion's mean is not, and
  // refined from there may not reach the exact one. Where no move helped,
  // the exact ones are tried (panda/partial basin truth 8: the shoulder's
  // mirror, joint 1 beyond its limit in 108 of 600 frames; the move back
  // about the mean refined to 0.7% worse and the run ended reported
  // ambiguous). Only for a near miss, or a flip through a joint at or
  // beyond its limits, a mirror's mark: about the mean, a short flip that
  // refined to far worse is no way to the exact one (humanoid38 with σ 2.5x
  // too small, no joint at its limits: 7 of 61 flips within kNearMiss, the
  // rest 13 s of refinements), but a long one can be (the unseen Z1's arm
  // mirror over the top refined to 44x the cost about the mean, 0.997x
  // exact).
  int chosen = choice.chosen();
  if (chosen < 0) {
    for (size_t m = 0; m < listed.size(); ++m) {
      MinimumMove move = listed[m];
      if (!move.flip.empty() && !move.half_turn.empty() && !move.flip_about_zero &&
          (cost[m] <= kNearMiss * base || turnsAny(guesses_, move, through))) {
        move.flip_about_zero = true;
        consider(std::move(move));
      }
    }
    chosen = choice.chosen();
  }
  if (chosen < 0) return std::nullopt;
  moveTo(moves[chosen], false, obs_, &est->theta, &est->state);
  return moves[chosen];
}

void WideBasin::moveTo(const MinimumMove& move, bool mirror_about_zero, const Observations& obs,
                       SensorParameters* theta, QState* state) const {
  // A wrap gathers where the markers put each frame (they see the joint
  // modulo a turn); the angles the pots' maps put there are what is wrong.
  if (!move.wrap.empty()) {
    QPhaseOptions markers = free_only_;
    markers.max_steps = 10;
    markers.frozen.assign(model_.dof(), true);
    for (int i : move.wrap) markers.frozen[guesses_[i].column] = false;
    // From the same fresh damping in every frame: the jump is judged on the
    // subsample, whose frames carry none, and a full log's damping carried
    // from its last iterations took ur5's wrist (partial swings, basin
    // truth 4) elsewhere in 10 steps, the turn then cut inside its motion.
    state->lambda.resize(0);
    qPhase(model_, *theta, noise_, loss_, obs, markers, ws_, state);
  }
  applyMove(model_.robot(), guesses_, move, theta, &state->q, mirror_about_zero);
  if ((move.flip_about_zero || move.world_turn) && marker_group_free_)
    initialiseMarkerGroup(model_, obs, *state, 3, threads_, ws_, theta);
  if (!move.wrap.empty() || !move.recentre.empty()) {
    ThetaPhaseOptions to;
    to.threads = threads_;
    thetaPhase(model_, noise_, loss_, obs, *state, to, ws_, theta);
  }
}

namespace {
// Whether the columns a move turns stay within [lower, upper].
bool withinLimits(const std::vector<PotGuess>& guesses, const MinimumMove& move,
                  const RowMatrix& q, const Eigen::VectorXd& lower, const Eigen::VectorXd& upper) {
  for (const std::vector<int>* moved : {&move.flip, &move.half_turn})
    for (int i : *moved) {
      const int j = guesses[i].column;
      if (q.col(j).minCoeff() < lower[j] || q.col(j).maxCoeff() > upper[j]) return false;
    }
  return true;
}

// Whether a and b put every frame's joints at the same angles, modulo whole
// turns, to the precision of the mirror centres' solve (a nearly exact
// mirror's centres, mirror_centres.cpp, are a least mismatch's, solved
// apart for a flip and its variant over the top).
bool sameTurns(const RowMatrix& a, const RowMatrix& b) {
  const auto offTurns = [](double d) { return std::abs(std::remainder(d, 2 * M_PI)); };
  return (a - b).unaryExpr(offTurns).maxCoeff() < 1e-6;
}
}  // namespace

std::vector<WideBasin::EquivalentMove> WideBasin::equivalentMoves(
    const Estimate& est, SensorParameters* refitted, double* refitted_cost) const {
  Eigen::VectorXd lower, upper;
  widenedLimits(model_.robot(), &lower, &upper);
  ThetaPhaseOptions to;
  to.threads = threads_;
  // The cost with θ re-fitted in closed form at the angles of `state`.
  auto refitCost = [&](SensorParameters* theta, QState state) {
    thetaPhase(model_, noise_, loss_, sub_, state, to, ws_, theta);
    return totalCost(model_, *theta, noise_, loss_, sub_, FrameOptions(), threads_, ws_, &state);
  };
  QState sub;
  sub.q = subsampleAngles(est.state.q);
  SensorParameters base_theta = est.theta;
  const double base = refitCost(&base_theta, sub);
  // est refined as the jumps are, once one is near enough to be refined.
  SensorParameters refined_base = est.theta;
  double refined_base_cost = -1;
  std::vector<EquivalentMove> out;
  // The angles each listed move put the frames at: about the kinematics'
  // exact centres (exactMirrorCentres), a flip and its variant over the top
  // can land on the same configuration, listed once.
  std::vector<RowMatrix> listed;
  // Returns the move's cost with θ re-fitted in closed form (+inf where it
  // leaves the limits or repeats a listed move); refined and listed only
  // where that is below kNearMirror times est's and `must_beat`.
  const auto tryMove = [&](const MinimumMove& move, double must_beat) {
    const double skipped = std::numeric_limits<double>::infinity();
    SensorParameters theta = est.theta;
    QState moved = sub;
    moveTo(move, true, sub_, &theta, &moved);
    if (!withinLimits(guesses_, move, moved.q, lower, upper)) return skipped;
    if (std::any_of(listed.begin(), listed.end(),
                    [&](const RowMatrix& q) { return sameTurns(q, moved.q); }))
      return skipped;
    const double refit = refitCost(&theta, moved);
    if (!(refit <= kNearMirror * base && refit < must_beat)) return refit;
    if (refined_base_cost < 0) {
      QState state = sub;
      refined_base_cost = refine(&refined_base, &state);
    }
    const RowMatrix moved_q = moved.q;
    const double refined = refine(&theta, &moved);
    if (refined <= (1 + kSameFit) * refined_base_cost) {
      out.push_back({move, std::move(theta), refined});
      listed.push_back(moved_q);
    }
    return refit;
  };
  for (const MinimumMove& move : minimumMoves(model_.robot(), guesses_, moves_)) {
    const double refit = tryMove(move, std::numeric_limits<double>::infinity());
    // A jump of one flip also about where the tendons over its joint are
    // symmetric: exact for them where the markers' centres are not (a
    // marker on the flipped link alone, re-fitted, takes any centre). Only
    // where that fits better in closed form: where the markers set the
    // centre, it fits worse and is not refined. (Not a chain's several
    // flips: their centres cost a search each in every one of the hand's
    // many chain flips, 20% of its calibration, for none exact.)
    if (move.flip.size() != 1) continue;
    if (std::optional<MinimumMove> centred = tendonCentred(move, est.theta, sub.q, false))
      tryMove(*centred, refit);
  }
  // The world's half turns with a limb's first joint: exact for the
  // markers, told apart (if at all) by the tendons and the limits alone.
  if (marker_group_free_)
    for (const MinimumMove& move : worldTurnMoves(model_, guesses_, est.theta))
      tryMove(move, std::numeric_limits<double>::infinity());
  if (refitted) *refitted = refined_base_cost < 0 ? base_theta : refined_base;
  if (refitted_cost) *refitted_cost = refined_base_cost < 0 ? base : refined_base_cost;
  return out;
}

std::optional<MinimumMove> WideBasin::jumpToBetterEquivalent(
    Estimate* est, std::vector<EquivalentMove>* same, SensorParameters* refitted) const {
  double base = 0;
  *same = equivalentMoves(*est, refitted, &base);
  const EquivalentMove* best = nullptr;
  for (const EquivalentMove& m : *same)
    if (m.cost < (1 - kBetterEquivalent) * base && (!best || m.cost < best->cost)) best = &m;
  if (!best) return std::nullopt;
  // About the kinematics' exact centres, as the listing moved it.
  moveTo(best->move, true, obs_, &est->theta, &est->state);
  return best->move;
}

// The pots' maps adopted, the marker group in closed form, then the
// marker-led alternation and its sign re-check.
Estimate WideBasin::estimateFrom(const Candidate* maps, QState state) const {
  Estimate est;
  est.theta = seed_;
  est.state = std::move(state);
  if (maps) adoptPotMaps(*maps, &est);
  if (marker_group_free_)
    initialiseMarkerGroup(model_, obs_, est.state, 3, threads_, ws_, &est.theta);
  if (maps && marker_group_free_) alternate(kInitPotWeight, 1e-3, &est);
  alternate(potWeight(), 1e-3, &est);
  if (marker_group_free_ && !moves_.empty() && recheckSigns(&est))
    alternate(potWeight(), 1e-4, &est);
  return est;
}

RowMatrix WideBasin::subsampleAngles(const RowMatrix& q) const {
  RowMatrix out(sub_.num_frames, model_.dof());
  for (int i = 0; i < sub_.num_frames; ++i) out.row(i) = q.row(sub_frames_[i]);
  return out;
}

SensorParameters WideBasin::withTendonsFitted(SensorParameters theta, const Observations& obs,
                                              const QState& state) const {
  ThetaPhaseOptions tendons;
  tendons.threads = threads_;
  tendons.update[0] = tendons.update[1] = false;
  if (!model_.sensors().tendon_sensors.empty())
    thetaPhase(model_, noise_, loss_, obs, state, tendons, ws_, &theta);
  return theta;
}

// The whole cost at est, the tendons (not initialised yet) fitted to its q
// first: two estimates whose markers and pots fit alike can differ there.
double WideBasin::fullCost(const Estimate& est) const {
  QState state = est.state;
  return totalCost(model_, withTendonsFitted(est.theta, obs_, state), noise_, loss_, obs_,
                   FrameOptions(), threads_, ws_, &state);
}

std::optional<Estimate> WideBasin::treeOrderEstimate(const QState& neutral) const {
  // Only where a marker or the mocap frame is held: with every part free,
  // mirror images of the whole fit can be equally good, and a fit cannot
  // choose between them.
  if (!marker_group_free_ || guesses_.empty() || !gaugeHeld(model_.sensors())) return std::nullopt;
  const auto tree = treeOrderMaps(model_, sub_, loss_, guesses_, seed_, threads_);
  if (!tree) return std::nullopt;
  return estimateFrom(&*tree, neutral);
}

SensorParameters WideBasin::finish(Estimate est, QState* state) const {
  ThetaPhaseOptions pots;
  pots.threads = threads_;
  pots.update[0] = false;
  thetaPhase(model_, noise_, loss_, obs_, est.state, pots, ws_, &est.theta);
  *state = std::move(est.state);
  return est.theta;
}

SensorParameters WideBasin::run(QState* state) const {
  const QState neutral = *state;
  const Candidate searched = guesses_.empty() ? Candidate() : searchPotMaps();
  Estimate est = estimateFrom(guesses_.empty() ? nullptr : &searched, std::move(*state));
  // A marker or pot still far off its noise: the sweeps' start (swings
  // about each range's middle) may have been wrong. The tree-order search
  // assumes nothing about the swings; its estimate replaces the first if
  // every sensor then fits clearly better (a mirror image that fits about
  // as well is no reason to leave the sweeps' answer). (Markers and pots:
  // the tree-order search fits nothing else, and a tendon's misfit is the
  // sign re-check's.)
  if (someSensorMisfits(model_, est.theta, noise_, sub_, subsampleAngles(est.state.q),
                        kRestartMisfit, 0.0))
    if (std::optional<Estimate> alt = treeOrderEstimate(neutral))
      if (fullCost(*alt) < kClearlyBetter * fullCost(est)) est = std::move(*alt);
  return finish(std::move(est), state);
}

std::optional<SensorParameters> WideBasin::runTreeOrder(QState* state) const {
  std::optional<Estimate> est = treeOrderEstimate(*state);
  if (!est) return std::nullopt;
  return finish(std::move(*est), state);
}

SensorParameters wideBasinInitialisation(const MeasurementModel& model, const Observations& obs,
                                         const NoiseModel& noise, const RobustLoss& loss,
                                         int threads, std::vector<FrameWorkspace>* ws,
                                         SensorParameters theta, QState* state,
                                         bool coupled_steps) {
  return WideBasin(model, obs, noise, loss, threads, ws, theta, coupled_steps).run(state);
}

}  // namespace stac
