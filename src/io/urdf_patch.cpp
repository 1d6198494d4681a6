// A calibrated URDF by editing the text (urdf_patch.hpp).
//
// The text is the robot's own, as its loader read it (io::UrdfDocument), so
// the joints found here are the model's, and only the `xyz` values of the
// chosen joints' <origin> elements are rewritten (io/urdf_edit.hpp).
#include "stac/urdf_patch.hpp"

#include <map>
#include <optional>
#include <stdexcept>

#include "io/urdf_document.hpp"
#include "io/rpy.hpp"
#include "io/urdf_edit.hpp"
#include "stac/error.hpp"

namespace stac {
namespace {

// Every link's rigid body (the nearest link at or above it attached by a
// movable joint, or the root) and its pose in that body's frame.
struct RigidBodies {
  std::vector<int> body, children;
  std::vector<Eigen::Isometry3d> in_body;

  explicit RigidBodies(const RobotModel& robot) {
    const int n = robot.numLinks();
    body.resize(n);
    children.assign(n, 0);
    in_body.assign(n, Eigen::Isometry3d::Identity());
    for (int l = 0; l < n; ++l) {  // topological order: parents first
      const Link& link = robot.links()[l];
      if (link.parent >= 0) ++children[link.parent];
      if (link.parent < 0 || link.movable_joint >= 0) {
        body[l] = l;
      } else {
        body[l] = body[link.parent];
        in_body[l] = in_body[link.parent] * link.origin;
      }
    }
  }
};

// Which link carries each marker (-1: none; the reason in `unplaced`).
class CarrierChoice {
 public:
  CarrierChoice(const RobotModel& robot, const SensorSet& sensors, const RigidBodies& bodies)
      : robot_(robot), sensors_(sensors), bodies_(bodies) {
    const int n = robot.numLinks();
    markers_on_.resize(n);
    for (size_t m = 0; m < sensors.markers.size(); ++m)
      markers_on_[sensors.markers[m].link].push_back(static_cast<int>(m));
    anchor_of_.resize(n);
    for (const TendonSensorConfig& t : sensors.tendon_sensors)
      for (const PathAnchor& a : t.path)
        if (anchor_of_[a.link].empty()) anchor_of_[a.link] = t.name;
  }

  std::vector<int> choose(std::vector<UnplacedMarker>* unplaced) const {
    const int M = static_cast<int>(sensors_.markers.size());
    std::vector<int> carrier(M, -1);
    std::map<int, std::vector<int>> markers_of_carrier;
    for (int m = 0; m < M; ++m) {
      const MarkerConfig& mc = sensors_.markers[m];
      const std::string own = unsuitable(m, mc.link);
      if (own.empty()) {
        carrier[m] = mc.link;
      } else {
        const std::optional<int> named = robot_.linkIndex(mc.name);
        std::string why;
        if (!named)
          why = "the URDF has no link named '" + mc.name + "'";
        else if (*named != mc.link)
          why = unsuitable(m, *named);
        if (named && *named != mc.link && why.empty()) {
          carrier[m] = *named;
        } else {
          unplaced->push_back({mc.name, own + (why.empty() ? "" : ", and " + why)});
          continue;
        }
      }
      markers_of_carrier[carrier[m]].push_back(m);
    }
    // Two markers must not move the same link.
    for (const auto& [L, ms] : markers_of_carrier) {
      if (ms.size() < 2) continue;
      std::string names;
      for (int m : ms) names += (names.empty() ? "'" : ", '") + sensors_.markers[m].name + "'";
      for (int m : ms) {
        carrier[m] = -1;
        unplaced->push_back({sensors_.markers[m].name, "markers " + names +
                                                           " would all move link '" +
                                                           robot_.links()[L].name + "'"});
      }
    }
    return carrier;
  }

 private:
  // Why link L cannot carry marker m ("" if it can).
  std::string unsuitable(int m, int L) const {
    const std::vector<Link>& links = robot_.links();
    const Link& link = links[L];
    const int k = sensors_.markers[m].link;
    const std::string quoted = "link '" + link.name + "'";
    if (link.parent < 0) return quoted + " is the root";
    if (link.movable_joint >= 0)
      return quoted + " is attached by the movable joint '" + link.joint_name + "'";
    if (bodies_.body[L] != bodies_.body[k])
      return quoted + " is not fixed to link '" + links[k].name + "'";
    if (bodies_.children[L] > 0) return quoted + " has child links, which would move with it";
    for (int other : markers_on_[L])
      if (other != m)
        return quoted + " also carries marker '" + sensors_.markers[other].name + "'";
    if (!anchor_of_[L].empty())
      return quoted + " carries an anchor of tendon sensor '" + anchor_of_[L] + "'";
    return "";
  }

