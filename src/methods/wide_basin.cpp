// Wide-basin initialisation (see calibrate.cpp's header comment): pots'
// readings mapped onto their joint ranges with signs chosen by the markers,
// closed-form mocap frame and markers, then a marker-led alternation.
#include "methods/wide_basin.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "stac/calibrate.hpp"
#include "stac/kinematics.hpp"
#include "stac/schur.hpp"
#include "stac/theta_phase.hpp"

namespace stac {
namespace {

// Global scales of the guessed maps below: the log covers 80%, 40%, 20% or
// 10% of the joints' ranges.
constexpr double kCoverageScales[] = {1.0, 0.5, 0.25, 0.125};
// The pots' weight in the first marker-led alternation (σ x 10): their
// guessed maps' scales are rough, so the markers lead q and the pots'
// θ-phase fits gains to marker-driven angles rather than to themselves.
constexpr double kInitPotWeight = 0.01;

// The joint angle a one-joint sensor implies if the log spans 80% of the
// joint's range: q = alpha (p - mean p) + mid. Such a guess has the right
// time course; alpha's sign and scale are unknown, and greedy sweeps pick
// each by how well the markers then fit.
struct PotGuess {
  int sensor = -1;   // joint sensor index
  int column = -1;   // q index
  double alpha = 0, mean = 0, mid = 0;
};

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
    g.mean = sum / n;
    g.mid = 0.5 * (lo + hi);
    if (sc.fixed) {
      // Known calibration: the exact inverse.
      const GainBias& gb = theta.joint_sensor[s];
      if (gb.gain == 0) continue;
      g.alpha = 1.0 / gb.gain;
      g.mid = (g.mean - gb.bias) / gb.gain;
    } else {
      if (!(pmax > pmin)) continue;
      g.alpha = 0.8 * (hi - lo) / (pmax - pmin);
    }
    covered[mj.q_index] = true;
    out.push_back(g);
  }
  return out;
}

void applyPotGuesses(const std::vector<PotGuess>& guesses, const Observations& obs,
                     RowMatrix* q) {
  for (const PotGuess& g : guesses) {
    double last = g.mid;
    for (int t = 0; t < obs.num_frames; ++t) {
      const double p = obs.joint(t, g.sensor);
      if (!std::isnan(p)) last = g.alpha * (p - g.mean) + g.mid;
      (*q)(t, g.column) = last;
    }
  }
}

// Mirrors joint angle column `g.column` about its mean and flips the sign
// of its pot's map so that every prediction stays the same:
// p = g q + b = (-g) (2c - q) + (b + 2 g c).
void flipSign(const PotGuess& g, SensorParameters* theta, RowMatrix* q) {
  const double c = q->col(g.column).mean();
  q->col(g.column) = (2.0 * c - q->col(g.column).array()).matrix();
  GainBias& gb = theta->joint_sensor[g.sensor];
  gb.bias += 2.0 * gb.gain * c;
  gb.gain = -gb.gain;
}

// Whether some marker or pot fits clearly worse than its noise: its median
// residual over the frames more than twice what Gaussian noise of its σ
// gives (a marker's Euclidean distance: 1.54 σ; a pot: 0.67 σ). Medians, so
// that gross outliers do not count: a sign chosen wrong shows in every
// frame.
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
      const Eigen::Vector3d x(obs.marker(t, 3 * m), obs.marker(t, 3 * m + 1), obs.marker(t, 3 * m + 2));
      if (x.allFinite())
        marker[m].push_back((x - Eigen::Vector3d(pm[3 * m], pm[3 * m + 1], pm[3 * m + 2])).norm());
    }
    for (int j = 0; j < J; ++j)
      if (!std::isnan(obs.joint(t, j))) joint[j].push_back(std::abs(obs.joint(t, j) - pj[j]));
  }
  auto median = [](std::vector<double>* v) {
    std::nth_element(v->begin(), v->begin() + v->size() / 2, v->end());
    return (*v)[v->size() / 2];
  };
  for (int m = 0; m < M; ++m)
    if (!marker[m].empty() && median(&marker[m]) > 2.0 * 1.54 * noise.marker[m]) return true;
  for (int j = 0; j < J; ++j)
    if (!joint[j].empty() && median(&joint[j]) > 2.0 * 0.674 * noise.joint[j]) return true;
  return false;
}

