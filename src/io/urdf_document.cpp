// The URDF layer over the strict XML reader (urdf_document.hpp).
#include "io/urdf_document.hpp"

#include <urdf_model/pose.h>

#include <exception>
#include <set>

#include "stac/error.hpp"

namespace stac::io {
namespace {

bool isControl(char c) {
  const unsigned char u = static_cast<unsigned char>(c);
  return u < 0x20 || u == 0x7f;
}

// A name as it can be printed: control characters as \xNN.
std::string printable(const std::string& name) {
  std::string out;
  const char* digits = "0123456789abcdef";
  for (char c : name) {
    const unsigned char u = static_cast<unsigned char>(c);
    if (isControl(c))
      out += std::string("\\x") + digits[u >> 4] + digits[u & 15];
    else
      out += c;
  }
  return out;
}

}  // namespace

UrdfDocument::UrdfDocument(std::string text, std::string source)
    : xml_(std::move(text), std::move(source)) {
  const XmlElement& robot = xml_.root();
  if (robot.name != "robot") fail(robot.line, "not a URDF: the root element must be <robot>");
  if (const XmlAttribute* a = robot.attribute("name")) robot_name_ = a->value;
  readLinks();
  readJoints();
  checkTree();
}

const UrdfJoint* UrdfDocument::joint(const std::string& name) const {
  auto it = joint_index_.find(name);
  return it == joint_index_.end() ? nullptr : &joints_[it->second];
}

void UrdfDocument::fail(int line, const std::string& what) const {
  throw InputError(source(), line, 0, what);
}

namespace {

// A name attribute's value: present, non-empty, without control characters
// (tabs and line breaks included: TinyXML keeps them raw where XML would
// turn them into spaces, so two readers could see two different names).
// `what` names the element for the message, e.g. "<joint>".
std::string nameOf(const XmlElement& e, const char* attribute, const std::string& what,
                   const std::string& source) {
  const XmlAttribute* a = e.attribute(attribute);
  if (!a || a->value.empty()) throw InputError(source, e.line, 0, what + " without a name");
  for (char c : a->value) {
    if (!isControl(c)) continue;
    const std::string code = printable(std::string(1, c)).substr(2);
    throw InputError(source, e.line, 0,
                     what + " name '" + printable(a->value) +
                         "' contains a control character (0x" + code + ")");
  }
  return a->value;
}

}  // namespace

void UrdfDocument::readLinks() {
  const XmlElement& robot = xml_.root();
  for (int c : robot.children) {
    const XmlElement& e = xml_.elements()[c];
    if (e.name != "link") continue;
    const std::string name = nameOf(e, "name", "<link>", source());
    if (!link_index_.emplace(name, static_cast<int>(links_.size())).second)
      fail(e.line, "link '" + name + "' defined twice");
    links_.push_back({name, c, e.line});
  }
  if (links_.empty()) fail(robot.line, "empty robot: no <link> elements");
}

void UrdfDocument::readJoints() {
  std::set<std::string> children;
  for (int c : xml_.root().children) {
    if (xml_.elements()[c].name != "joint") continue;
    UrdfJoint j = readJoint(c);
    if (!joint_index_.emplace(j.name, static_cast<int>(joints_.size())).second)
      fail(j.line, "joint '" + j.name + "' defined twice");
    if (!children.insert(j.child).second)
      fail(j.line, "link '" + j.child + "' is the child of two joints");
    joints_.push_back(std::move(j));
  }
  for (const UrdfJoint& j : joints_) {
    if (!j.mimic.empty() && !joint_index_.count(j.mimic))
      fail(j.line, "joint '" + j.name + "' mimics unknown joint '" + j.mimic + "'");
  }
}

UrdfJoint UrdfDocument::readJoint(int element) const {
  const XmlElement& e = xml_.elements()[element];
  UrdfJoint j;
  j.element = element;
  j.line = e.line;
  j.name = nameOf(e, "name", "<joint>", source());
  if (const XmlAttribute* a = e.attribute("type")) j.type = a->value;
  const std::string quoted = "joint '" + printable(j.name) + "'";
  if (j.type == "floating" || j.type == "planar")
    fail(j.line, quoted + " is " + j.type +
                     ": floating and planar joints are not supported "
                     "(the base must be fixed in the world)");
  if (j.type != "revolute" && j.type != "continuous" && j.type != "prismatic" &&
      j.type != "fixed")
    fail(j.line, quoted + " has unknown type '" + j.type + "'");
  // urdfdom reads the first of each; a second one would be silently ignored
  // by it and could be the one a reader of the file (or the writer) takes.
  std::set<std::string> seen;
  for (int c : e.children) {
    const XmlElement& child = xml_.elements()[c];
    for (const char* unique : {"parent", "child", "origin", "axis", "limit", "mimic"})
      if (child.name == unique && !seen.insert(unique).second)
        fail(child.line, quoted + " has a second <" + child.name + ">");
  }
  const int parent = xml_.firstChild(element, "parent");
  const int child = xml_.firstChild(element, "child");
  if (parent < 0 || child < 0 || !xml_.elements()[parent].attribute("link") ||
      !xml_.elements()[child].attribute("link"))
    fail(j.line, quoted + " lacks a <parent> or <child> link");
  j.parent = nameOf(xml_.elements()[parent], "link", "<parent> link", source());
  j.child = nameOf(xml_.elements()[child], "link", "<child> link", source());
  for (const std::string* l : {&j.parent, &j.child})
    if (!link_index_.count(*l)) fail(j.line, quoted + " names unknown link '" + *l + "'");
  if (j.parent == j.child)
    fail(j.line, quoted + " has link '" + j.parent + "' as both its parent and its child");
  if ((j.type == "revolute" || j.type == "prismatic") && xml_.firstChild(element, "limit") < 0)
    fail(j.line, quoted + " is " + j.type + " but has no <limit>");
  if (const int m = xml_.firstChild(element, "mimic"); m >= 0) {
    const XmlElement& mimic = xml_.elements()[m];
    if (!mimic.attribute("joint") || mimic.attribute("joint")->value.empty())
      fail(mimic.line, "<mimic> of " + quoted + " names no joint");
    j.mimic = nameOf(mimic, "joint", "<mimic> joint", source());
  }
  j.origin = xml_.firstChild(element, "origin");
  if (j.origin >= 0) {
    // With urdfdom's own parser, so that the two cannot disagree.
    const XmlElement& origin = xml_.elements()[j.origin];
    for (const char* key : {"xyz", "rpy"}) {
      const XmlAttribute* a = origin.attribute(key);
      if (!a) continue;
      try {
        urdf::Vector3().init(a->value);
      } catch (const std::exception&) {
        fail(origin.line, "<origin " + std::string(key) + "=\"" + printable(a->value) +
                              "\"> of " + quoted + " is not three numbers");
      }
    }
  }
  return j;
}

// One root, and every link reachable from it: a joint loop away from the
// root (a -> b -> a) leaves the root unique but cuts those links off, and the
// model would silently lose them.
void UrdfDocument::checkTree() {
  std::set<std::string> children;
  for (const UrdfJoint& j : joints_) children.insert(j.child);
  std::vector<std::string> roots;
  for (const UrdfLink& l : links_)
    if (!children.count(l.name)) roots.push_back(l.name);
  if (roots.size() != 1) {
    std::string list;
    for (const auto& r : roots) list += (list.empty() ? "" : ", ") + r;
    fail(xml_.root().line, roots.empty() ? "the links form a loop: no root link"
                                         : "more than one root link: " + list);
  }
  root_link_ = roots.front();
  std::unordered_map<std::string, std::vector<const UrdfJoint*>> below;
  for (const UrdfJoint& j : joints_) below[j.parent].push_back(&j);
  std::set<std::string> reached{root_link_};
  std::vector<std::string> stack{root_link_};
  while (!stack.empty()) {
    const std::string l = stack.back();
    stack.pop_back();
    for (const UrdfJoint* j : below[l])
      if (reached.insert(j->child).second) stack.push_back(j->child);
  }
  for (const UrdfLink& l : links_)
    if (!reached.count(l.name))
      fail(l.line, "link '" + l.name + "' is not connected to the root link '" + root_link_ +
                       "': the joints above it form a loop");
}

}  // namespace stac::io
