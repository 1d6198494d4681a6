// The joint-origin corrections in the alternation's θ-phase. They have no
// closed form: with every q_t fixed they are a small dense nonlinear least
// squares that couples all frames (and trades off with the marker positions
// and the mocap frame). So after the closed forms, a few Levenberg-Marquardt
// steps over every free θ entry at once, q fixed, the origin prior included:
// Σ_t J_θᵀ J_θ is nf x nf, summed per frame from the readings' sparse
// θ-Jacobians in fixed blocks of frames (deterministic).
#pragma once

#include <vector>

#include "stac/log.hpp"
#include "stac/measurement.hpp"
#include "solve/q_phase.hpp"

namespace stac {

// Up to `steps` accepted LM steps on *theta (q fixed) while the cost (data
// plus prior) falls; *lambda carries the damping between calls. A no-op
// without joint-origin corrections. Returns the final cost (data + prior).
double originPhase(const MeasurementModel& model, const NoiseModel& noise, const RobustLoss& loss,
                   const Observations& obs, const RowMatrix& q, int steps, int threads,
                   std::vector<FrameWorkspace>* ws, double* lambda, SensorParameters* theta);

}  // namespace stac
