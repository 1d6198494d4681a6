// Wide-basin initialisation (see calibrate.cpp's header comment): pots'
// readings mapped onto their joint ranges with signs chosen by the markers,
// closed-form mocap frame and markers, then a marker-led alternation.
#include "methods/wide_basin.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "stac/calibrate.hpp"
#include "stac/kinematics.hpp"
#include "solve/schur.hpp"
#include "solve/theta_phase.hpp"

namespace stac {
namespace {

// Global scales of the guessed maps below: the log covers 80%, 40%, 20% or
// 10% of the joints' ranges.
constexpr double kCoverageScales[] = {1.0, 0.5, 0.25, 0.125};
// The pots' weight in the first marker-led alternation (σ x 10): their
// guessed maps' scales are rough, so the markers lead q and the pots'
// θ-phase fits gains to marker-driven angles rather than to themselves.
constexpr double kInitPotWeight = 0.01;
// Frames of the candidate search and of the coupled re-check.
constexpr int kSearchFrames = 150;

bool hasFreeMarkerGroup(const SensorSet& sensors) {
  return !sensors.markers.empty() &&
         (!sensors.mocap_frame_fixed ||
          std::any_of(sensors.markers.begin(), sensors.markers.end(),
                      [](const MarkerConfig& m) { return !m.fixed; }));
}

// The search scores by the markers alone.
FrameOptions markersOnly() {
  FrameOptions eval;
  eval.group_weight[1] = eval.group_weight[2] = 0.0;
  return eval;
}

double median(std::vector<double>* v) {
  std::nth_element(v->begin(), v->begin() + v->size() / 2, v->end());
  return (*v)[v->size() / 2];
}

}  // namespace

// ---- Pot guesses and candidates ----

std::vector<PotGuess> makePotGuesses(const RobotModel& robot, const SensorSet& sensors,
                                     const SensorParameters& theta, const Observations& obs) {
  std::vector<PotGuess> out;
  std::vector<bool> covered(robot.dof(), false);
  for (size_t s = 0; s < sensors.joint_sensors.size(); ++s) {
    const JointSensorConfig& sc = sensors.joint_sensors[s];
    const MovableJoint& mj = robot.movableJoints()[sc.joint];
    if (mj.is_mimic || covered[mj.q_index]) continue;
    double lo = robot.lowerLimits()[mj.q_index], hi = robot.upperLimits()[mj.q_index];
    if (!std::isfinite(lo) || !std::isfinite(hi)) lo = -M_PI, hi = M_PI;
    double pmin = INFINITY, pmax = -INFINITY, sum = 0;
    int n = 0;
    for (int t = 0; t < obs.num_frames; ++t) {
      const double p = obs.joint(t, s);
      if (std::isnan(p)) continue;
      pmin = std::min(pmin, p), pmax = std::max(pmax, p), sum += p, ++n;
    }
    if (n < 2) continue;
    PotGuess g;
    g.sensor = static_cast<int>(s);
    g.column = mj.q_index;
    g.fixed = sc.fixed;
    g.mean = sum / n;
    g.map.mid = 0.5 * (lo + hi);
    if (sc.fixed) {
      // Known calibration: the exact inverse.
      const GainBias& gb = theta.joint_sensor[s];
      if (gb.gain == 0) continue;
      g.map.alpha = 1.0 / gb.gain;
      g.map.mid = (g.mean - gb.bias) / gb.gain;
    } else {
      if (!(pmax > pmin)) continue;
      g.map.alpha = 0.8 * (hi - lo) / (pmax - pmin);
    }
    covered[mj.q_index] = true;
    out.push_back(g);
  }
  return out;
}

Candidate guessedMaps(const std::vector<PotGuess>& guesses) {
  Candidate c;
  for (const PotGuess& g : guesses) c.maps.push_back(g.map);
  return c;
}

void applyCandidate(const std::vector<PotGuess>& guesses, const Candidate& candidate,
                    const Observations& obs, RowMatrix* q) {
  for (size_t i = 0; i < guesses.size(); ++i) {
    const PotGuess& g = guesses[i];
    const PotMap& map = candidate.maps[i];
    double last = map.mid;
    for (int t = 0; t < obs.num_frames; ++t) {
      const double p = obs.joint(t, g.sensor);
      if (!std::isnan(p)) last = map.alpha * (p - g.mean) + map.mid;
      (*q)(t, g.column) = last;
    }
  }
}

Candidate withSigns(const Candidate& c, const std::vector<PotGuess>& guesses,
                    const std::vector<bool>& flip) {
  Candidate out = c;
  for (size_t i = 0; i < guesses.size(); ++i)
    if (flip[i] && !guesses[i].fixed) out.maps[i].alpha = -out.maps[i].alpha;
  return out;
}

Candidate scaled(const Candidate& c, const std::vector<PotGuess>& guesses, double s) {
  Candidate out = c;
  for (size_t i = 0; i < guesses.size(); ++i)
    if (!guesses[i].fixed) out.maps[i].alpha *= s;
  return out;
}

Candidate seededMaps(const Candidate& c, const std::vector<PotGuess>& guesses,
                     const SensorParameters& seed) {
  // A fixed guess's map is this inverse already.
  Candidate out = c;
  for (size_t i = 0; i < guesses.size(); ++i) {
    const GainBias& gb = seed.joint_sensor[guesses[i].sensor];
    if (gb.gain == 0 || !std::isfinite(gb.gain)) continue;
    out.maps[i].alpha = 1.0 / gb.gain;
    out.maps[i].mid = (guesses[i].mean - gb.bias) / gb.gain;
  }
  return out;
}

Candidate flipped(const Candidate& c, const std::vector<int>& move) {
  Candidate out = c;
  for (int i : move) out.maps[i].alpha = -out.maps[i].alpha;
  return out;
}

bool touchesFixed(const std::vector<PotGuess>& guesses, const std::vector<int>& move) {
  return std::any_of(move.begin(), move.end(), [&](int i) { return guesses[i].fixed; });
}

Candidate rescaled(const Candidate& c, int i, double s) {
  Candidate out = c;
  out.maps[i].alpha *= s;
  return out;
}

std::vector<std::vector<bool>> mirrorPatterns(const RobotModel& robot,
                                              const std::vector<PotGuess>& guesses) {
  KinematicsWorkspace kin(robot);
  forwardKinematics(robot, neutralPose(robot), &kin);
  std::vector<std::vector<bool>> patterns(4, std::vector<bool>(guesses.size(), true));
  for (size_t i = 0; i < guesses.size(); ++i) {
    const Eigen::Vector3d u = kin.joint_axis[robot.qJoints()[guesses[i].column]].normalized();
    for (int a = 0; a < 3; ++a) patterns[1 + a][i] = std::abs(u[a]) < 0.7;
  }
  return patterns;
}

// Two wrong signs in a row (e.g. a wrist's pitch and roll) can each look
// right alone, since flipping either one by itself moves the markers
// farther: hence the pairs.
std::vector<std::vector<int>> signMoves(const RobotModel& robot,
                                        const std::vector<PotGuess>& guesses) {
  std::vector<std::vector<int>> moves;
  std::vector<int> guess_of_q(robot.dof(), -1);
  for (size_t i = 0; i < guesses.size(); ++i) guess_of_q[guesses[i].column] = static_cast<int>(i);
  for (size_t i = 0; i < guesses.size(); ++i) moves.push_back({static_cast<int>(i)});
  for (size_t i = 0; i < guesses.size(); ++i) {
    const int movable = robot.qJoints()[guesses[i].column];
    const std::vector<int>& chain =
        robot.supportingJoints(robot.movableJoints()[movable].child_link);
    for (int k = static_cast<int>(chain.size()) - 2; k >= 0; --k) {
      const MovableJoint& above = robot.movableJoints()[chain[k]];
      if (above.is_mimic || guess_of_q[above.q_index] < 0) continue;
      moves.push_back({guess_of_q[above.q_index], static_cast<int>(i)});
      break;
    }
  }
  return moves;
}

// p = g q + b = (-g) (2c - q) + (b + 2 g c).
void flipSign(const PotGuess& g, SensorParameters* theta, RowMatrix* q) {
  const double c = q->col(g.column).mean();
  q->col(g.column) = (2.0 * c - q->col(g.column).array()).matrix();
  GainBias& gb = theta->joint_sensor[g.sensor];
  gb.bias += 2.0 * gb.gain * c;
  gb.gain = -gb.gain;
}

// Misfit: a median residual over the frames more than twice what Gaussian
// noise of the sensor's σ gives (a marker's Euclidean distance: 1.54 σ; a
// pot: 0.67 σ). Medians, so that gross outliers do not count: a sign chosen
// wrong shows in every frame.
bool someSensorMisfits(const MeasurementModel& model, const SensorParameters& theta,
                       const NoiseModel& noise, const Observations& obs, const RowMatrix& q) {
  const SensorSet& sensors = model.sensors();
  const int M = static_cast<int>(sensors.markers.size());
  const int J = static_cast<int>(sensors.joint_sensors.size());
  const int N = static_cast<int>(sensors.tendon_sensors.size());
  std::vector<std::vector<double>> marker(M), joint(J);
  KinematicsWorkspace kin(model.robot());
  std::vector<double> pm(3 * M), pj(J), pt(N);
  for (int t = 0; t < obs.num_frames; ++t) {
    predictFrame(model, theta, q.row(t).transpose(), &kin, pm.data(), pj.data(), pt.data());
    for (int m = 0; m < M; ++m) {
      const Eigen::Vector3d x(obs.marker(t, 3 * m), obs.marker(t, 3 * m + 1),
                              obs.marker(t, 3 * m + 2));
      if (x.allFinite())
        marker[m].push_back((x - Eigen::Vector3d(pm[3 * m], pm[3 * m + 1], pm[3 * m + 2])).norm());
    }
    for (int j = 0; j < J; ++j)
      if (!std::isnan(obs.joint(t, j))) joint[j].push_back(std::abs(obs.joint(t, j) - pj[j]));
  }
  for (int m = 0; m < M; ++m)
    if (!marker[m].empty() && median(&marker[m]) > 2.0 * 1.54 * noise.marker[m]) return true;
  for (int j = 0; j < J; ++j)
    if (!joint[j].empty() && median(&joint[j]) > 2.0 * 0.674 * noise.joint[j]) return true;
  return false;
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
      guesses_(makePotGuesses(model.robot(), model.sensors(), seed, obs)),
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
  applyCandidate(guesses_, c, obs_, &est->state.q);
  for (size_t i = 0; i < guesses_.size(); ++i) {
    const PotGuess& g = guesses_[i];
    if (g.fixed) continue;
    GainBias& gb = est->theta.joint_sensor[g.sensor];
    gb.gain = 1.0 / c.maps[i].alpha;
    gb.bias = g.mean - c.maps[i].mid / c.maps[i].alpha;
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
                      &est->theta, &est->state, qo.eval, true);
    if (prev > 0 && std::abs(prev - c) <= tol * prev) break;
    prev = c;
  }
}

