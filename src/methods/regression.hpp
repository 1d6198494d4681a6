// The classical regression's least-squares core (internal): θ-only
// Levenberg-Marquardt with every joint angle read off its defining sensor's
// inverse map (classical.hpp). Shared by the classical baseline and by the
// tree-order search of the wide basin (tree_search.hpp), which solves the
// same θ-only problem on a subsample, one stage of the kinematic tree at a
// time.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "methods/classical.hpp"
#include "methods/method.hpp"

namespace stac {

// One pass over the usable frames.
struct Pass {
  double cost = 0;
  Eigen::MatrixXd H;  // free x free (with normal equations)
  Eigen::VectorXd g;
  double sse[kNumSensorGroups] = {0, 0, 0};    // raw units²
  double wsse[kNumSensorGroups] = {0, 0, 0};   // Σ ρ'(s) s at the seed σ
  double rows[kNumSensorGroups] = {0, 0, 0};
  double count[kNumSensorGroups] = {0, 0, 0};  // readings
};

// The regression over the frames of obs (each must have every defining
// reading). Holds references to its arguments; owns one workspace per thread.
class Regression {
 public:
  Regression(const MeasurementModel& model, const JointSources& sources,
             const Observations& obs, const RobustLoss& loss, int threads);
  const std::vector<int>& freeIndex() const { return free_; }

  // Cost and statistics at p (and with normal_equations, H and g over the
  // free entries).
  Pass pass(const ClassicalParameters& p, const NoiseModel& noise, const NoiseModel& seed_noise,
            bool normal_equations);

  // Levenberg-Marquardt from *p (at most options.max_iterations, stopping
  // when the relative decrease is below options.tolerance; progress reported
  // as iteration first_iteration + k); returns iterations, sets *converged.
  int solve(const NoiseModel& noise, const NoiseModel& seed_noise,
            const CalibrationOptions& options, Clock::time_point start, int first_iteration,
            ClassicalParameters* p, bool* converged);

  // The pass (with normal equations) at the last solve's end.
  const Pass& last() const { return last_; }

 private:
  const MeasurementModel& model_;
  const JointSources& sources_;
  const Observations& obs_;
  const RobustLoss& loss_;
  int threads_;
  const std::vector<int>& free_;
  std::vector<FrameWorkspace> ws_;
  Pass last_;
};

}  // namespace stac
