// The coupled (q, θ) step (schur.cpp coupledStep): its back-substitution
// moves every q_t along its tangent, and where frames are far from linear a
// trial scored with those q_t alone is rejected however good its θ step is;
// λ then grows and the run crawls. A rejected trial is scored again with its
// q_t refitted to the trial's θ.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "solve/q_phase.hpp"
#include "solve/schur.hpp"
#include "stac/measurement.hpp"
#include "support/arm_fixture.hpp"

namespace stac {
namespace {

// The arm at its true θ with every frame's angles 0.8 rad off theirs: far
// outside the range where one linear step per frame lands near the fit.
struct FarFrames {
  test::ArmProblem p = test::makeArmProblem(200, 3);
  MeasurementModel model{p.robot, p.sensors};
  NoiseModel noise = NoiseModel::fromSeeds(p.sensors);
  std::vector<FrameWorkspace> ws = std::vector<FrameWorkspace>(2, FrameWorkspace(model));
  QState q;
  FarFrames() {
    std::mt19937 rng(7);
    std::uniform_int_distribution<int> sign(0, 1);
    q.q = p.q_true;
    for (Eigen::Index t = 0; t < q.q.rows(); ++t)
      for (Eigen::Index j = 0; j < q.q.cols(); ++j) q.q(t, j) += sign(rng) ? 0.8 : -0.8;
  }
  double cost(const SensorParameters& theta, QState* state) {
    return totalCost(model, theta, noise, RobustLoss(), p.obs, FrameOptions(), 2, &ws, state);
  }
};

TEST(CoupledStep, FarFramesDoNotRaiseTheDamping) {
  FarFrames f;
  const double before = f.cost(f.p.truth, &f.q);
  SensorParameters theta = f.p.truth;
  double lambda = 1e-4;
  CoupledStepOptions refit;
  refit.refit_rejected = true;
  const double after =
      coupledStep(f.model, f.noise, RobustLoss(), f.p.obs, 2, &f.ws, &lambda, &theta, &f.q, refit);
  // Accepted at the damping it was given (λ then falls), and the cost it
  // reports is that of the state it leaves.
  EXPECT_LT(after, 0.5 * before);
  EXPECT_LT(lambda, 1e-4);
  EXPECT_NEAR(f.cost(theta, &f.q), after, 1e-9 * after);
}

}  // namespace
}  // namespace stac
