#include "fuzz_targets.hpp"

#include <optional>
#include <stdexcept>
#include <string>

#include "stac/error.hpp"
#include "stac/log.hpp"
#include "stac/robot_model.hpp"
#include "stac/sensors_file.hpp"
#include "stac/urdf_patch.hpp"

#ifndef STAC_DATA_DIR
#error "STAC_DATA_DIR must name the repository's data/ folder"
#endif

namespace stac::fuzz {

namespace {
const RobotModel& hand() {
  static const RobotModel robot = RobotModel::fromFile(STAC_DATA_DIR "/hand24.urdf");
  return robot;
}

std::string text(const std::uint8_t* data, std::size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

// A marker named like each link, on it, placed 1 mm off its origin.
void markerOnEveryLink(const RobotModel& robot, SensorSet* sensors, SensorParameters* theta) {
  for (int l = 0; l < robot.numLinks(); ++l) {
    MarkerConfig m;
    m.name = robot.links()[l].name;
    m.link_name = m.name;
    m.link = l;
    sensors->markers.push_back(m);
    theta->marker_position.push_back(Eigen::Vector3d(1e-3, -2e-3, 0.5));
  }
}
}  // namespace

void logReader(const std::uint8_t* data, std::size_t size) {
  try {
    const Log log = parseLog(text(data, size), "fuzz.csv");
    requireDataRows(log);
    const SensorsFile sf = inferSensorsFromLog(log, hand());
    (void)bindLog(log, sf.sensors, "inferred", 1.0);
  } catch (const InputError&) {
  }
}

void sensorsReader(const std::uint8_t* data, std::size_t size) {
  SensorsFile sf;
  try {
    sf = parseSensorsYaml(text(data, size), "fuzz.yaml", hand());
  } catch (const InputError&) {
    return;
  }
  // What was accepted writes back to an accepted file.
  (void)parseSensorsYaml(sensorsToYaml(sf.sensors, sf.theta), "written.yaml", hand());
}

void urdfLoader(const std::uint8_t* data, std::size_t size) {
  try {
    (void)RobotModel::fromString(text(data, size), "fuzz.urdf");
  } catch (const InputError&) {
  }
}

void urdfPatcher(const std::uint8_t* data, std::size_t size) {
  const std::string urdf = text(data, size);
  std::optional<RobotModel> robot;
  try {
    robot.emplace(RobotModel::fromString(urdf, "fuzz.urdf"));
  } catch (const InputError&) {
    return;
  }
  SensorSet sensors;
  SensorParameters theta;
  markerOnEveryLink(*robot, &sensors, &theta);
  // No InputError from here: the loader accepted the text.
  const UrdfPatch patch = patchUrdfMarkers(urdf, *robot, sensors, theta, "fuzz.urdf");
  (void)RobotModel::fromString(patch.urdf, "patched.urdf");
}

}  // namespace stac::fuzz