// After the initial alternation: if a marker or pot still fits far worse
// than its noise, the likeliest cause is a pot whose sign the marker-only
// scoring above got wrong (a joint that moves its markers little, e.g. a
// wrist with markers close to its axes). Each sign change of `moves`, tried
// on 150 frames from the current estimate and refined by a few alternations,
// is kept if it lowers the cost clearly. Returns whether any was kept.
bool verifySigns(const MeasurementModel& model, const Observations& obs, const NoiseModel& noise,
                 const RobustLoss& loss, int threads, std::vector<FrameWorkspace>* ws,
                 const std::vector<PotGuess>& guesses,
                 const std::vector<std::vector<int>>& moves, SensorParameters* theta,
                 QState* state) {
  const std::vector<int> sub = spreadFrames(obs.num_frames, 150);
  const Observations so = selectFrames(obs, sub);
  QState ss;
  ss.q = RowMatrix(so.num_frames, model.dof());
  for (int i = 0; i < so.num_frames; ++i) ss.q.row(i) = state->q.row(sub[i]);
  if (!someSensorMisfits(model, *theta, noise, so, ss.q)) return false;

  // A candidate's worth: the cost after a few alternations on the subsample.
  QPhaseOptions qo;
  qo.method = QPhaseMethod::kLmIter;
  qo.threads = threads;
  ThetaPhaseOptions to;
  to.threads = threads;
  auto refined = [&](SensorParameters th, QState st) {
    double c = 0;
    for (int it = 0; it < 2; ++it) {
      c = qPhase(model, th, noise, loss, so, qo, ws, &st);
      thetaPhase(model, noise, loss, so, st, to, ws, &th);
    }
    // Coupled steps converge in a few iterations where the alternation crawls.
    double lambda = 1e-3;
    for (int it = 0; it < 5; ++it)
      c = coupledStep(model, noise, loss, so, threads, ws, &lambda, &th, &st, qo.eval, true);
    return c;
  };
  bool flipped = false;
  double base = refined(*theta, ss);
  for (int sweep = 0; sweep < 2; ++sweep) {
    bool changed = false;
    for (const std::vector<int>& move : moves) {
      if (std::any_of(move.begin(), move.end(), [&](int i) {
            return model.sensors().joint_sensors[guesses[i].sensor].fixed;
          }))
        continue;
      SensorParameters th = *theta;
      QState st = ss;
      for (int i : move) flipSign(guesses[i], &th, &st.q);
      const double c = refined(th, st);
      if (c < 0.8 * base) {
        // Clearly better: keep it, on every frame.
        for (int i : move) flipSign(guesses[i], theta, &state->q);
        for (int i = 0; i < so.num_frames; ++i) ss.q.row(i) = state->q.row(sub[i]);
        base = refined(*theta, ss);
        changed = flipped = true;
      }
    }
    if (!changed) break;
  }
  return flipped;
}

}  // namespace

