// One frame's whitened residuals and Jacobians as dense matrices.
//
// evaluateFrame() leaves each reading's residual and its few nonzero
// Jacobian entries in a FrameWorkspace (the alternation and the q-phase want
// them sparse). The EKF (ekf.hpp) and the classical regression
// (classical.hpp) work on whole state vectors and want
//   r (rows), dr/dθ (rows x thetaSize, MeasurementModel layout) and
//   dr/dq (rows x dof),
// rows stacked in the order of the readings. Building them here keeps both
// baselines on the very same sensor models and Jacobians as STAC.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "stac/measurement.hpp"

namespace stac {

struct DenseFrame {
  Eigen::VectorXd r;
  Eigen::MatrixXd Jtheta;  // rows x model.thetaSpace().size()
  Eigen::MatrixXd Jq;      // rows x model.dof()
  int rows = 0;
};

// From the last evaluateFrame(..., jacobians and theta_jacobians, ws).
// Readings of the joint sensors flagged in skip_joint (may be null: none)
// are left out.
void denseFrame(const MeasurementModel& model, const FrameWorkspace& ws,
                const std::vector<bool>* skip_joint, DenseFrame* out);

}  // namespace stac
