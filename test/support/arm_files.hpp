// The small arm of arm_fixture as files (URDF, truth and seed sensors), for
// command-line tests.
#pragma once

#include <string>

namespace stac::test {

inline const char* kArmUrdf = R"(<robot name="arm4">
  <link name="base"/><link name="l1"/><link name="l2"/><link name="l3"/><link name="l4"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 0 1"/><limit lower="-1.5" upper="1.5" effort="1" velocity="1"/></joint>
  <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/>
    <origin xyz="0 0 0.05"/><axis xyz="0 1 0"/><limit lower="-1.2" upper="1.2" effort="1" velocity="1"/></joint>
  <joint name="j3" type="revolute"><parent link="l2"/><child link="l3"/>
    <origin xyz="0.25 0 0"/><axis xyz="1 0 0"/><limit lower="-1.2" upper="1.2" effort="1" velocity="1"/></joint>
  <joint name="j4" type="revolute"><parent link="l3"/><child link="l4"/>
    <origin xyz="0.2 0 0"/><axis xyz="0 0 1"/><limit lower="-1.2" upper="1.2" effort="1" velocity="1"/></joint>
</robot>
)";

inline const char* kArmTruth = R"(mocap:
  sigma: 0.002
  frame:
    translation: [0.5, -0.3, 0.8]
    rpy: [0.3, -0.2, 2.0]
  markers:
    - {name: m_base, link: base, position: [0.05, 0.03, 0.0], fixed: true}
    - {name: m_l2a, link: l2, position: [0.1, 0.03, 0.02]}
    - {name: m_l2b, link: l2, position: [0.15, -0.02, 0.03]}
    - {name: m_l4a, link: l4, position: [0.04, 0.03, 0.02], fixed: true}
    - {name: m_l4b, link: l4, position: [0.02, -0.03, 0.04]}
joint_sensors:
  - {name: j1_pot, joint: j1, gain: -1.5, bias: 0.4, sigma: 0.01}
  - {name: j2_pot, joint: j2, gain: 2.1, bias: -0.7, sigma: 0.01}
  - {name: j3_pot, joint: j3, gain: 0.8, bias: 1.1, sigma: 0.01}
  - {name: j4_pot, joint: j4, gain: -1.2, bias: 0.2, sigma: 0.01}
tendon_sensors:
  - name: cyl
    gain: 30.0
    bias: -1.0
    sigma: 0.01
    path:
      - {link: l1, point: [0.03, 0.02, 0.0]}
      - {link: l3, point: [0.05, 0.0, 0.03]}
)";

// The paper's seeding: markers at the link origin (but the two fixed ones),
// gains 1, biases 0, mocap frame identity.
inline const char* kArmSeed = R"(mocap:
  sigma: 0.002
  markers:
    - {name: m_base, link: base, position: [0.05, 0.03, 0.0], fixed: true}
    - {name: m_l2a, link: l2}
    - {name: m_l2b, link: l2}
    - {name: m_l4a, link: l4, position: [0.04, 0.03, 0.02], fixed: true}
    - {name: m_l4b, link: l4}
joint_sensors:
  - {name: j1_pot, joint: j1}
  - {name: j2_pot, joint: j2}
  - {name: j3_pot, joint: j3}
  - {name: j4_pot, joint: j4}
tendon_sensors:
  - name: cyl
    path:
      - {link: l1, point: [0.03, 0.02, 0.0]}
      - {link: l3, point: [0.05, 0.0, 0.03]}
)";

// kArmUrdf with joint `joint` (j1..j4) continuous (no limits).
inline std::string armUrdfWithContinuousJoint(const std::string& joint) {
  std::string urdf = kArmUrdf;
  const std::string revolute = "<joint name=\"" + joint + "\" type=\"revolute\">";
  return urdf.replace(urdf.find(revolute), revolute.size(),
                      "<joint name=\"" + joint + "\" type=\"continuous\">");
}

// kArmUrdf with its first joint continuous.
inline std::string armUrdfWithContinuousBase() { return armUrdfWithContinuousJoint("j1"); }

}  // namespace stac::test
