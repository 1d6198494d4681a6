// The joint Gauss-Newton system of (q_1..q_T, θ) reduced onto θ by
// eliminating every q_t (Schur complement), computed frame by frame in
// parallel. It serves both the uncertainty of θ with the q_t marginalised
// out and the coupled (q, θ) Levenberg-Marquardt step that lets the STAC
// alternation finish quickly where q and θ are strongly coupled.
#pragma once

#include <Eigen/Core>
#include <functional>
#include <vector>

#include "stac/log.hpp"
#include "stac/measurement.hpp"
#include "solve/q_phase.hpp"

namespace stac {

// One reading's share of the θθ Gauss-Newton system over the free entries
// (free_of: θ index -> free index, -1 if held): J_θᵀ r added to g (when
// given) and J_θᵀ J_θ to the lower triangle of S. The one place either the
// Schur reduction or the origin phase forms it.
void accumulateThetaNormalEquations(const ReadingJacobian& rj, const std::vector<int>& free_of,
                                    Eigen::MatrixXd* S, Eigen::VectorXd* g);

struct ReducedSystem {
  std::vector<int> free_index;    // θ entry of each reduced row
  Eigen::MatrixXd S;              // H_θθ - Σ H_θq (H_qq + λD)⁻¹ H_qθ (+ λ diag)
  Eigen::VectorXd g;              // g_θ - Σ H_θq (H_qq + λD)⁻¹ g_q
  double cost = 0;                // ½ Σ ρ at the linearisation point
  // ½ Σ_t g_qᵀ (H_qq + λD)⁻¹ g_q: what the q_t alone could still take off
  // the cost (computed with the gradient).
  double q_decrement = 0;
};

// Frames are summed in this many fixed blocks of consecutive frames
// (independent of the thread count, so sums are deterministic).
constexpr int kReductionBlocks = 16;

// Sees each frame of a gradient pass: its block, its evaluation with
// Jacobians, and its H_qq before damping. Called from worker threads, at
// most one call per block at a time.
using FrameVisitor =
    std::function<void(int block, const FrameWorkspace& w, const Eigen::MatrixXd& Hqq)>;

// With score_outer, also Σ_t g̃_t g̃_tᵀ over the frames, g̃_t being frame t's
// share of the reduced gradient g (its θ score with q_t profiled out): the
// "meat" of a sandwich covariance (uncertainty.hpp). With unreduced_diag,
// also diag(H_θθ), before the q_t are eliminated (pot_chart.hpp reads how
// much of a gain's curvature the q_t take).
ReducedSystem reduceOntoTheta(const MeasurementModel& model, const SensorParameters& theta,
                              const NoiseModel& noise, const RobustLoss& loss,
                              const Observations& obs, const RowMatrix& q, double lambda,
                              bool with_gradient, int threads,
                              std::vector<FrameWorkspace>* ws,
                              const FrameOptions& groups = FrameOptions(),
                              const FrameVisitor& visit = nullptr,
                              Eigen::MatrixXd* score_outer = nullptr,
                              Eigen::VectorXd* unreduced_diag = nullptr);

// How a coupled step treats the frames (coupledStep below).
struct CoupledStepOptions {
  FrameOptions groups;  // which sensor groups count, with what weight
  // Project every q_t onto the q-phase's box (q_phase.hpp widenedLimits):
  // the initialisation uses it so that a joint cannot walk to its half-turn
  // mirror (a joint turned by π with its links' markers turned back fits as
  // well); the main loop does not, since a projected step stalls when a bad
  // start leaves frames at the bounds.
  bool within_limits = false;
  // Score a trial that the back-substituted q_t make worse again with every
  // q_t refitted to its θ (a few LM steps; the .cpp says why) before λ
  // grows: the main loop's steps. The initialisation's searches compare
  // candidate starts by the cost a few plain steps reach, and keep them so
  // (a refit there let a mirrored finger joint that only tendons show score
  // as well as its right sign).
  bool refit_rejected = false;
  // Move each pot that dominates its joint's angle in its inverse chart
  // (pot_chart.hpp): the main loop's steps, and the escape's scoring of
  // jumps. The initialisation's sign re-check keeps (gain, bias): it scores
  // a candidate sign by the cost a few steps reach, and in the inverse
  // chart a few steps also carry the other candidate through a still
  // joint, so the two no longer differ (a finger's sign that only the
  // tendons show went unrighted).
  bool inverse_charts = false;
  // Sees every frame at the starting point (θ, q), once.
  FrameVisitor visit;
};

// One coupled LM step on (q, θ): tries damping *lambda (adapting it) until
// the total cost decreases; returns the new cost, or the old one (state
// unchanged) if no damping helped.
double coupledStep(const MeasurementModel& model, const NoiseModel& noise,
                   const RobustLoss& loss, const Observations& obs, int threads,
                   std::vector<FrameWorkspace>* ws, double* lambda,
                   SensorParameters* theta, QState* state,
                   const CoupledStepOptions& options = CoupledStepOptions());

}  // namespace stac
