#include "support/chain_fixture.hpp"

#include "stac/simulate.hpp"

namespace stac::test {

std::string chainUrdf(double j3_limit) {
  const std::string l = std::to_string(j3_limit);
  return R"(<robot name="chain4">
  <link name="base"/><link name="l1"/><link name="l2"/><link name="l3"/><link name="l4"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 0 1"/><limit lower="-4" upper="4" effort="1" velocity="1"/></joint>
  <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 1 0"/><limit lower="-1.5" upper="1.5" effort="1" velocity="1"/></joint>
  <joint name="j3" type="revolute"><parent link="l2"/><child link="l3"/>
    <origin xyz="0 0 0.3"/><axis xyz="0 0 1"/><limit lower="-)" + l + R"(" upper=")" + l +
         R"(" effort="1" velocity="1"/></joint>
  <joint name="j4" type="revolute"><parent link="l3"/><child link="l4"/>
    <origin xyz="0 0 0.2"/><axis xyz="0 1 0"/><limit lower="-1.5" upper="1.5" effort="1" velocity="1"/></joint>
</robot>
)";
}

std::string chainTruthYaml(bool l2_held) {
  return std::string(R"(mocap:
  sigma: 0.002
  frame:
    translation: [0.4, -0.2, 0.7]
    rpy: [0.2, -0.1, 1.0]
  markers:
    - {name: m_base, link: base, position: [0.05, 0.03, 0.0], fixed: true}
    - {name: m_l1, link: l1, position: [0.06, 0.02, 0.03]}
    - {name: m_l2, link: l2, position: [0.05, -0.04, 0.15])") +
         (l2_held ? ", fixed: true}" : "}") + R"(
    - {name: m_l3, link: l3, position: [0.04, 0.05, 0.1]}
    - {name: m_l4a, link: l4, position: [0.04, 0.03, 0.05], fixed: true}
    - {name: m_l4b, link: l4, position: [0.02, -0.03, 0.08]}
joint_sensors:
  - {name: j1_pot, joint: j1, gain: -1.5, bias: 0.4, sigma: 0.01}
  - {name: j2_pot, joint: j2, gain: 2.1, bias: -0.7, sigma: 0.01}
  - {name: j3_pot, joint: j3, gain: 0.8, bias: 1.1, sigma: 0.01}
  - {name: j4_pot, joint: j4, gain: -1.2, bias: 0.2, sigma: 0.01}
)";
}

ChainLog::ChainLog(bool l2_held, unsigned seed, const std::vector<ColumnRange>& ranges,
                   double urdf_j3_limit)
    : robot(RobotModel::fromString(chainUrdf(urdf_j3_limit), "chain4")),
      truth(parseSensorsYaml(chainTruthYaml(l2_held), "chain truth", robot)),
      model(robot, truth.sensors) {
  const RobotModel truth_robot = RobotModel::fromString(chainUrdf(), "chain4");
  const MeasurementModel truth_model(truth_robot, truth.sensors);
  std::mt19937_64 rng(seed);
  const int frames = 400;
  q = simulateMotion(truth_robot, frames, 100.0, rng);
  for (const ColumnRange& r : ranges) {
    const double lo = q.col(r.column).minCoeff(), hi = q.col(r.column).maxCoeff();
    q.col(r.column) = ((q.col(r.column).array() - lo) * ((r.hi - r.lo) / (hi - lo)) + r.lo).matrix();
  }
  SimulationOptions so;
  so.frames = frames;
  obs = bindLog(simulateLog(truth_model, truth.theta, q, so, rng).log, truth.sensors, "chain", 1.0);
}

}  // namespace stac::test
