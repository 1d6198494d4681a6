#include "stac/sensors.hpp"

namespace stac {

const char* groupName(SensorGroup g) {
  switch (g) {
    case SensorGroup::kMarker: return "marker";
    case SensorGroup::kJoint: return "joint";
    case SensorGroup::kTendon: return "tendon";
  }
  return "?";
}

std::optional<SensorGroup> groupFromName(const std::string& name) {
  for (int g = 0; g < kNumSensorGroups; ++g)
    if (name == groupName(static_cast<SensorGroup>(g))) return static_cast<SensorGroup>(g);
  return std::nullopt;
}

std::array<std::string, 3> MarkerConfig::logColumns() const {
  const char* axis[3] = {".x", ".y", ".z"};
  std::array<std::string, 3> out;
  for (int i = 0; i < 3; ++i) out[i] = columns[i].empty() ? name + axis[i] : columns[i];
  return out;
}

const char* groupUnit(SensorGroup g) { return g == SensorGroup::kMarker ? "m" : "raw"; }

int SensorSet::groupSize(SensorGroup g) const {
  switch (g) {
    case SensorGroup::kMarker: return static_cast<int>(markers.size());
    case SensorGroup::kJoint: return static_cast<int>(joint_sensors.size());
    case SensorGroup::kTendon: return static_cast<int>(tendon_sensors.size());
  }
  return 0;
}

const std::string& SensorSet::sensorName(SensorGroup g, int i) const {
  switch (g) {
    case SensorGroup::kMarker: return markers[i].name;
    case SensorGroup::kJoint: return joint_sensors[i].name;
    case SensorGroup::kTendon: break;
  }
  return tendon_sensors[i].name;
}

}  // namespace stac
