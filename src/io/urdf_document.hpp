// UrdfDocument: a URDF text, read once, checked, with the positions of its
// links and joints.
//
// The one reader of URDF text: the RobotModel loader validates through it
// (and hands urdfdom only text it accepted), and the URDF writer
// (urdf_edit.hpp, urdf_patch.cpp) edits the text at the byte ranges it
// recorded. So anything the loader accepts, the writer can edit, and both
// read the same joints. Errors are InputError(source, line, 0, ...).
//
// What it checks beyond XML (xml_document.hpp): the root is <robot>; links
// and joints (direct children of <robot>, as urdfdom reads them) have names
// without control characters, defined once; a joint's type is known and not
// floating or planar; it has one <parent> and one <child> naming known,
// different links; no link is the child of two joints; revolute and
// prismatic joints have a <limit>; a <mimic> names a joint; <origin> xyz
// and rpy are three numbers; there is one root link and every link hangs
// below it (no loops).
#pragma once

#include <string>
#include <unordered_map>
#include <vector>

#include "io/xml_document.hpp"

namespace stac::io {

struct UrdfLink {
  std::string name;
  int element = -1;  // index into xml().elements()
  int line = 0;
};

struct UrdfJoint {
  std::string name, type, parent, child;
  std::string mimic;  // the mimicked joint, "" if none
  int element = -1;   // its <joint>
  int origin = -1;    // its <origin>, -1 if it has none
  int line = 0;
};

class UrdfDocument {
 public:
  UrdfDocument(std::string text, std::string source);

  const XmlDocument& xml() const { return xml_; }
  const std::string& text() const { return xml_.text(); }
  const std::string& source() const { return xml_.source(); }
  const std::string& robotName() const { return robot_name_; }
  const std::string& rootLink() const { return root_link_; }
  const std::vector<UrdfLink>& links() const { return links_; }
  // In file order (which defines q's order, SPEC §1).
  const std::vector<UrdfJoint>& joints() const { return joints_; }
  // nullptr if there is no such joint.
  const UrdfJoint* joint(const std::string& name) const;

 private:
  void readLinks();
  void readJoints();
  UrdfJoint readJoint(int element) const;
  void checkTree();
  [[noreturn]] void fail(int line, const std::string& what) const;

  XmlDocument xml_;
  std::string robot_name_, root_link_;
  std::vector<UrdfLink> links_;
  std::vector<UrdfJoint> joints_;
  std::unordered_map<std::string, int> link_index_, joint_index_;
};

}  // namespace stac::io
