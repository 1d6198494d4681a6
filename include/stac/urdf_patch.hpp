// A calibrated URDF: the marker links of a URDF moved to the calibrated
// marker positions, by editing the text so that everything else (comments,
// formatting, attribute order) stays byte for byte as it was.
//
//   UrdfPatch p = patchUrdfMarkers(robot, sensors, theta);
//   // p.urdf: the new text; p.unplaced: markers it had no link for.
//
// Which link carries a marker (the URDF idiom of SPEC §3: a link named like
// the marker, or the marker's own `link:`, attached by a fixed joint):
//   1. the marker's `link:` itself, if a fixed joint attaches it;
//   2. otherwise a link named exactly like the marker, attached by a fixed
//      joint (or a chain of them) to the same rigid body as the marker's
//      `link:`.
// The link must be the marker's alone: no other marker on it, no tendon
// anchor on it, no child links (they would all move with it). Its joint's
// origin xyz becomes the calibrated point in the joint's parent frame (rpy
// kept), so the link's origin lands on the marker; a joint without <origin>
// gets one. Numbers are written with the fewest digits that read back
// exactly. With the calibrated URDF the marker sits at [0, 0, 0] of that
// link.
#pragma once

#include <string>
#include <vector>

#include "stac/robot_model.hpp"
#include "stac/sensors.hpp"

namespace stac {

struct PlacedMarker {
  std::string marker;
  std::string link;   // the URDF link now at the calibrated position
  std::string joint;  // the fixed joint whose origin was written
  int line = 0;       // that joint's line in the input text
};

struct UnplacedMarker {
  std::string marker;
  std::string reason;  // one human sentence
};

struct UrdfPatch {
  std::string urdf;  // the patched text
  std::vector<PlacedMarker> placed;
  std::vector<UnplacedMarker> unplaced;
};

// Patches the text `robot` was loaded from (robot.urdfText()), as the loader
// read it: any URDF the loader accepts can be patched. Markers whose
// position already equals the joint origin are placed without a text change.
// Throws std::invalid_argument if theta does not match sensors.
UrdfPatch patchUrdfMarkers(const RobotModel& robot, const SensorSet& sensors,
                           const SensorParameters& theta);

// The same, for a caller that holds the text: `urdf_text` must be, byte for
// byte, the text `robot` was loaded from (source_name names it in errors).
// Throws InputError(source_name, line, ...) if it is not a URDF the loader
// would accept, or where it first differs from the robot's text.
UrdfPatch patchUrdfMarkers(const std::string& urdf_text, const RobotModel& robot,
                           const SensorSet& sensors, const SensorParameters& theta,
                           const std::string& source_name = "<string>");

}  // namespace stac