// A candidate's worth: the cost after a few alternations on the subsample.
double WideBasin::refinedCost(SensorParameters th, QState st) const {
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
  for (int it = 0; it < 5; ++it)
    c = coupledStep(model_, noise_, loss_, sub_, threads_, ws_, &lambda, &th, &st, qo.eval, true);
  return c;
}

// After the initial alternation: if a marker or pot still fits far worse
// than its noise, the likeliest cause is a pot whose sign the marker-only
// scoring above got wrong (a joint that moves its markers little, e.g. a
// wrist with markers close to its axes). Each sign move, tried on the
// subsample from the current estimate and refined by a few alternations,
// is kept if it lowers the cost clearly.
bool WideBasin::recheckSigns(Estimate* est) const {
  QState ss;
  ss.q = RowMatrix(sub_.num_frames, model_.dof());
  for (int i = 0; i < sub_.num_frames; ++i) ss.q.row(i) = est->state.q.row(sub_frames_[i]);
  if (!someSensorMisfits(model_, est->theta, noise_, sub_, ss.q)) return false;
  bool flipped_any = false;
  double base = refinedCost(est->theta, ss);
  for (int sweep = 0; sweep < 2; ++sweep) {
    bool changed = false;
    for (const std::vector<int>& move : moves_) {
      if (touchesFixed(guesses_, move)) continue;
      SensorParameters th = est->theta;
      QState st = ss;
      for (int i : move) flipSign(guesses_[i], &th, &st.q);
      if (!(refinedCost(th, st) < 0.8 * base)) continue;
      // Clearly better: keep it, on every frame.
      for (int i : move) flipSign(guesses_[i], &est->theta, &est->state.q);
      for (int i = 0; i < sub_.num_frames; ++i) ss.q.row(i) = est->state.q.row(sub_frames_[i]);
      base = refinedCost(est->theta, ss);
      changed = flipped_any = true;
    }
    if (!changed) break;
  }
  return flipped_any;
}

