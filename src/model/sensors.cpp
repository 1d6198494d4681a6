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

std::array<std::string, 3> MarkerConfig::logColumns() const {
  const char* axis[3] = {".x", ".y", ".z"};
  std::array<std::string, 3> out;
  for (int i = 0; i < 3; ++i) out[i] = columns[i].empty() ? name + axis[i] : columns[i];
  return out;
}

const char* groupUnit(SensorGroup g) { return g == SensorGroup::kMarker ? "m" : "raw"; }

}  // namespace stac
