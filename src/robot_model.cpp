// URDF -> RobotModel (and its KDL tree), our own conversion.
//
// Two readers look at the same text: TinyXML (which urdfdom itself uses) for
// what urdfdom's ModelInterface loses or cannot report — the order joints
// appear in the file (it defines q's order, SPEC §1), line numbers for error
// messages, and validation before urdfdom so that our errors name the file
// and the line — and urdfdom for the model content itself.
#include "stac/robot_model.hpp"

#include <tinyxml.h>
#include <urdf_parser/urdf_parser.h>

#include <cmath>
#include <functional>
#include <kdl/frames.hpp>
#include <kdl/joint.hpp>
#include <kdl/segment.hpp>
#include <limits>
#include <map>
#include <fstream>
#include <set>
#include <sstream>

#include "stac/error.hpp"

namespace stac {
namespace {

struct XmlJoint {
  std::string name, type, parent, child, mimic;
  int line = 0;
};

struct XmlRobot {
  std::string name;
  std::vector<std::pair<std::string, int>> links;  // name, line
  std::vector<XmlJoint> joints;                    // file order
};

std::string attr(const TiXmlElement* e, const char* name) {
  const char* v = e->Attribute(name);
  return v ? std::string(v) : std::string();
}

// Parses the XML structure and checks everything we can name a line for.
XmlRobot scanUrdf(const std::string& text, const std::string& source) {
  TiXmlDocument doc;
  doc.Parse(text.c_str());
  if (doc.Error()) {
    throw InputError(source, doc.ErrorRow(), doc.ErrorCol(),
                     std::string("malformed XML: ") + doc.ErrorDesc());
  }
  const TiXmlElement* robot = doc.RootElement();
  if (!robot || std::string(robot->Value()) != "robot") {
    throw InputError(source, robot ? robot->Row() : 0, 0,
                     "not a URDF: the root element must be <robot>");
  }
  XmlRobot out;
  out.name = attr(robot, "name");
  std::set<std::string> link_names, joint_names;
  for (const TiXmlElement* e = robot->FirstChildElement("link"); e;
       e = e->NextSiblingElement("link")) {
    std::string name = attr(e, "name");
    if (name.empty())
      throw InputError(source, e->Row(), 0, "<link> without a name");
    if (!link_names.insert(name).second)
      throw InputError(source, e->Row(), 0, "link '" + name + "' defined twice");
    out.links.emplace_back(name, e->Row());
  }
  if (out.links.empty())
    throw InputError(source, robot->Row(), 0, "empty robot: no <link> elements");

  std::set<std::string> children;
  for (const TiXmlElement* e = robot->FirstChildElement("joint"); e;
       e = e->NextSiblingElement("joint")) {
    XmlJoint j;
    j.name = attr(e, "name");
    j.type = attr(e, "type");
    j.line = e->Row();
    if (j.name.empty())
      throw InputError(source, j.line, 0, "<joint> without a name");
    if (!joint_names.insert(j.name).second)
      throw InputError(source, j.line, 0, "joint '" + j.name + "' defined twice");
    if (j.type == "floating" || j.type == "planar") {
      throw InputError(source, j.line, 0,
                       "joint '" + j.name + "' is " + j.type +
                           ": floating and planar joints are not supported "
                           "(the base must be fixed in the world)");
    }
    if (j.type != "revolute" && j.type != "continuous" &&
        j.type != "prismatic" && j.type != "fixed") {
      throw InputError(source, j.line, 0,
                       "joint '" + j.name + "' has unknown type '" + j.type + "'");
    }
    const TiXmlElement* p = e->FirstChildElement("parent");
    const TiXmlElement* c = e->FirstChildElement("child");
    j.parent = p ? attr(p, "link") : "";
    j.child = c ? attr(c, "link") : "";
    if (j.parent.empty() || j.child.empty())
      throw InputError(source, j.line, 0,
                       "joint '" + j.name + "' lacks a <parent> or <child> link");
    for (const std::string* l : {&j.parent, &j.child}) {
      if (!link_names.count(*l))
        throw InputError(source, j.line, 0,
                         "joint '" + j.name + "' names unknown link '" + *l + "'");
    }
    if (!children.insert(j.child).second)
      throw InputError(source, j.line, 0,
                       "link '" + j.child + "' is the child of two joints");
    if ((j.type == "revolute" || j.type == "prismatic") &&
        !e->FirstChildElement("limit")) {
      throw InputError(source, j.line, 0,
                       "joint '" + j.name + "' is " + j.type +
                           " but has no <limit>");
    }
    if (const TiXmlElement* m = e->FirstChildElement("mimic")) {
      j.mimic = attr(m, "joint");
      if (j.mimic.empty())
        throw InputError(source, m->Row(), 0,
                         "<mimic> of joint '" + j.name + "' names no joint");
    }
    out.joints.push_back(j);
  }
  for (const XmlJoint& j : out.joints) {
    if (j.mimic.empty()) continue;
    if (!joint_names.count(j.mimic))
      throw InputError(source, j.line, 0,
                       "joint '" + j.name + "' mimics unknown joint '" +
                           j.mimic + "'");
  }
  std::vector<std::string> roots;
  for (const auto& l : out.links)
    if (!children.count(l.first)) roots.push_back(l.first);
  if (roots.size() != 1) {
    std::string list;
    for (const auto& r : roots) list += (list.empty() ? "" : ", ") + r;
    throw InputError(source, robot->Row(), 0,
                     roots.empty() ? "the links form a loop: no root link"
                                   : "more than one root link: " + list);
  }
  return out;
}

Eigen::Isometry3d toEigen(const urdf::Pose& p) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = Eigen::Quaterniond(p.rotation.w, p.rotation.x, p.rotation.y,
                                  p.rotation.z)
                   .normalized()
                   .toRotationMatrix();
  T.translation() = Eigen::Vector3d(p.position.x, p.position.y, p.position.z);
  return T;
}

KDL::Frame toKdl(const Eigen::Isometry3d& T) {
  const Eigen::Matrix3d& R = T.linear();
  return KDL::Frame(
      KDL::Rotation(R(0, 0), R(0, 1), R(0, 2), R(1, 0), R(1, 1), R(1, 2),
                    R(2, 0), R(2, 1), R(2, 2)),
      KDL::Vector(T.translation().x(), T.translation().y(),
                  T.translation().z()));
}

}  // namespace

