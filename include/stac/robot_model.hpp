// RobotModel: the kinematic description of a robot, built once from a URDF
// and never mutated (SPEC §1).
//
// The joint vector q holds every revolute, continuous and prismatic joint that
// is not a <mimic> follower, in the order the joints appear in the URDF file.
// Mimic followers take `multiplier * q_master + offset` (chains of followers
// are resolved to the independent master). Fixed joints are folded: their
// child link's frame is a constant offset from the parent's.
//
// Internally every URDF link is a node of a tree in topological order (parent
// before child); "movable joints" (followers included) are the coordinates of
// the full joint vector that KDL sees. The model also owns a KDL::Tree built
// by our own URDF->KDL conversion, for code that wants KDL's solvers.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <kdl/tree.hpp>
#include <memory>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

namespace stac {

namespace io {
class UrdfDocument;  // src/io/urdf_document.hpp: internal
}

enum class JointType { kRevolute, kContinuous, kPrismatic };

// A movable URDF joint (independent or mimic follower).
struct MovableJoint {
  std::string name;
  JointType type = JointType::kRevolute;
  int child_link = -1;      // node index of the link this joint moves
  int q_index = -1;         // index into q of the independent master
  double multiplier = 1.0;  // angle = multiplier * q[q_index] + offset
  double offset = 0.0;
  bool is_mimic = false;
  double lower = -1e300, upper = 1e300;  // limits (continuous: unbounded)
  bool has_limits = false;
};

// A link: a node of the kinematic tree.
struct Link {
  std::string name;
  int parent = -1;          // node index of the parent link, -1 for the root
  // Pose of this link's frame in the parent's frame at joint angle 0
  // (the URDF joint origin), and the joint axis in this link's frame.
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();
  int movable_joint = -1;   // index into movableJoints(), -1 if fixed/root
  std::string joint_name;   // the URDF joint that attaches it ("" for root)
};

class RobotModel {
 public:
  // Throws stac::InputError naming the file (or "<string>") and the problem.
  static RobotModel fromFile(const std::string& path);
  static RobotModel fromString(const std::string& urdf_xml,
                               const std::string& source_name = "<string>");

  const std::string& name() const { return name_; }
  const std::string& sourceName() const { return source_; }
  // The URDF text the model was loaded from, byte for byte (what a
  // calibrated URDF is written from: urdf_patch.hpp).
  const std::string& urdfText() const;
  // That text as the library parsed it (internal: src/io/urdf_document.hpp).
  const io::UrdfDocument& urdfDocument() const { return *urdf_; }

  // Independent joints (the q vector).
  int dof() const { return static_cast<int>(q_joints_.size()); }
  const std::vector<int>& qJoints() const { return q_joints_; }  // -> movable
  const std::string& qName(int i) const;
  std::optional<int> qIndex(const std::string& joint_name) const;

  const std::vector<MovableJoint>& movableJoints() const { return movable_; }
  std::optional<int> movableJointIndex(const std::string& joint_name) const;

  const std::vector<Link>& links() const { return links_; }
  int numLinks() const { return static_cast<int>(links_.size()); }
  std::optional<int> linkIndex(const std::string& link_name) const;
  // The link a URDF joint attaches (any joint, fixed ones too, but none for
  // the root): where a joint-origin correction acts.
  std::optional<int> linkOfJoint(const std::string& joint_name) const;
  const std::vector<std::string>& allJointNames() const { return joint_names_; }

  // For a link, the movable joints on its path to the root (the only columns
  // of a point Jacobian on that link that can be nonzero), root first.
  const std::vector<int>& supportingJoints(int link) const {
    return support_[link];
  }

  // Fills the full (movable) joint vector from q, applying mimic maps.
  void expand(const Eigen::VectorXd& q, Eigen::VectorXd* movable_q) const;

  // Lower/upper limits of q (±inf where the joint has none).
  const Eigen::VectorXd& lowerLimits() const { return lower_; }
  const Eigen::VectorXd& upperLimits() const { return upper_; }

  // The KDL tree (segments named after links; segment joints named after
  // URDF joints; mimic followers carry their multiplier/offset as the KDL
  // joint's scale/offset and read the master's value from kdlJointIndex).
  const KDL::Tree& kdlTree() const { return kdl_tree_; }
  // KDL's q_nr of each movable joint.
  const std::vector<int>& kdlJointIndex() const { return kdl_q_nr_; }

 private:
  RobotModel() = default;
  friend class UrdfLoader;

  std::string name_, source_;
  // Shared by copies: immutable, and the text can be megabytes.
  std::shared_ptr<const io::UrdfDocument> urdf_;
  std::vector<Link> links_;
  std::vector<MovableJoint> movable_;
  std::vector<int> q_joints_;
  std::vector<std::vector<int>> support_;
  std::vector<std::string> joint_names_;
  std::unordered_map<std::string, int> link_by_name_, movable_by_name_;
  std::unordered_map<std::string, int> q_by_name_;
  Eigen::VectorXd lower_, upper_;
  KDL::Tree kdl_tree_;
  std::vector<int> kdl_q_nr_;
};

}  // namespace stac
