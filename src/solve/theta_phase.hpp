// θ-phase (paper §III-A..C): with every q_t fixed the sensors are
// independent. Closed forms where the paper has them:
//  - gain/bias of a joint or tendon sensor: weighted linear least squares of
//    the reading against the joint angle or tendon length (eq. 18-20);
//  - the mocap frame: Procrustes (eq. 13-16) with a proper rotation;
//  - marker positions: averaging in the link frame (eq. 17).
// Because the mocap frame and the marker positions share every marker
// reading, the marker group is refined jointly by Gauss-Newton from the
// closed-form values (a few 9-parameter-per-reading passes over cached link
// poses), so that the alternation minimises exactly the same cost as the
// monolithic problem.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "stac/log.hpp"
#include "stac/measurement.hpp"
#include "solve/q_phase.hpp"

namespace stac {

// ---- Closed forms (usable on their own; tested against exact truth) ----

struct LineFit {
  GainBias value;
  bool gain_identifiable = true;  // false: the input never varied
  bool any_data = true;           // false: no reading at all
};
// Weighted least squares of p ≈ gain * x + bias over the n pairs whose p is
// not NaN (w may be null: unit weights). Degenerate input keeps `previous`'s
// gain (and, without data, its bias).
LineFit fitGainBias(const double* x, const double* p, const double* w, int n,
                    const GainBias& previous);
// The same with the parts in `fixed` held at `previous`'s values: with the
// gain held, the bias is the weighted mean of p - gain * x; with the bias
// held, the gain is Σ w x (p - bias) / Σ w x² (kept where x was always 0).
LineFit fitGainBias(const double* x, const double* p, const double* w, int n,
                    const GainBias& previous, const FixedGainBias& fixed);

// (R, t) minimising Σ w_i |R a_i + t - b_i|² with det R = +1, or nullopt when
// the points do not determine a rotation (fewer than 3 or all collinear).
std::optional<MocapFrame> procrustes(const std::vector<Eigen::Vector3d>& a,
                                     const std::vector<Eigen::Vector3d>& b,
                                     const std::vector<double>& w);
// Procrustes with a part of the frame held at `frame`'s value: with the
// rotation held, t is the weighted mean of b - R a; with the translation
// held, R is the proper rotation minimising Σ w_i |R a_i - (b_i - t)|² (nullopt
// as above). Both held: `frame` itself.
std::optional<MocapFrame> procrustes(const std::vector<Eigen::Vector3d>& a,
                                     const std::vector<Eigen::Vector3d>& b,
                                     const std::vector<double>& w, const MocapFrame& frame,
                                     const FixedFrame& fixed);

// Link poses (in the base frame) of every marker in every frame, cached once
// per θ-phase: T x markers; with θ's joint-origin corrections when theta is
// given (else the URDF as is).
struct MarkerPoseCache {
  int markers = 0;
  std::vector<Eigen::Matrix3d> rotation;     // [t * markers + m]
  std::vector<Eigen::Vector3d> translation;
};
MarkerPoseCache cacheMarkerPoses(const MeasurementModel& model, const RowMatrix& q,
                                 int threads, std::vector<FrameWorkspace>* ws,
                                 const SensorParameters* theta = nullptr);

// Eq. 17: d_m = mean over frames of h_r^T (R^T (x - t) - h_p). Returns
// nullopt for a marker that was never seen.
std::optional<Eigen::Vector3d> averageMarkerPosition(const MarkerPoseCache& poses,
                                                     const Observations& obs,
                                                     const MocapFrame& frame, int m);

// ---- The whole θ-phase ----

struct ThetaPhaseOptions {
  bool update[kNumSensorGroups] = {true, true, true};
  int marker_gauss_newton_steps = 4;
  int threads = 0;
};

struct ThetaPhaseReport {
  std::vector<std::string> degenerate;  // parameters the data left untouched
};

// Updates the free parameters of *theta for the fixed q in state.
ThetaPhaseReport thetaPhase(const MeasurementModel& model, const NoiseModel& noise,
                            const RobustLoss& loss, const Observations& obs,
                            const QState& state, const ThetaPhaseOptions& options,
                            std::vector<FrameWorkspace>* workspaces,
                            SensorParameters* theta);

// Closed-form initialisation of the marker group (wide basin): Procrustes of
// the measured marker cloud against the predicted one, then averaging, a few
// rounds. Only free parameters change.
void initialiseMarkerGroup(const MeasurementModel& model, const Observations& obs,
                           const QState& state, int rounds, int threads,
                           std::vector<FrameWorkspace>* workspaces,
                           SensorParameters* theta);

}  // namespace stac