class UrdfLoader {
 public:
  static RobotModel load(const std::string& text, const std::string& source);
};

RobotModel UrdfLoader::load(const std::string& text, const std::string& source) {
  const XmlRobot xml = scanUrdf(text, source);
  urdf::ModelInterfaceSharedPtr urdf = urdf::parseURDF(text);
  if (!urdf) {
    throw InputError(source, "urdfdom could not parse this URDF (see its "
                             "message above for the cause)");
  }
  std::map<std::string, int> joint_line;
  for (const XmlJoint& j : xml.joints) joint_line[j.name] = j.line;

  RobotModel m;
  m.name_ = xml.name;
  m.source_ = source;

  // Movable joints in file order; independent ones define q's order.
  for (const XmlJoint& xj : xml.joints) {
    m.joint_names_.push_back(xj.name);
    if (xj.type == "fixed") continue;
    const urdf::JointConstSharedPtr uj = urdf->getJoint(xj.name);
    MovableJoint mj;
    mj.name = xj.name;
    mj.type = xj.type == "prismatic"    ? JointType::kPrismatic
              : xj.type == "continuous" ? JointType::kContinuous
                                        : JointType::kRevolute;
    if (uj->limits && mj.type != JointType::kContinuous) {
      mj.lower = uj->limits->lower;
      mj.upper = uj->limits->upper;
      mj.has_limits = true;
    }
    m.movable_by_name_[mj.name] = static_cast<int>(m.movable_.size());
    m.movable_.push_back(mj);
  }
  // Mimic: resolve chains to the independent master.
  std::function<void(int, int)> resolve = [&](int idx, int depth) {
    MovableJoint& mj = m.movable_[idx];
    const urdf::JointConstSharedPtr uj = urdf->getJoint(mj.name);
    if (!uj->mimic) return;
    if (depth > static_cast<int>(m.movable_.size()))
      throw InputError(source, joint_line[mj.name], 0,
                       "mimic joints form a cycle through '" + mj.name + "'");
    auto it = m.movable_by_name_.find(uj->mimic->joint_name);
    if (it == m.movable_by_name_.end())
      throw InputError(source, joint_line[mj.name], 0,
                       "joint '" + mj.name + "' mimics '" +
                           uj->mimic->joint_name + "', which is not movable");
    mj.is_mimic = true;
    mj.multiplier = uj->mimic->multiplier;
    mj.offset = uj->mimic->offset;
    mj.q_index = it->second;  // temporarily: the direct master (movable idx)
    (void)depth;
  };
  for (int i = 0; i < static_cast<int>(m.movable_.size()); ++i) resolve(i, 0);
  for (int i = 0; i < static_cast<int>(m.movable_.size()); ++i) {
    if (!m.movable_[i].is_mimic) {
      m.movable_[i].q_index = static_cast<int>(m.q_joints_.size());
      m.q_by_name_[m.movable_[i].name] = m.movable_[i].q_index;
      m.q_joints_.push_back(i);
    }
  }
  for (int i = 0; i < static_cast<int>(m.movable_.size()); ++i) {
    MovableJoint& mj = m.movable_[i];
    if (!mj.is_mimic) continue;
    double mult = mj.multiplier, off = mj.offset;
    int master = mj.q_index;  // movable index of the direct master
    int steps = 0;
    while (m.movable_[master].is_mimic) {
      if (++steps > static_cast<int>(m.movable_.size()))
        throw InputError(source, joint_line[mj.name], 0,
                         "mimic joints form a cycle through '" + mj.name + "'");
      const urdf::JointConstSharedPtr up =
          urdf->getJoint(m.movable_[master].name);
      // angle = mult * (mult_p * q + off_p) + off
      off = mult * up->mimic->offset + off;
      mult = mult * up->mimic->multiplier;
      master = m.movable_by_name_.at(up->mimic->joint_name);
    }
    mj.multiplier = mult;
    mj.offset = off;
    mj.q_index = -1 - master;  // resolved below, once masters have q indices
  }
  for (MovableJoint& mj : m.movable_)
    if (mj.is_mimic) mj.q_index = m.movable_[-1 - mj.q_index].q_index;

  // Links in depth-first order from the root, children in file order.
  std::map<std::string, std::vector<const XmlJoint*>> children_of;
  for (const XmlJoint& j : xml.joints) children_of[j.parent].push_back(&j);
  const std::string root = urdf->getRoot()->name;
  KDL::Tree tree(root);
  std::vector<std::pair<std::string, const XmlJoint*>> stack{{root, nullptr}};
  std::vector<int> kdl_nr(m.movable_.size(), -1);
  while (!stack.empty()) {
    auto [name, xj] = stack.back();
    stack.pop_back();
    Link link;
    link.name = name;
    if (xj) {
      const urdf::JointConstSharedPtr uj = urdf->getJoint(xj->name);
      link.parent = m.link_by_name_.at(xj->parent);
      link.origin = toEigen(uj->parent_to_joint_origin_transform);
      link.joint_name = xj->name;
      KDL::Joint kj(xj->name, KDL::Joint::Fixed);
      if (xj->type != "fixed") {
        Eigen::Vector3d axis(uj->axis.x, uj->axis.y, uj->axis.z);
        if (axis.norm() < 1e-12)
          throw InputError(source, xj->line, 0,
                           "joint '" + xj->name + "' has a zero axis");
        link.axis = axis.normalized();
        link.movable_joint = m.movable_by_name_.at(xj->name);
        m.movable_[link.movable_joint].child_link =
            static_cast<int>(m.links_.size());
        const KDL::Frame F = toKdl(link.origin);
        const KDL::Vector a =
            F.M * KDL::Vector(link.axis.x(), link.axis.y(), link.axis.z());
        kj = KDL::Joint(xj->name, F.p, a,
                        xj->type == "prismatic" ? KDL::Joint::TransAxis
                                                : KDL::Joint::RotAxis);
      }
      tree.addSegment(KDL::Segment(name, kj, toKdl(link.origin)), xj->parent);
    }
    m.link_by_name_[name] = static_cast<int>(m.links_.size());
    m.links_.push_back(link);
    auto it = children_of.find(name);
    if (it != children_of.end())
      for (auto c = it->second.rbegin(); c != it->second.rend(); ++c)
        stack.emplace_back((*c)->child, *c);
  }
  // KDL numbers movable segments in the order they were added.
  for (const auto& kv : tree.getSegments()) {
    const KDL::Segment& seg = kv.second.segment;
    if (seg.getJoint().getType() == KDL::Joint::Fixed) continue;
    kdl_nr[m.movable_by_name_.at(seg.getJoint().getName())] =
        static_cast<int>(kv.second.q_nr);
  }
  m.kdl_tree_ = tree;
  m.kdl_q_nr_ = kdl_nr;

  m.support_.resize(m.links_.size());
  for (int i = 0; i < m.numLinks(); ++i) {
    std::vector<int> chain;
    for (int l = i; l >= 0; l = m.links_[l].parent)
      if (m.links_[l].movable_joint >= 0) chain.push_back(m.links_[l].movable_joint);
    m.support_[i].assign(chain.rbegin(), chain.rend());
  }
  const double inf = std::numeric_limits<double>::infinity();
  m.lower_ = Eigen::VectorXd::Constant(m.dof(), -inf);
  m.upper_ = Eigen::VectorXd::Constant(m.dof(), inf);
  for (int i = 0; i < m.dof(); ++i) {
    const MovableJoint& mj = m.movable_[m.q_joints_[i]];
    if (mj.has_limits) {
      m.lower_[i] = mj.lower;
      m.upper_[i] = mj.upper;
    }
  }
  return m;
}

