// A joint-angles log (as stac_calib --joint-angles writes it) read back as q.
#include <cmath>
#include <optional>

#include "stac/error.hpp"
#include "stac/log.hpp"
#include "stac/robot_model.hpp"

namespace stac {

Eigen::VectorXd firstJointAngles(const Log& log, const RobotModel& robot) {
  const int line = log.header_line;
  std::vector<int> column_of(robot.dof(), -1);
  for (size_t c = 0; c < log.columns.size(); ++c) {
    const std::optional<int> i = robot.qIndex(log.columns[c]);
    if (!i) {
      const std::string why = robot.movableJointIndex(log.columns[c])
                                  ? "' is a mimic follower, not a joint of q"
                                  : "' is not a joint of the robot";
      throw InputError(log.path, line, 0, "joint-angle column '" + log.columns[c] + why);
    }
    column_of[*i] = static_cast<int>(c);
  }
  std::string missing;
  for (int i = 0; i < robot.dof(); ++i)
    if (column_of[i] < 0) missing += (missing.empty() ? "" : ", ") + robot.qName(i);
  if (!missing.empty())
    throw InputError(log.path, line, 0, "joint-angle columns missing for: " + missing);
  if (log.numFrames() == 0) throw InputError(log.path, line, 0, "no joint angles (no data rows)");
  const int row_line = log.line_of_frame.empty() ? line + 1 : log.line_of_frame[0];
  Eigen::VectorXd q(robot.dof());
  for (int i = 0; i < robot.dof(); ++i) {
    q[i] = log.values(0, column_of[i]);
    if (std::isnan(q[i]))
      throw InputError(log.path, row_line, 0,
                       "missing joint angle for " + robot.qName(i) + " (column '" +
                           log.columns[column_of[i]] + "')");
  }
  return q;
}

}  // namespace stac