SensorParameters WideBasin::run(QState* state) const {
  Estimate est;
  est.theta = seed_;
  est.state = std::move(*state);
  if (!guesses_.empty()) adoptPotMaps(searchPotMaps(), &est);
  if (marker_group_free_)
    initialiseMarkerGroup(model_, obs_, est.state, 3, threads_, ws_, &est.theta);
  if (!guesses_.empty() && marker_group_free_) alternate(kInitPotWeight, 1e-3, &est);
  alternate(potWeight(), 1e-3, &est);
  if (marker_group_free_ && !moves_.empty() && recheckSigns(&est))
    alternate(potWeight(), 1e-4, &est);
  ThetaPhaseOptions pots;
  pots.threads = threads_;
  pots.update[0] = false;
  thetaPhase(model_, noise_, loss_, obs_, est.state, pots, ws_, &est.theta);
  *state = std::move(est.state);
  return est.theta;
}

SensorParameters wideBasinInitialisation(const MeasurementModel& model, const Observations& obs,
                                         const NoiseModel& noise, const RobustLoss& loss,
                                         int threads, std::vector<FrameWorkspace>* ws,
                                         SensorParameters theta, QState* state,
                                         bool coupled_steps) {
  return WideBasin(model, obs, noise, loss, threads, ws, theta, coupled_steps).run(state);
}

}  // namespace stac