RobotModel RobotModel::fromFile(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw InputError(path, "cannot open the URDF file");
  std::stringstream text;
  text << f.rdbuf();
  return UrdfLoader::load(text.str(), path);
}

RobotModel RobotModel::fromString(const std::string& urdf_xml,
                                  const std::string& source_name) {
  return UrdfLoader::load(urdf_xml, source_name);
}

const std::string& RobotModel::qName(int i) const {
  return movable_[q_joints_.at(i)].name;
}

std::optional<int> RobotModel::qIndex(const std::string& joint_name) const {
  auto it = q_by_name_.find(joint_name);
  if (it == q_by_name_.end()) return std::nullopt;
  return it->second;
}

std::optional<int> RobotModel::movableJointIndex(
    const std::string& joint_name) const {
  auto it = movable_by_name_.find(joint_name);
  if (it == movable_by_name_.end()) return std::nullopt;
  return it->second;
}

std::optional<int> RobotModel::linkIndex(const std::string& link_name) const {
  auto it = link_by_name_.find(link_name);
  if (it == link_by_name_.end()) return std::nullopt;
  return it->second;
}

void RobotModel::expand(const Eigen::VectorXd& q,
                        Eigen::VectorXd* movable_q) const {
  movable_q->resize(static_cast<Eigen::Index>(movable_.size()));
  for (size_t i = 0; i < movable_.size(); ++i) {
    const MovableJoint& mj = movable_[i];
    (*movable_q)[i] = mj.multiplier * q[mj.q_index] + mj.offset;
  }
}

}  // namespace stac