SensorParameters wideBasinInitialisation(const MeasurementModel& model, const Observations& obs,
                                         const NoiseModel& noise, const RobustLoss& loss,
                                         int threads, std::vector<FrameWorkspace>* ws_ptr,
                                         SensorParameters theta, QState* state,
                                         bool coupled_steps) {
  const RobotModel& robot = model.robot();
  const SensorSet& sensors = model.sensors();
  const bool marker_group_free =
      !sensors.markers.empty() && (!sensors.mocap_frame_fixed ||
                      std::any_of(sensors.markers.begin(), sensors.markers.end(),
                                  [](const MarkerConfig& m) { return !m.fixed; }));
  std::vector<PotGuess> guesses = makePotGuesses(robot, sensors, theta, obs);
  std::vector<std::vector<int>> moves;  // sign changes tried: guess indices
  {
    QPhaseOptions qo;
    qo.method = QPhaseMethod::kLmIter;
    qo.threads = threads;
    qo.eval.group_weight[1] = qo.eval.group_weight[2] = 0.0;
    ThetaPhaseOptions to;
    to.threads = threads;
    to.update[1] = to.update[2] = false;
    if (!guesses.empty()) {
      // Pick each guess's sign on a subsample of frames.
      const Observations so = selectFrames(obs, spreadFrames(obs.num_frames, 150));
      QState ss;
      ss.q = neutralPose(robot).transpose().replicate(so.num_frames, 1);
      // A candidate's score: how well the markers fit once the mocap frame
      // and markers are re-solved in closed form and the joints no pot
      // covers (gimbals driven by linear pots, say) follow the markers.
      QPhaseOptions free_only = qo;
      free_only.method = QPhaseMethod::kLmBatch;
      free_only.max_steps = 4;
      free_only.step_tolerance = 1e-6;  // a score, not a fit
      free_only.frozen.assign(robot.dof(), false);
      bool any_free = false;
      for (const PotGuess& g : guesses) free_only.frozen[g.column] = true;
      for (int j = 0; j < robot.dof(); ++j) any_free |= !free_only.frozen[j];
      // The free joints start where the best candidate so far left them:
      // one sign or scale change moves them little, so a few LM steps
      // re-converge them.
      RowMatrix warm_q = ss.q;
      auto markerCost = [&](SensorParameters* th) {
        ss.q = warm_q;
        applyPotGuesses(guesses, so, &ss.q);
        if (marker_group_free) {
          initialiseMarkerGroup(model, so, ss, 2, threads, ws_ptr, th);
          thetaPhase(model, noise, loss, so, ss, to, ws_ptr, th);
        }
        if (any_free) qPhase(model, *th, noise, loss, so, free_only, ws_ptr, &ss);
        return totalCost(model, *th, noise, loss, so, qo.eval, threads, ws_ptr, &ss);
      };
      SensorParameters th = theta;
      double best = markerCost(&th);
      warm_q = ss.q;
      auto fixedGuess = [&](const PotGuess& g) { return sensors.joint_sensors[g.sensor].fixed; };
      // The likeliest wrong answers are mirror images of the whole motion:
      // the world turned half a turn about a base axis a flips the sign of
      // every joint whose axis is perpendicular to a. Try those patterns
      // (and all signs flipped) before the greedy single-sign sweeps.
      {
        KinematicsWorkspace kin(robot);
        forwardKinematics(robot, neutralPose(robot), &kin);
        std::vector<std::vector<bool>> patterns(4, std::vector<bool>(guesses.size(), true));
        for (size_t i = 0; i < guesses.size(); ++i) {
          const Eigen::Vector3d u =
              kin.joint_axis[robot.qJoints()[guesses[i].column]].normalized();
          for (int a = 0; a < 3; ++a) patterns[1 + a][i] = std::abs(u[a]) < 0.7;
        }
        auto flip = [&](const std::vector<bool>& pattern) {
          for (size_t i = 0; i < guesses.size(); ++i)
            if (pattern[i] && !fixedGuess(guesses[i])) guesses[i].alpha = -guesses[i].alpha;
        };
        // The 80%-coverage scale is a guess too: a log that moves each
        // joint through a fifth of a ±2π range (a UR arm's) needs a map 4x
        // narrower. Each pattern is scored at a few common scales.
        auto scale = [&](double s) {
          for (PotGuess& g : guesses)
            if (!fixedGuess(g)) g.alpha *= s;
        };
        int best_pattern = -1;
        double best_scale = 1.0;
        for (double s : kCoverageScales) {
          scale(s);
          for (int k = -1; k < static_cast<int>(patterns.size()); ++k) {
            if (k >= 0) flip(patterns[k]);
            th = theta;
            const double c = markerCost(&th);
            if (k >= 0) flip(patterns[k]);
            if (c < best) best = c, best_pattern = k, best_scale = s, warm_q = ss.q;
          }
          scale(1.0 / s);
        }
        scale(best_scale);
        if (best_pattern >= 0) flip(patterns[best_pattern]);
        // The seed's own maps inverted are a candidate too: a user's rough
        // calibration (or a previous one) must not lose to the guesses.
        std::vector<PotGuess> seeded = guesses;
        for (PotGuess& g : seeded) {
          const GainBias& gb = theta.joint_sensor[g.sensor];
          if (gb.gain == 0 || !std::isfinite(gb.gain)) continue;
          g.alpha = 1.0 / gb.gain;
          g.mid = (g.mean - gb.bias) / gb.gain;
        }
        std::swap(guesses, seeded);
        th = theta;
        const double c = markerCost(&th);
        if (c < best) best = c, warm_q = ss.q; else std::swap(guesses, seeded);
      }
      // Greedy sign sweeps: each guess alone, then each guess together with
      // the nearest guessed joint above it in the tree. Two wrong signs in a
      // row (e.g. a wrist's pitch and roll) can each look right alone, since
      // flipping either one by itself moves the markers farther.
      {
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
      }
      auto flipMove = [&](const std::vector<int>& move) {
        for (int i : move) guesses[i].alpha = -guesses[i].alpha;
      };
      // Each guess's own scale: halved or doubled while the markers fit
      // clearly better (joints of one log rarely cover their ranges alike).
      auto rescaleSweep = [&]() {
        bool changed = false;
        for (PotGuess& g : guesses) {
          if (fixedGuess(g)) continue;
          for (double s : {0.5, 2.0}) {
            for (int step = 0; step < 3; ++step) {
              g.alpha *= s;
              SensorParameters trial = theta;
              const double c = markerCost(&trial);
              if (c < 0.98 * best) {
                best = c;
                warm_q = ss.q;
                changed = true;
              } else {
                g.alpha /= s;
                break;
              }
            }
          }
        }
        return changed;
      };
      // Until no sign change helps (at most 3 sweeps).
      auto signSweeps = [&]() {
        for (int sweep = 0; sweep < 3; ++sweep) {
          bool changed = false;
          for (const std::vector<int>& move : moves) {
            if (std::any_of(move.begin(), move.end(),
                            [&](int i) { return fixedGuess(guesses[i]); }))
              continue;
            flipMove(move);
            SensorParameters trial = theta;
            const double c = markerCost(&trial);
            // Two signs at once only for a clear gain: with outliers in the
            // data a double mirror can score marginally better by chance.
            if (c < (move.size() > 1 ? 0.95 : 1.0) * best) {
              best = c;
              warm_q = ss.q;
              changed = true;
            } else {
              flipMove(move);
            }
          }
          if (!changed) break;
        }
      };
      // Signs first (with wrong signs a narrower map always fits better),
      // then each guess's own scale, then signs again if a scale changed.
      signSweeps();
      if (rescaleSweep()) signSweeps();
      applyPotGuesses(guesses, obs, &state->q);
      for (const PotGuess& g : guesses) {
        if (sensors.joint_sensors[g.sensor].fixed) continue;
        GainBias& gb = theta.joint_sensor[g.sensor];
        gb.gain = 1.0 / g.alpha;
        gb.bias = g.mean - g.mid / g.alpha;
      }
      qo.eval.group_weight[1] = 1.0;  // pots now carry their guessed map
      to.update[1] = true;
    }
    if (marker_group_free)
      initialiseMarkerGroup(model, obs, *state, 3, threads, ws_ptr, &theta);
    double init_lambda = 1e-3;
    auto alternate = [&](double tol) {
    double prev = -1;
    for (int it = 0; it < 30; ++it) {
      double c = 0;
      if (it < 2 && guesses.empty()) {
        // No pot to guess from: track through time from the neutral pose
        // (twice: the second time with the mocap frame and markers the
        // first pass allowed).
        QPhaseOptions tr = qo;
        tr.method = QPhaseMethod::kLmBatch;
        tr.max_steps = 20;
        c = trackingPass(model, theta, noise, loss, obs, tr, neutralPose(robot), 32, ws_ptr, state);
      } else {
        c = qPhase(model, theta, noise, loss, obs, qo, ws_ptr, state);
      }
      if (marker_group_free || !guesses.empty())
        thetaPhase(model, noise, loss, obs, *state, to, ws_ptr, &theta);
      // Coupled steps once the alternation stalls (they cost more).
      if (coupled_steps && prev > 0 && prev - c < 1e-2 * prev)
        c = coupledStep(model, noise, loss, obs, threads, ws_ptr, &init_lambda, &theta, state,
                        qo.eval, true);
      if (prev > 0 && std::abs(prev - c) <= tol * prev) break;
      prev = c;
    }
    };
    if (!guesses.empty() && marker_group_free) {
      qo.eval.group_weight[1] = kInitPotWeight;
      alternate(1e-3);
      qo.eval.group_weight[1] = 1.0;
    }
    alternate(1e-3);
    if (marker_group_free && !moves.empty() &&
        verifySigns(model, obs, noise, loss, threads, ws_ptr, guesses, moves, &theta, state))
      alternate(1e-4);
    ThetaPhaseOptions pots;
    pots.threads = threads;
    pots.update[0] = false;
    thetaPhase(model, noise, loss, obs, *state, pots, ws_ptr, &theta);
  }
  return theta;
}

}  // namespace stac
