// Wide-basin initialisation (see calibrate.cpp's header comment): pots'
// readings mapped onto their joint ranges with signs chosen by the markers,
// closed-form mocap frame and markers, then a marker-led alternation.
#include "wide_basin.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>

#include "stac/calibrate.hpp"
#include "stac/schur.hpp"
#include "stac/theta_phase.hpp"

namespace stac {
namespace {

// The joint angle a one-joint sensor implies if the log spans 80% of the
// joint's range: q = alpha (p - mean p) + mid. Such a guess has the right
// time course and roughly the right scale; only alpha's sign is unknown,
// and a greedy sweep picks each sign by how well the markers then fit.
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

}  // namespace

std::vector<int> spreadFrames(int frames, int count) {
  std::vector<int> out;
  const int n = std::min(frames, count);
  for (int i = 0; i < n; ++i) out.push_back(static_cast<int>(static_cast<long>(i) * frames / n));
  return out;
}

Observations selectFrames(const Observations& obs, const std::vector<int>& frames) {
  Observations out;
  out.num_frames = static_cast<int>(frames.size());
  out.marker.resize(out.num_frames, obs.marker.cols());
  out.joint.resize(out.num_frames, obs.joint.cols());
  out.tendon.resize(out.num_frames, obs.tendon.cols());
  for (int i = 0; i < out.num_frames; ++i) {
    out.marker.row(i) = obs.marker.row(frames[i]);
    out.joint.row(i) = obs.joint.row(frames[i]);
    out.tendon.row(i) = obs.tendon.row(frames[i]);
    if (!obs.time.empty()) out.time.push_back(obs.time[frames[i]]);
  }
  out.time_name = obs.time_name;
  return out;
}

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
      std::vector<int> sub;
      const int n_sub = std::min(obs.num_frames, 150);
      for (int i = 0; i < n_sub; ++i)
        sub.push_back(static_cast<int>(static_cast<long>(i) * obs.num_frames / n_sub));
      const Observations so = selectFrames(obs, sub);
      QState ss;
      ss.q = neutralPose(robot).transpose().replicate(so.num_frames, 1);
      // A candidate's score: how well the markers fit once the mocap frame
      // and markers are re-solved in closed form and the joints no pot
      // covers (gimbals driven by linear pots, say) follow the markers.
      QPhaseOptions free_only = qo;
      free_only.method = QPhaseMethod::kLmBatch;
      free_only.max_steps = 8;
      free_only.frozen.assign(robot.dof(), false);
      bool any_free = false;
      for (const PotGuess& g : guesses) free_only.frozen[g.column] = true;
      for (int j = 0; j < robot.dof(); ++j) any_free |= !free_only.frozen[j];
      auto markerCost = [&](SensorParameters* th) {
        ss.q = neutralPose(robot).transpose().replicate(so.num_frames, 1);
        applyPotGuesses(guesses, so, &ss.q);
        for (int round = 0; round < (any_free ? 2 : 1); ++round) {
          if (marker_group_free) {
            initialiseMarkerGroup(model, so, ss, 2, threads, ws_ptr, th);
            thetaPhase(model, noise, loss, so, ss, to, ws_ptr, th);
          }
          if (any_free) qPhase(model, *th, noise, loss, so, free_only, ws_ptr, &ss);
        }
        return totalCost(model, *th, noise, loss, so, qo.eval, threads, ws_ptr, &ss);
      };
      SensorParameters th = theta;
      double best = markerCost(&th);
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
            if (pattern[i] && !sensors.joint_sensors[guesses[i].sensor].fixed)
              guesses[i].alpha = -guesses[i].alpha;
        };
        int best_pattern = -1;
        for (int k = 0; k < static_cast<int>(patterns.size()); ++k) {
          flip(patterns[k]);
          th = theta;
          const double c = markerCost(&th);
          flip(patterns[k]);
          if (c < best) best = c, best_pattern = k;
        }
        if (best_pattern >= 0) flip(patterns[best_pattern]);
      }
      for (int sweep = 0; sweep < 2; ++sweep) {
        bool changed = false;
        for (PotGuess& g : guesses) {
          if (sensors.joint_sensors[g.sensor].fixed) continue;
          g.alpha = -g.alpha;
          SensorParameters trial = theta;
          const double c = markerCost(&trial);
          if (c < best) {
            best = c;
            changed = true;
          } else {
            g.alpha = -g.alpha;
          }
        }
        if (!changed) break;
      }
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
    double prev = -1, init_lambda = 1e-3;
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
                        qo.eval);
      if (prev > 0 && std::abs(prev - c) <= 1e-4 * prev) break;
      prev = c;
    }
    ThetaPhaseOptions pots;
    pots.threads = threads;
    pots.update[0] = false;
    thetaPhase(model, noise, loss, obs, *state, pots, ws_ptr, &theta);
  }
  return theta;
}

}  // namespace stac