  const RobotModel& robot_;
  const SensorSet& sensors_;
  const RigidBodies& bodies_;
  std::vector<std::vector<int>> markers_on_;
  std::vector<std::string> anchor_of_;
};

// The edit must do what it claims: every placed link's origin on its marker,
// in the same body frame (an internal invariant, hence logic_error).
void checkPatched(const RobotModel& robot, const std::string& patched_text,
                  const SensorSet& sensors, const RigidBodies& bodies,
                  const std::vector<int>& carrier, const std::vector<Eigen::Vector3d>& target) {
  const RobotModel patched = RobotModel::fromString(patched_text, robot.sourceName());
  const std::vector<Link>& links = robot.links();
  for (size_t m = 0; m < carrier.size(); ++m) {
    if (carrier[m] < 0) continue;
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    int l = *patched.linkIndex(links[carrier[m]].name);
    for (; patched.links()[l].parent >= 0 && patched.links()[l].movable_joint < 0;
         l = patched.links()[l].parent)
      T = patched.links()[l].origin * T;
    const double err = (T.translation() - target[m]).norm();
    if (patched.links()[l].name != links[bodies.body[carrier[m]]].name ||
        !(err <= 1e-9 * (1.0 + target[m].norm())))
      throw std::logic_error("patchUrdfMarkers: link '" + links[carrier[m]].name +
                             "' missed marker '" + sensors.markers[m].name + "' by " +
                             std::to_string(err) + " m");
  }
}

// The first line where two texts differ (1-based), and that line of each.
int firstDifferentLine(const std::string& a, const std::string& b, std::string* line_a,
                       std::string* line_b) {
  size_t i = 0, start = 0;
  int line = 1;
  for (; i < a.size() && i < b.size() && a[i] == b[i]; ++i)
    if (a[i] == '\n') ++line, start = i + 1;
  auto lineFrom = [start](const std::string& t) {
    std::string l = t.substr(start, std::min(t.find('\n', start), t.size()) - start);
    const size_t first = l.find_first_not_of(" \t\r");
    l = first == std::string::npos ? "" : l.substr(first, l.find_last_not_of(" \t\r") + 1 - first);
    return l.size() > 100 ? l.substr(0, 97) + "..." : l;
  };
  *line_a = lineFrom(a);
  *line_b = lineFrom(b);
  return line;
}

bool correctedJoint(const SensorSet& sensors, int link) {
  for (const JointOriginConfig& c : sensors.joint_origins)
    if (c.link == link) return true;
  return false;
}

// The joint-origin corrections (SPEC §3): each corrected joint's <origin>
// becomes T(urdf origin) · T(correction), as xyz and rpy.
void addOriginEdits(const RobotModel& robot, const SensorSet& sensors,
                    const SensorParameters& theta, std::vector<io::OriginEdit>* edits) {
  for (size_t c = 0; c < sensors.joint_origins.size(); ++c) {
    const OriginCorrection& o = theta.joint_origin[c];
    if (o.xyz.isZero(0) && o.rpy.isZero(0)) continue;
    const Link& link = robot.links()[sensors.joint_origins[c].link];
    const Eigen::Isometry3d T = link.origin * o.transform();
    edits->push_back({link.joint_name, Eigen::Vector3d(T.translation()),
                      toRpy(Eigen::Quaterniond(T.linear()))});
  }
}

}  // namespace

UrdfPatch patchUrdfMarkers(const RobotModel& robot, const SensorSet& sensors,
                           const SensorParameters& theta) {
  const int M = static_cast<int>(sensors.markers.size());
  if (static_cast<int>(theta.marker_position.size()) != M)
    throw std::invalid_argument("patchUrdfMarkers: theta has " +
                                std::to_string(theta.marker_position.size()) +
                                " marker positions for " + std::to_string(M) + " markers");
  if (theta.joint_origin.size() != sensors.joint_origins.size())
    throw std::invalid_argument("patchUrdfMarkers: theta does not match the joint origins");
  const io::UrdfDocument& doc = robot.urdfDocument();
  const RigidBodies bodies(robot);
  UrdfPatch out;
  std::vector<int> carrier = CarrierChoice(robot, sensors, bodies).choose(&out.unplaced);

  std::vector<io::OriginEdit> edits;
  std::vector<Eigen::Vector3d> target(M);  // the marker in its body's frame
  for (int m = 0; m < M; ++m) {
    const int L = carrier[m];
    if (L < 0) continue;
    if (correctedJoint(sensors, L)) {
      out.unplaced.push_back({sensors.markers[m].name,
                              "link '" + robot.links()[L].name +
                                  "' is attached by a joint whose origin is corrected "
                                  "(joint_origins)"});
      carrier[m] = -1;
      continue;
    }
    const int k = sensors.markers[m].link;
    const Link& link = robot.links()[L];
    const Eigen::Vector3d& d = theta.marker_position[m];
    target[m] = bodies.in_body[k] * d;
    // The calibrated point in the frame of the joint's parent link. For the
    // marker's own link this is T_J d exactly (no detour through the body).
    const Eigen::Vector3d xyz =
        L == k ? Eigen::Vector3d(link.origin * d)
               : Eigen::Vector3d(bodies.in_body[link.parent].inverse() * target[m]);
    const io::UrdfJoint* joint = doc.joint(link.joint_name);
    if (!joint)  // the model was built from this very document
      throw std::logic_error("patchUrdfMarkers: joint '" + link.joint_name +
                             "' of the robot model is not in its own URDF");
    out.placed.push_back({sensors.markers[m].name, link.name, link.joint_name, joint->line});
    if (xyz != link.origin.translation()) edits.push_back({link.joint_name, xyz, std::nullopt});
  }
  const size_t marker_edits = edits.size();
  addOriginEdits(robot, sensors, theta, &edits);
  out.urdf = io::withJointOrigins(doc, edits);
  if (marker_edits > 0) checkPatched(robot, out.urdf, sensors, bodies, carrier, target);
  return out;
}

UrdfPatch patchUrdfMarkers(const std::string& urdf_text, const RobotModel& robot,
                           const SensorSet& sensors, const SensorParameters& theta,
                           const std::string& source_name) {
  // Read as the loader reads, so a broken text gets the loader's error.
  const io::UrdfDocument doc(urdf_text, source_name);
  if (urdf_text != robot.urdfText()) {
    std::string here, there;
    const int line = firstDifferentLine(urdf_text, robot.urdfText(), &here, &there);
    throw InputError(source_name, line, 0,
                     "not the text the robot model was loaded from (" + robot.sourceName() +
                         "): line " + std::to_string(line) + " reads '" + here +
                         "' here but '" + there + "' there");
  }
  return patchUrdfMarkers(robot, sensors, theta);
}

}  // namespace stac
