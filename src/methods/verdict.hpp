// The tool's own checks of a calibration (SPEC §3 summary.verdict, §4 exit
// 4): a result that fails one is still written, with the reasons, so that a
// wrong minimum is never a silent, confident answer.
#pragma once

#include <string>
#include <vector>

#include "methods/method.hpp"

namespace stac {

// Fitted σ (or, without variance adaptation, residual RMS per reading row)
// over the seed σ beyond which a group is suspect.
constexpr double kSuspectFitRatio = 3.0;
// A sensor whose RMS residual is this many times its own σ (no robust loss).
constexpr double kSuspectSensorRatio = 4.0;
// A marker moved by a joint whose pot gain is listed undetermined, fitting
// this many times worse than the markers' median (median errors): well
// beyond what sampling gives (a median over some hundred frames varies by
// a few per cent).
constexpr double kWeakMarkerRatio = 1.25;

// A joint the fit holds at a bound of the q-phase's box (the URDF limits
// widened by 5%) in more than this share of the frames: its readings ask
// for angles the robot cannot reach. True angles never leave the limits, so
// a calibration that puts a joint's motion beyond them in many frames is a
// wrong minimum (a pot's map a whole turn off, a wrong scale), or the URDF's
// limits are narrower than the robot's. Gross readings put frames there
// too: a pot's gross error on a joint few markers see moves the joint with
// it (5% gross readings held 2-5% of the frames of the basin test's arm4 at
// a limit), hence a share well above that.
constexpr double kSuspectShareAtLimit = 0.10;
// A frame counts as put beyond a joint's limit when its unconstrained angle
// lies beyond the URDF's limit by more than this many of its own std.
constexpr double kLimitExcessStd = 3.0;
// The share of frames at a limit from which a converged run looks for a
// better minimum (alternation.cpp): a false start costs only time. Also the
// share beyond a joint's URDF limits from which a mirror move that brings
// the joint inside them counts as relieving them (wide_basin.cpp).
constexpr double kEscapeShareAtLimit = 0.02;

// Whether `count` of `rows` frames is "often": more than `share` of them,
// and at least 3 (the escape's trigger, its relief and the verdict alike).
inline bool often(double count, double rows, double share) {
  return count >= 3 && count > share * rows;
}

// The joints (q indices) q holds at a limit in more than `share` of its
// rows, and in at least 3.
std::vector<int> jointsOftenAtLimit(const RobotModel& robot, const RowMatrix& q, double share);

// Of the frames `frames` marks for joint j, how many the readings put
// beyond the URDF's limit by more than kLimitExcessStd of that frame's own
// angle std (q: the fitted angles; θ, σ: the fit's).
int framesBeyondLimit(const MeasurementModel& model, const SensorParameters& theta,
                      const NoiseModel& noise, const RobustLoss& loss, const Observations& obs,
                      const RowMatrix& q,
                      const Eigen::Matrix<bool, Eigen::Dynamic, Eigen::Dynamic>& frames, int j);

// The joints whose fitted angles lie beyond the URDF's limits, by more than
// kLimitExcessStd of their own std, in more than `share` of the frames and
// in at least 3. Within the 5% widening a wrong minimum's motion need not
// reach the q-phase's bound (a shoulder's mirror image, panda/partial basin
// truth 12) while it still asks for angles the robot cannot reach.
std::vector<int> jointsOftenBeyondLimits(const MeasurementModel& model,
                                         const SensorParameters& theta, const NoiseModel& noise,
                                         const RobustLoss& loss, const Observations& obs,
                                         const RowMatrix& q, double share);

// Whether the data leave where joint j's motion lies open: the bias of a
// pot on it is `listed` exactly null (a lift's bias against the mocap
// translation), known modulo a turn, or in a mirror configuration that fits
// as well. Its frames at a limit then show where the fit drifted to, not a
// wrong minimum, and the limit check passes it. Not a bias listed only
// weakly determined, nor a still pot's: the data still place the joint's
// motion, and a wrong minimum can sit there (an unseen Unitree B1 on
// partial swings, fresh seed 13's truth 3: a calf whose marker lies near
// the knee's axis converged with its motion mirrored at half scale, below
// the knee's lower limit in 169 of 600 frames, the calf pot's gain and bias
// listed as trading off, the thigh's marker 10 std off, verdict ok).
bool placementUndetermined(const RobotModel& robot, const SensorSet& sensors,
                           const std::vector<UnidentifiableDirection>& listed, int j);

// The frames a method fitted (all of the log's, or the classical
// regression's usable ones) and their q.
struct Fit {
  const Observations& obs;
  const RowMatrix& q;
};

// The reasons r fails the checks (empty: ok). `in` is the run's input, `out`
// its outcome (for the EKF's costs), `fit` what r's statistics are over; r
// has its summary and statistics.
std::vector<std::string> verdictOf(const MethodInput& in, const Outcome& out, const Fit& fit,
                                   const CalibrationResult& r);

}  // namespace stac
