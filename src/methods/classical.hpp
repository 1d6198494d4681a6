// Classical regression baseline (paper §II-A and §IV-B, eq. 28-29;
// --method classical).
//
// STAC with σ_p -> 0: every joint angle is read off its one-joint sensor,
//   angle_j = a_j p_j + c_j          (the paper's eq. 2; a = 1/gain, c = -bias/gain)
// and the remaining parameters (the mocap frame, the markers, tendon sensors,
// any further joint sensors on an already covered joint) together with every
// (a_j, c_j) are fitted to the marker and tendon readings by nonlinear least
// squares over θ alone (Levenberg-Marquardt on the normal equations, the
// mocap rotation updated on SO(3)). Not Ceres: Ceres keeps the whole Jacobian
// (every reading of every frame against nearly every θ entry, since a
// frame's markers depend on most joint sensors: ~1.7 GB for 25,000 frames of
// hand24), while the normal equations are θ x θ. Joint angles are never
// estimated, so a joint without a one-joint sensor of its own (e.g. one
// moved only by tendons) cannot be handled: such robots are refused. Mimic
// followers need no sensor; a sensor on a follower covers its master.
//
// The regression fits the inverse map (a, c) rather than (gain, bias): it is
// linear in the reading and smooth through a = 0, so a seed with the wrong
// gain sign (the paper's seeding: gains 1) can still move to the right one.
// It starts from the seed as given; the paper's classical baseline starts
// from a manual calibration, and from gains 1 / biases 0 it may stop in a
// local minimum. Frames with a missing reading of a defining joint sensor
// are skipped.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "stac/log.hpp"
#include "stac/measurement.hpp"
#include "stac/robot_model.hpp"
#include "stac/sensors.hpp"

namespace stac {

// Which joint sensor gives each joint angle.
struct JointSources {
  std::vector<int> sensor;             // per q column: joint sensor index, -1 if none
  std::vector<bool> defining;          // per joint sensor: it gives its joint's angle
  std::vector<std::string> uncovered;  // joints of q without a one-joint sensor
};
// The first joint sensor (in file order) on each joint of q or on one of its
// mimic followers defines that joint's angle.
JointSources findJointSources(const RobotModel& robot, const SensorSet& sensors);

// The inverse sensor map of a defining joint sensor: angle = a p + c.
struct InverseMap {
  double a = 1.0, c = 0.0;
};
// (gain, bias) -> (a, c); a zero gain maps to a = c = 0 (angle held at 0).
InverseMap inverseMap(const GainBias& gb);
// (a, c) -> (gain, bias); throws std::domain_error for a = 0.
GainBias forwardMap(const InverseMap& ic);

// A defining sensor whose bias alone is held: its offset is tied to its
// inverse gain, c = -bias a.
bool tiedOffset(const FixedGainBias& fixed);

// The regression's parameters: θ, where the (gain, bias) of defining joint
// sensors are ignored in favour of `inverse` (indexed by joint sensor).
struct ClassicalParameters {
  SensorParameters theta;
  std::vector<InverseMap> inverse;
};

// q from the defining sensors' readings; false if one of them is missing.
bool anglesFromSensors(const RobotModel& robot, const SensorSet& sensors,
                       const JointSources& sources, const std::vector<InverseMap>& inverse,
                       const double* joint_readings, Eigen::VectorXd* q);

// The frames of obs with every defining sensor's reading.
std::vector<int> framesWithEveryDefiningReading(const Observations& obs,
                                                const JointSources& sources);
// q from the defining sensors' maps for every frame of obs (NaN where a
// reading is missing).
RowMatrix anglesOfEveryFrame(const RobotModel& robot, const SensorSet& sensors,
                             const JointSources& sources, const ClassicalParameters& p,
                             const Observations& obs);

// One frame of eq. 29: whitened (and robustified) residuals of the markers,
// tendon sensors and non-defining joint sensors at q(p, a, c), and (J not
// null) their Jacobian w.r.t. the regression's parameters in MeasurementModel's
// θ layout (rotation as the left perturbation δ), where the (gain, bias)
// columns of a defining joint sensor hold d/d(a, c). Returns false (nothing
// written) when a defining reading is missing.
bool classicalFrame(const MeasurementModel& model, const JointSources& sources,
                    const ClassicalParameters& params, const NoiseModel& noise,
                    const RobustLoss& loss, const FrameReadings& readings,
                    FrameWorkspace* ws, Eigen::VectorXd* r, Eigen::MatrixXd* J);

}  // namespace stac
