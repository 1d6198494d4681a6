// URDF -> RobotModel (and its KDL tree), our own conversion (the model's
// queries are model/robot_model.cpp).
//
// The text is read once, by io::UrdfDocument: it checks everything we can
// name a line for, and keeps what urdfdom's ModelInterface loses — the order
// joints appear in the file (it defines q's order, SPEC §1) and where each
// joint is, for errors and for writing a calibrated URDF later. urdfdom then
// reads the same text, which the document has already accepted, for the
// model content itself (SPEC §1 names it for the URDF semantics).
#include "stac/robot_model.hpp"

#include <console_bridge/console.h>
#include <urdf_parser/urdf_parser.h>

#include <cmath>
#include <fstream>
#include <kdl/frames.hpp>
#include <kdl/joint.hpp>
#include <kdl/segment.hpp>
#include <limits>
#include <map>
#include <mutex>
#include <sstream>

#include "io/urdf_document.hpp"
#include "stac/error.hpp"

namespace stac {
namespace {

using io::UrdfJoint;

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

// urdfdom reports through console_bridge, whose default handler prints to
// stderr (a dozen "material ... undefined" lines for a robot's URDF): the
// library never prints, and what urdfdom refuses we report ourselves (the
// document's checks, or the error below). console_bridge's handler is
// process-wide, so the library holds no handler of its own: this guard
// swaps in one that keeps urdfdom's errors (for our own message) and drops
// the rest, for the parse only, and then puts back whatever was there (the
// default, or the application's own). The mutex keeps two of our threads
// from saving each other's swap as "the previous handler".
class QuietUrdfdom {
 public:
  QuietUrdfdom() : lock_(mutex()), previous_(console_bridge::getOutputHandler()) {
    console_bridge::useOutputHandler(&keep_);
  }
  const std::string& errors() const { return keep_.errors; }
  ~QuietUrdfdom() { console_bridge::useOutputHandler(previous_); }
  QuietUrdfdom(const QuietUrdfdom&) = delete;
  QuietUrdfdom& operator=(const QuietUrdfdom&) = delete;

 private:
  struct KeepErrors : console_bridge::OutputHandler {
    void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
      if (level < console_bridge::CONSOLE_BRIDGE_LOG_ERROR) return;
      errors += (errors.empty() ? "" : "; ") + text;
    }
    std::string errors;
  };
  static std::mutex& mutex() {
    static std::mutex m;
    return m;
  }
  std::lock_guard<std::mutex> lock_;
  console_bridge::OutputHandler* previous_;
  KeepErrors keep_;
};

// urdfdom's model, or an InputError with urdfdom's own errors.
urdf::ModelInterfaceSharedPtr parseQuietly(const std::string& text, const std::string& source) {
  const QuietUrdfdom quiet;
  urdf::ModelInterfaceSharedPtr urdf = urdf::parseURDF(text);
  if (!urdf)
    throw InputError(source, "urdfdom could not parse this URDF" +
                                 (quiet.errors().empty() ? "" : ": " + quiet.errors()));
  return urdf;
}

}  // namespace

class UrdfLoader {
 public:
  static RobotModel load(std::string text, const std::string& source);

 private:
  using Urdf = urdf::ModelInterface;
  static void readJoints(RobotModel& m, const io::UrdfDocument& doc, const Urdf& urdf);
  static void resolveMimics(RobotModel& m, const io::UrdfDocument& doc, const Urdf& urdf);
  static void buildTree(RobotModel& m, const io::UrdfDocument& doc, const Urdf& urdf);
  static void finish(RobotModel& m);
};

RobotModel UrdfLoader::load(std::string text, const std::string& source) {
  auto doc = std::make_shared<const io::UrdfDocument>(std::move(text), source);
  const urdf::ModelInterfaceSharedPtr urdf = parseQuietly(doc->text(), source);
  RobotModel m;
  m.name_ = doc->robotName();
  m.source_ = source;
  m.urdf_ = doc;
  readJoints(m, *doc, *urdf);
  resolveMimics(m, *doc, *urdf);
  buildTree(m, *doc, *urdf);
  finish(m);
  return m;
}

// Movable joints in file order; independent ones define q's order.
void UrdfLoader::readJoints(RobotModel& m, const io::UrdfDocument& doc, const Urdf& urdf) {
  for (const UrdfJoint& xj : doc.joints()) {
    m.joint_names_.push_back(xj.name);
    if (xj.type == "fixed") continue;
    const urdf::JointConstSharedPtr uj = urdf.getJoint(xj.name);
    MovableJoint mj;
    mj.name = xj.name;
    mj.type = xj.type == "prismatic"    ? JointType::kPrismatic
              : xj.type == "continuous" ? JointType::kContinuous
                                        : JointType::kRevolute;
    // Limits that span nothing bound nothing: a <limit> with only effort
    // and velocity reads as lower = upper = 0 (the URDF default), which
    // MuJoCo's importer leaves unlimited (an unseen quadruped's knees,
    // written so; held at 0 by the q-phase's box, a log that moves them
    // could not be fitted). A revolute joint so is a continuous one (its
    // pots' biases then known modulo a turn, as any continuous joint's), a
    // prismatic one unbounded; so is one whose limits lock it (lower =
    // upper): a joint the log holds still is reported so
    // (still_joints.hpp), not by its limits.
    const bool spans = uj->limits && uj->limits->upper > uj->limits->lower;
    if (mj.type == JointType::kRevolute && !spans) mj.type = JointType::kContinuous;
    if (spans && mj.type != JointType::kContinuous) {
      mj.lower = uj->limits->lower;
      mj.upper = uj->limits->upper;
      mj.has_limits = true;
    }
    m.movable_by_name_[mj.name] = static_cast<int>(m.movable_.size());
    m.movable_.push_back(mj);
  }
}

