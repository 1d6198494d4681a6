// The Ceres pieces of the monolithic mode (--method joint, monolithic_problem.cpp):
// an EvaluationCallback that runs forward kinematics once per frame and
// evaluation point, and one cost function per reading type. Internal: the
// problem is assembled in monolithic_problem.cpp; test/monolithic_costs_test.cpp
// checks every Jacobian here against finite differences.
//
// Parameter blocks (one per physical quantity): q_t (robot.dof()), the mocap
// rotation as a unit quaternion [w, x, y, z] on ceres::QuaternionManifold,
// the mocap translation (3), a marker position in its link frame (3), a
// scalar sensor's (gain, bias) (2). Residuals are whitened: divided by σ.
#pragma once

#include <ceres/ceres.h>

#include <Eigen/Core>
#include <vector>

#include "stac/kinematics.hpp"
#include "stac/log.hpp"
#include "stac/robot_model.hpp"
#include "stac/sensors.hpp"

namespace stac::monolithic {

// For every frame t: forward kinematics at q_t, i.e. the link poses h_k(q_t),
// the world joint axes and origins, and the mimic-expanded joint vector.
//
// Every marker and tendon residual of a frame needs the same FK; Ceres calls
// PrepareForEvaluation after writing a new point into the parameter blocks
// (q points at the matrix whose rows are the q_t blocks) and before it
// evaluates any residual, so FK runs once per frame and point, in parallel,
// and the const Evaluate calls only read it.
//
// Joint-origin corrections (joint_origins.hpp) are parameter blocks of 6
// (x, y, z, roll, pitch, yaw) at `origins` (one buffer, origin_links.size()
// blocks); FK applies their current values.
class KinematicsCache : public ceres::EvaluationCallback {
 public:
  KinematicsCache(const RobotModel& robot, const RowMatrix* q, int threads,
                  std::vector<int> origin_links = {}, const double* origins = nullptr);

  void PrepareForEvaluation(bool evaluate_jacobians, bool new_evaluation_point) override;

  const KinematicsWorkspace& frame(int t) const { return frames_[t]; }

 private:
  const RobotModel& robot_;
  const RowMatrix* q_;
  int threads_;
  std::vector<int> origin_links_;
  const double* origins_;
  std::vector<KinematicsWorkspace> frames_;
  bool valid_ = false;
};

// A marker reading x of frame t, on link k at position d in the link frame:
//
//   r = (R(ρ) h_k(q_t) d + t - x) / σ          blocks [q_t, ρ(4), t(3), d(3)]
//
//   dr/dq_t = R J_k(x_b) / σ     J_k: Jacobian of the point x_b = h_k(q_t) d
//                                fixed on link k (kinematics.hpp)
//   dr/dρ   = d(R(ρ) x_b)/dρ / σ, in closed form from
//             R(ρ) y = (w² - v·v) y + 2 (v·y) v + 2 w v × y,  ρ = (w, v)
//   dr/dt   = I / σ
//   dr/dd   = R R_k / σ          R_k: rotation of h_k(q_t)
//
// R(ρ) normalises ρ while dr/dρ is the derivative of the quadratic form
// above; the two agree on the tangent space of the unit sphere, which is all
// the solver sees through the QuaternionManifold. FK comes from the cache.
//
// With joint-origin corrections upstream of link k (`origins`, indices of
// the cache's corrections), one more block of 6 per correction c:
//   dr/dc = R dx_b/dc / σ        (kinematics.hpp addOriginJacobian)
class MarkerReadingCost : public ceres::CostFunction {
 public:
  MarkerReadingCost(const RobotModel& robot, const KinematicsCache& cache, int frame, int link,
                    const Eigen::Vector3d& x, double sigma, std::vector<int> origins = {});

  static ceres::CostFunction* Create(const RobotModel& robot, const KinematicsCache& cache,
                                     int frame, int link, const Eigen::Vector3d& x,
                                     double sigma);

  bool Evaluate(double const* const* p, double* residuals, double** jac) const override;

 private:
  const RobotModel& robot_;
  const KinematicsCache& cache_;
  int frame_, link_;
  Eigen::Vector3d x_;
  double inv_;
  std::vector<int> origins_;
};

// The origin prior of one joint's correction c (SPEC §3 prior_std):
//   r_k = c_k / σ_k   (6 residuals; 0 where that part has no prior or is
// held, as ThetaSpace's free entries with a prior are what every other
// solver's cost sums, origin_prior.hpp)
class OriginPriorCost : public ceres::SizedCostFunction<6, 6> {
 public:
  OriginPriorCost(double xyz_std, double rpy_std, const FixedOrigin& held);
  bool Evaluate(double const* const* p, double* residuals, double** jac) const override;

 private:
  double inv_[6];
};

// A scalar reading p of frame t (a joint sensor or a tendon sensor):
//
//   r = (g v(q_t) + b - p) / σ                 blocks [q_t, (g, b)]
//
//   joint sensor:  v = m q_t[i] + o            (a mimic follower reads its
//                                               master i with multiplier m)
//   path tendon:   v = Σ_k |a_{k+1} - a_k|     (anchors a_k = h_{l_k}(q_t) p_k)
//   coupling:      v = Σ_j c_j (m_j q_t[i_j] + o_j)
//
//   dr/dq_t = g dv/dq_t / σ      (sensor_models.hpp: tendon_sensor)
//   dr/d(g, b) = (v, 1) / σ
//
// Exactly one of joint and tendon is set. Tendon lengths read the cache.
//
// A path whose anchors joint-origin corrections move (`origins`, indices of
// the cache's corrections; `anchor_slots[k]`, those of anchor k as
// positions in `origins`) has one more block of 6 per correction c:
//   dr/dc = g dL/dc / σ          (sensor_models.hpp addOriginLengthJacobian)
class ScalarReadingCost : public ceres::CostFunction {
 public:
  ScalarReadingCost(const RobotModel& robot, const KinematicsCache& cache, int frame,
                    const JointSensorConfig* joint, const TendonSensorConfig* tendon, double p,
                    double sigma, std::vector<int> origins = {},
                    std::vector<std::vector<int>> anchor_slots = {});

  static ceres::CostFunction* Create(const RobotModel& robot, const KinematicsCache& cache,
                                     int frame, const JointSensorConfig* joint,
                                     const TendonSensorConfig* tendon, double p, double sigma);

  bool Evaluate(double const* const* p, double* residuals, double** jac) const override;

 private:
  const RobotModel& robot_;
  const KinematicsCache& cache_;
  int frame_;
  const JointSensorConfig* joint_;
  const TendonSensorConfig* tendon_;
  double p_, inv_;
  std::vector<int> origins_;
  std::vector<std::vector<int>> anchor_slots_;
};

}  // namespace stac::monolithic
