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

const char* groupUnit(SensorGroup g) { return g == SensorGroup::kMarker ? "m" : "raw"; }

}  // namespace stac
