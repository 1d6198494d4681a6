// `--joint-origins` (SPEC §4): zero corrections added to a seed.
#include <algorithm>
#include <optional>
#include <stdexcept>

#include "stac/sensors_file.hpp"

namespace stac {
void addJointOrigins(const RobotModel& model, const std::vector<std::string>& joints,
                     SensorsFile* file) {
  std::vector<std::string> names;
  if (joints.size() == 1 && joints[0] == "all") {
    for (const MovableJoint& mj : model.movableJoints())
      if (!mj.is_mimic) names.push_back(mj.name);
  } else {
    names = joints;
  }
  SensorSet& s = file->sensors;
  for (const std::string& name : names) {
    const std::optional<int> found = model.linkOfJoint(name);
    if (!found)
      throw std::invalid_argument("unknown joint '" + name + "' (not in " + model.sourceName() +
                                  ")");
    const int link = *found;
    const bool listed = std::any_of(s.joint_origins.begin(), s.joint_origins.end(),
                                    [&](const JointOriginConfig& c) { return c.link == link; });
    if (listed) continue;
    s.joint_origins.push_back({name, link, FixedOrigin{}});
    file->theta.joint_origin.push_back(OriginCorrection{});
  }
}

}  // namespace stac
