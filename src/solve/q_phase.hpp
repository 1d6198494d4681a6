// q-phase (paper §III-D): with θ fixed the frames are independent; each
// q_t is refined by a small dense solver, in parallel over frames.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "stac/log.hpp"
#include "solve/marker_bodies.hpp"
#include "stac/measurement.hpp"

namespace stac {

struct QPhaseOptions {
  QPhaseMethod method = QPhaseMethod::kLmIter;
  int max_steps = 30;       // per frame, for lm-batch and bfgs
  double step_tolerance = 1e-10;
  int threads = 0;
  FrameOptions eval;         // group weights; jacobian flags are set inside
  std::vector<bool> frozen; // q columns held at their value (empty: none)
  // Also try, per frame, the whole turns its pots' readings ask for
  // (whole_turns.hpp). Only once the maps are estimates: in the
  // initialisation a rough map turned frames at random (a frame its map
  // does not explain lands within the bound by chance), and the pots fitted
  // to them dragged a ur5 with gross readings from a start 0.03 off in its
  // pots to one 0.37 off, 200 iterations to converge.
  bool whole_turns = false;
};

// Per-frame solver state carried across outer iterations (warm start).
// The box every estimated q_t is kept in: the URDF limits widened by 5% of
// each joint's range (±inf where a joint has none). Outside it lie mirror
// solutions of the marker geometry (a joint turned half a turn with its
// link's markers turned back), which fit the readings as well.
void widenedLimits(const RobotModel& robot, Eigen::VectorXd* lower, Eigen::VectorXd* upper);
// Whether each joint of each row of q sits on that box's bound (within a
// micro-radian or micrometre): the q-phase stopped it there, its readings
// asking for more. Rows of q x dof.
Eigen::Matrix<bool, Eigen::Dynamic, Eigen::Dynamic> atWidenedLimit(const RobotModel& robot,
                                                                   const RowMatrix& q);
// Whether each joint of each row of q lies beyond the URDF's own limits
// (by more than a micro-radian or micrometre), where true angles never go:
// the q-phase's box allows it, so that noise does not hold a joint moved to
// its limit. Rows of q x dof.
Eigen::Matrix<bool, Eigen::Dynamic, Eigen::Dynamic> beyondLimits(const RobotModel& robot,
                                                                 const RowMatrix& q);

struct QState {
  RowMatrix q;               // frames x dof
  Eigen::VectorXd lambda;    // LM damping per frame
  Eigen::VectorXd cost;      // last cost per frame
};

// Refines every row of state->q. Returns the total cost ½ Σ ρ afterwards.
// `workspaces` holds one FrameWorkspace per thread.
double qPhase(const MeasurementModel& model, const SensorParameters& theta,
              const NoiseModel& noise, const RobustLoss& loss,
              const Observations& obs, const QPhaseOptions& options,
              std::vector<FrameWorkspace>* workspaces, QState* state);

// Tracking: the frames are cut into `segments` fixed runs; the first frame
// of each run starts from `start`, every other one from its predecessor's
// solution, and each is solved by LM to convergence. Used to initialise q
// from a poor seed without jumping between mirror solutions.
double trackingPass(const MeasurementModel& model, const SensorParameters& theta,
                    const NoiseModel& noise, const RobustLoss& loss,
                    const Observations& obs, const QPhaseOptions& options,
                    const Eigen::VectorXd& start, int segments,
                    std::vector<FrameWorkspace>* workspaces, QState* state);

// Total cost ½ Σ ρ at the current q (no Jacobians); fills state->cost.
double totalCost(const MeasurementModel& model, const SensorParameters& theta,
                 const NoiseModel& noise, const RobustLoss& loss,
                 const Observations& obs, const FrameOptions& eval, int threads,
                 std::vector<FrameWorkspace>* workspaces, QState* state);

// The Gauss-Newton system of one frame from the last evaluation in ws:
// H = Σ Jqᵀ Jq, g = Σ Jqᵀ r (dof x dof, dof).
void accumulateNormalEquations(const FrameWorkspace& ws, Eigen::MatrixXd* H,
                               Eigen::VectorXd* g);

// Adds each sensor group's share of the dof the frame's q_t takes,
// tr(J_g H⁻¹ J_gᵀ) (the leverage of its readings), to leverage[]. H is that
// evaluation's accumulateNormalEquations H (overwritten); Linv is a dof x dof
// scratch. The shares sum to the number of joints some reading sees, but
// that the virtual points of one tracked body (marker_bodies.hpp) count
// their leverage rowsPerDim times: the rows it leaves them carry no error.
void addGroupLeverage(const FrameWorkspace& ws, const MarkerBodies& bodies, Eigen::MatrixXd* H,
                      Eigen::MatrixXd* Linv, double leverage[kNumSensorGroups]);

}  // namespace stac