// Mimic: chains resolved to the independent master; the others get q indices.
void UrdfLoader::resolveMimics(RobotModel& m, const io::UrdfDocument& doc, const Urdf& urdf) {
  const std::string& source = doc.source();
  auto line = [&](const std::string& joint) { return doc.joint(joint)->line; };
  for (MovableJoint& mj : m.movable_) {
    const urdf::JointConstSharedPtr uj = urdf.getJoint(mj.name);
    if (!uj->mimic) continue;
    auto it = m.movable_by_name_.find(uj->mimic->joint_name);
    if (it == m.movable_by_name_.end())
      throw InputError(source, line(mj.name), 0,
                       "joint '" + mj.name + "' mimics '" + uj->mimic->joint_name +
                           "', which is not movable");
    mj.is_mimic = true;
    mj.multiplier = uj->mimic->multiplier;
    mj.offset = uj->mimic->offset;
    mj.q_index = it->second;  // temporarily: the direct master (movable idx)
  }
  for (int i = 0; i < static_cast<int>(m.movable_.size()); ++i) {
    if (!m.movable_[i].is_mimic) {
      m.movable_[i].q_index = static_cast<int>(m.q_joints_.size());
      m.q_by_name_[m.movable_[i].name] = m.movable_[i].q_index;
      m.q_joints_.push_back(i);
    }
  }
  for (MovableJoint& mj : m.movable_) {
    if (!mj.is_mimic) continue;
    double mult = mj.multiplier, off = mj.offset;
    int master = mj.q_index;  // movable index of the direct master
    int steps = 0;
    while (m.movable_[master].is_mimic) {
      if (++steps > static_cast<int>(m.movable_.size()))
        throw InputError(source, line(mj.name), 0,
                         "mimic joints form a cycle through '" + mj.name + "'");
      const urdf::JointConstSharedPtr up = urdf.getJoint(m.movable_[master].name);
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
}

// Links in depth-first order from the root, children in file order, and the
// KDL tree in the same order.
void UrdfLoader::buildTree(RobotModel& m, const io::UrdfDocument& doc, const Urdf& urdf) {
  std::map<std::string, std::vector<const UrdfJoint*>> children_of;
  for (const UrdfJoint& j : doc.joints()) children_of[j.parent].push_back(&j);
  const std::string root = urdf.getRoot()->name;
  KDL::Tree tree(root);
  std::vector<std::pair<std::string, const UrdfJoint*>> stack{{root, nullptr}};
  while (!stack.empty()) {
    auto [name, xj] = stack.back();
    stack.pop_back();
    Link link;
    link.name = name;
    if (xj) {
      const urdf::JointConstSharedPtr uj = urdf.getJoint(xj->name);
      link.parent = m.link_by_name_.at(xj->parent);
      link.origin = toEigen(uj->parent_to_joint_origin_transform);
      link.joint_name = xj->name;
      KDL::Joint kj(xj->name, KDL::Joint::Fixed);
      if (xj->type != "fixed") {
        Eigen::Vector3d axis(uj->axis.x, uj->axis.y, uj->axis.z);
        if (axis.norm() < 1e-12)
          throw InputError(doc.source(), xj->line, 0, "joint '" + xj->name + "' has a zero axis");
        link.axis = axis.normalized();
        link.movable_joint = m.movable_by_name_.at(xj->name);
        m.movable_[link.movable_joint].child_link = static_cast<int>(m.links_.size());
        const KDL::Frame F = toKdl(link.origin);
        const KDL::Vector a = F.M * KDL::Vector(link.axis.x(), link.axis.y(), link.axis.z());
        kj = KDL::Joint(xj->name, F.p, a,
                        xj->type == "prismatic" ? KDL::Joint::TransAxis : KDL::Joint::RotAxis);
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
  m.kdl_q_nr_.assign(m.movable_.size(), -1);
  for (const auto& kv : tree.getSegments()) {
    const KDL::Segment& seg = kv.second.segment;
    if (seg.getJoint().getType() == KDL::Joint::Fixed) continue;
    m.kdl_q_nr_[m.movable_by_name_.at(seg.getJoint().getName())] =
        static_cast<int>(kv.second.q_nr);
  }
  m.kdl_tree_ = tree;
}

// Supporting joints per link and the limits of q.
void UrdfLoader::finish(RobotModel& m) {
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

const std::string& RobotModel::urdfText() const { return urdf_->text(); }

}  // namespace stac
