// The coupled steps' damping (solve/lm_damping.hpp, addScaleFreeDamping): a
// damped step does not depend on the unit of a parameter that readings see,
// however small its curvature against the system's largest, and a
// parameter that no reading sees (or only rounding does) stays put.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <random>

#include "solve/lm_damping.hpp"

namespace stac {
namespace {

Eigen::VectorXd dampedStep(double lambda, const Eigen::MatrixXd& H, const Eigen::VectorXd& g) {
  Eigen::MatrixXd A = H;
  addScaleFreeDamping(lambda, H, &A);
  return A.ldlt().solve(-g);
}

// A well-conditioned system of 4 parameters, the last one's curvature 1e13
// (e.g. a pot's inverse chart in encoder ticks beside angles in radians).
struct System {
  Eigen::MatrixXd H;
  Eigen::VectorXd g;
  System() {
    std::mt19937 rng(11);
    std::normal_distribution<double> z;
    Eigen::MatrixXd J(8, 4);
    for (Eigen::Index i = 0; i < J.size(); ++i) J.data()[i] = z(rng);
    J.col(3) *= 3e6;
    Eigen::VectorXd r(8);
    for (int i = 0; i < 8; ++i) r[i] = z(rng);
    H = J.transpose() * J;
    g = J.transpose() * r;
  }
};

// Parameter 0 in a unit 1e4 times smaller (its curvature 1e-8 times, 21
// orders below the largest): the step, in the old unit, is the same. (An
// absolute ridge of 1e-12 the largest curvature on every entry damped it
// 1e9 times more than λ = 1 does: the step in the small unit was nothing.)
TEST(LmDamping, AStepDoesNotDependOnAParametersUnit) {
  const System s;
  const double unit = 1e4;
  Eigen::VectorXd scale = Eigen::VectorXd::Ones(4);
  scale[0] = unit;  // new coordinate = unit * old: J column / unit
  const Eigen::MatrixXd H2 = scale.cwiseInverse().asDiagonal() * s.H * scale.cwiseInverse().asDiagonal();
  const Eigen::VectorXd g2 = scale.cwiseInverse().asDiagonal() * s.g;
  for (double lambda : {1e-9, 1e-3, 1.0}) {
    const Eigen::VectorXd a = dampedStep(lambda, s.H, s.g);
    const Eigen::VectorXd b = dampedStep(lambda, H2, g2).cwiseQuotient(scale);
    EXPECT_LT((a - b).norm(), 1e-6 * a.norm()) << "lambda " << lambda;
  }
}

// A parameter that no reading sees (zero row, column and gradient) stays
// put; one that only rounding sees (its Jacobian column 1e-16 of the
// others', curvature 1e-32 of theirs, a gradient of rounding) hardly moves.
TEST(LmDamping, AnUnseenParameterStaysPut) {
  System s;
  Eigen::MatrixXd H = Eigen::MatrixXd::Zero(5, 5);
  H.topLeftCorner(4, 4) = s.H;
  Eigen::VectorXd g = Eigen::VectorXd::Zero(5);
  g.head(4) = s.g;
  EXPECT_EQ(dampedStep(1e-9, H, g)[4], 0.0);
  const double typical = std::sqrt(s.H(0, 0));
  H(4, 4) = 1e-32 * typical * typical;
  g[4] = 1e-16 * typical;
  EXPECT_LT(std::abs(dampedStep(1e-9, H, g)[4]), 1e-3);
}

}  // namespace
}  // namespace stac
