// Mirror configurations the data cannot tell apart (mirror_ambiguity.hpp):
// a chain whose axes 1 and 3 align at q2 = 0 passes through the same places
// with q1 + π, −q2, q3 + π. With the markers of links 1 and 2 free and a
// motion that fits within the limits either way, the two fit alike: the
// result lists the pots' parameters as undetermined; a marker held on link
// 2 tells them apart, and then nothing is listed.
#include "methods/mirror_ambiguity.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <string>

#include "methods/wide_basin.hpp"
#include "stac/calibrate.hpp"
#include "stac/sensors_file.hpp"
#include "stac/simulate.hpp"

namespace stac {
namespace {

const char* kChainUrdf = R"(<robot name="chain4">
  <link name="base"/><link name="l1"/><link name="l2"/><link name="l3"/><link name="l4"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 0 1"/><limit lower="-4" upper="4" effort="1" velocity="1"/></joint>
  <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 1 0"/><limit lower="-1.5" upper="1.5" effort="1" velocity="1"/></joint>
  <joint name="j3" type="revolute"><parent link="l2"/><child link="l3"/>
    <origin xyz="0 0 0.3"/><axis xyz="0 0 1"/><limit lower="-4" upper="4" effort="1" velocity="1"/></joint>
  <joint name="j4" type="revolute"><parent link="l3"/><child link="l4"/>
    <origin xyz="0 0 0.2"/><axis xyz="0 1 0"/><limit lower="-1.5" upper="1.5" effort="1" velocity="1"/></joint>
</robot>
)";

// `l2_held`: the marker of link 2 at its known position.
std::string chainTruth(bool l2_held) {
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

struct Chain {
  explicit Chain(bool l2_held)
      : robot(RobotModel::fromString(kChainUrdf, "chain4")),
        truth(parseSensorsYaml(chainTruth(l2_held), "chain truth", robot)),
        model(robot, truth.sensors) {
    std::mt19937_64 rng(3);
    q = simulateMotion(robot, 400, 100.0, rng);
    // j1 and j3 over [-0.5, 0.7] only: half a turn away fits the limits too.
    for (int j : {0, 2}) {
      const double lo = q.col(j).minCoeff(), hi = q.col(j).maxCoeff();
      q.col(j) = ((q.col(j).array() - lo) * (1.2 / (hi - lo)) - 0.5).matrix();
    }
    SimulationOptions so;
    so.frames = 400;
    obs = bindLog(simulateLog(model, truth.theta, q, so, rng).log, truth.sensors, "chain", 1.0);
  }
  RobotModel robot;
  SensorsFile truth;
  MeasurementModel model;
  RowMatrix q;
  Observations obs;
};

bool listsTheMirror(const std::vector<UnidentifiableDirection>& dirs) {
  return std::any_of(dirs.begin(), dirs.end(), [](const UnidentifiableDirection& d) {
    return d.reason.find("j1 and j3 half a turn away with j2 mirrored") != std::string::npos &&
           std::find(d.parameters.begin(), d.parameters.end(), "joint_sensors.j2_pot.gain") !=
               d.parameters.end();
  });
}

// Calibrated from the truth and its angles (no initialisation).
CalibrationResult calibrateFromTheTruth(const Chain& c) {
  CalibrationOptions o;
  o.threads = 2;
  return calibrate(c.robot, c.truth.sensors, c.truth.theta, c.obs, o, nullptr, &c.q);
}

TEST(MirrorAmbiguity, TheWristFlipFitsAlikeWithTheMiddleMarkersFree) {
  const Chain c(false);
  const NoiseModel noise = NoiseModel::fromSeeds(c.truth.sensors);
  const RobustLoss loss;
  Workspaces ws = makeWorkspaces(c.model, 2);
  const WideBasin basin(c.model, c.obs, noise, loss, 2, &ws, c.truth.theta, false);
  Estimate est;
  est.theta = c.truth.theta;
  est.state.q = c.q;
  const std::vector<MinimumMove> same = basin.equivalentMoves(est);
  ASSERT_EQ(same.size(), 1u);
  EXPECT_EQ(same[0].flip, std::vector<int>{1});
  EXPECT_EQ(same[0].half_turn, (std::vector<int>{0, 2}));
}

TEST(MirrorAmbiguity, ACalibrationListsIt) {
  const CalibrationResult r = calibrateFromTheTruth(Chain(false));
  EXPECT_TRUE(listsTheMirror(r.summary.unidentifiable));
}

TEST(MirrorAmbiguity, AMarkerHeldOnALinkInBetweenTellsThemApart) {
  const CalibrationResult r = calibrateFromTheTruth(Chain(true));
  EXPECT_FALSE(listsTheMirror(r.summary.unidentifiable));
  EXPECT_TRUE(r.summary.unidentifiable.empty()) << r.summary.unidentifiable[0].reason;
  EXPECT_FALSE(r.summary.suspect()) << r.summary.verdict[0];
}

}  // namespace
}  // namespace stac
