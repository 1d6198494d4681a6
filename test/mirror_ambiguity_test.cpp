// Mirror configurations the data cannot tell apart (mirror_ambiguity.hpp):
// a chain whose axes 1 and 3 align at q2 = 0 passes through the same places
// with q1 + π, −q2, q3 + π. With the markers of links 1 and 2 free and a
// motion that fits within the limits either way, the two fit alike: the
// result lists the pots' parameters as undetermined; a marker held on link
// 2 tells them apart, and then nothing is listed.
#include "methods/mirror_ambiguity.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>

#include "methods/wide_basin.hpp"
#include "solve/theta_phase.hpp"
#include "stac/calibrate.hpp"
#include "stac/sensors_file.hpp"
#include "stac/simulate.hpp"
#include "stac/theta_space.hpp"
#include "support/chain_fixture.hpp"

namespace stac {
namespace {

// j1 and j3 over [-0.5, 0.7] only: half a turn away fits the limits too.
struct Chain : test::ChainLog {
  explicit Chain(bool l2_held) : ChainLog(l2_held, 3, {{0, -0.5, 0.7}, {2, -0.5, 0.7}}) {}
};

bool listsTheMirror(const std::vector<UnidentifiableDirection>& dirs) {
  return std::any_of(dirs.begin(), dirs.end(), [](const UnidentifiableDirection& d) {
    return d.kind == Undetermined::kMirror &&
           d.reason.find("j1 and j3 half a turn away with j2 mirrored") != std::string::npos &&
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
  const std::vector<WideBasin::EquivalentMove> same = basin.equivalentMoves(est);
  ASSERT_EQ(same.size(), 1u);
  EXPECT_EQ(same[0].move.flip, std::vector<int>{1});
  EXPECT_EQ(same[0].move.half_turn, (std::vector<int>{0, 2}));
}

// test::chainUrdf() with `from` replaced by `to` (an empty string if
// `from` is not there).
std::string editedChain(const std::string& from, const std::string& to) {
  std::string urdf = test::chainUrdf();
  const size_t at = urdf.find(from);
  if (at == std::string::npos) return "";
  return urdf.replace(at, from.size(), to);
}

// The truth's jumps that fit as well on a log of the chain `urdf` with j1
// and j3 over [-0.5, 0.7] (half a turn away fits too); *q the log's angles.
std::vector<WideBasin::EquivalentMove> equivalentFromTheTruth(const std::string& urdf,
                                                              RowMatrix* q) {
  const RobotModel robot = RobotModel::fromString(urdf, "chain4");
  const SensorsFile truth = parseSensorsYaml(test::chainTruthYaml(false), "chain truth", robot);
  const MeasurementModel model(robot, truth.sensors);
  std::mt19937_64 rng(3);
  *q = simulateMotion(robot, 400, 100.0, rng);
  for (int c : {0, 2}) {
    const double lo = q->col(c).minCoeff(), hi = q->col(c).maxCoeff();
    q->col(c) = ((q->col(c).array() - lo) * (1.2 / (hi - lo)) - 0.5).matrix();
  }
  SimulationOptions so;
  so.frames = 400;
  const Observations obs =
      bindLog(simulateLog(model, truth.theta, *q, so, rng).log, truth.sensors, "chain", 1.0);
  const NoiseModel noise = NoiseModel::fromSeeds(truth.sensors);
  const RobustLoss loss;
  Workspaces ws = makeWorkspaces(model, 2);
  const WideBasin basin(model, obs, noise, loss, 2, &ws, truth.theta, false);
  Estimate est;
  est.theta = truth.theta;
  est.state.q = *q;
  return basin.equivalentMoves(est);
}

// The same chain with j2 straight at π (its origin turned half a turn about
// its axis, its limits π ± 1.5), as the Kinova Jaco's wrist joint 5: the
// mirror is q2 -> 2π − q2, within the limits, where −q2 is not (it was
// missed, and four of ten random Jaco truths ended in the flip, silent).
TEST(MirrorAmbiguity, AJointStraightAtHalfATurnMirrorsAboutIt) {
  const std::string urdf =
      editedChain(R"(<origin xyz="0 0 0.1"/><axis xyz="0 1 0"/><limit lower="-1.5" upper="1.5")",
                  R"(<origin xyz="0 0 0.1" rpy="0 3.141592653589793 0"/><axis xyz="0 1 0"/>)"
                  R"(<limit lower="1.6415926535897931" upper="4.6415926535897931")");
  ASSERT_FALSE(urdf.empty());
  RowMatrix q;
  const std::vector<WideBasin::EquivalentMove> same = equivalentFromTheTruth(urdf, &q);
  ASSERT_GT(q.col(1).minCoeff(), 1.6);  // j2 near π, as its limits say
  ASSERT_EQ(same.size(), 1u);
  EXPECT_EQ(same[0].move.flip, std::vector<int>{1});
  EXPECT_EQ(same[0].move.half_turn, (std::vector<int>{0, 2}));
}

// A mirror made inexact by an offset in the chain (j3's axis 0.5 mm off
// j1's; the Kinova Jaco's are 1.6 and 11 mm) fits as well only once the
// angles follow it: with θ alone re-fitted at the moved angles it fit 0.7%
// worse and was not listed (an unseen Jaco ended in its shoulder's such
// mirror, the mocap rotation 5 std off, verdict ok); refined, 0.07%. (At
// 1 mm here the refined fit is 0.2% worse: told apart.)
TEST(MirrorAmbiguity, AMirrorMadeInexactByAnOffsetIsFoundOnceRefined) {
  const std::string urdf =
      editedChain(R"(<origin xyz="0 0 0.3"/>)", R"(<origin xyz="0.0005 0 0.3"/>)");
  ASSERT_FALSE(urdf.empty());
  RowMatrix q;
  const std::vector<WideBasin::EquivalentMove> same = equivalentFromTheTruth(urdf, &q);
  ASSERT_EQ(same.size(), 1u);
  EXPECT_EQ(same[0].move.flip, std::vector<int>{1});
  EXPECT_EQ(same[0].move.half_turn, (std::vector<int>{0, 2}));
}

bool lists(const std::vector<UnidentifiableDirection>& dirs, const std::string& parameter) {
  return std::any_of(dirs.begin(), dirs.end(), [&](const UnidentifiableDirection& d) {
    return std::find(d.parameters.begin(), d.parameters.end(), parameter) != d.parameters.end();
  });
}

// The pots the mirror moves and the markers of links 1 and 2, which move
// with them, are listed and get no std; link 3's marker and j4's pot, the
// same in both configurations, keep theirs.
TEST(MirrorAmbiguity, ACalibrationListsItAndGivesTheMovedParametersNoStd) {
  const CalibrationResult r = calibrateFromTheTruth(Chain(false));
  const auto& u = r.summary.unidentifiable;
  EXPECT_TRUE(listsTheMirror(u));
  for (const char* p : {"joint_sensors.j1_pot.bias", "joint_sensors.j2_pot.gain",
                        "joint_sensors.j3_pot.bias", "markers.m_l1.position.x",
                        "markers.m_l2.position.x"})
    EXPECT_TRUE(lists(u, p)) << p;
  for (const char* p : {"joint_sensors.j4_pot.gain", "markers.m_l3.position.x"})
    EXPECT_FALSE(lists(u, p)) << p;
  EXPECT_TRUE(std::isinf(r.std.joint_sensor[1].gain));
  EXPECT_TRUE(std::isinf(r.std.joint_sensor[0].bias));
  EXPECT_TRUE(std::isinf(r.std.marker_position[1].x()));  // m_l1
  EXPECT_TRUE(std::isfinite(r.std.joint_sensor[3].gain));
  EXPECT_TRUE(std::isfinite(r.std.marker_position[3].norm()));  // m_l3
  EXPECT_FALSE(r.summary.suspect()) << r.summary.verdict[0];
}

// Started in the mirror (the configuration the data cannot tell from the
// truth), the calibration stays there and says so: the truth lies within 4
// reported std of every parameter — the mirrored ones' std infinite, the
// others' finite and the truth within them. Before, the mirrored pots kept
// a sharp local std and the answer read as confidently wrong.
TEST(MirrorAmbiguity, FromTheMirrorTheTruthIsWithinTheReportedStd) {
  const Chain c(false);
  const NoiseModel noise = NoiseModel::fromSeeds(c.truth.sensors);
  const RobustLoss loss;
  Workspaces ws = makeWorkspaces(c.model, 2);
  // The mirror on every frame, θ re-fitted there in closed form.
  QState mirrored;
  mirrored.q = c.q;  // q1 + π, −q2, q3 + π
  mirrored.q.col(0).array() += M_PI;
  mirrored.q.col(1) *= -1.0;
  mirrored.q.col(2).array() += M_PI;
  SensorParameters start = c.truth.theta;
  ThetaPhaseOptions to;
  to.threads = 2;
  thetaPhase(c.model, noise, loss, c.obs, mirrored, to, &ws, &start);
  CalibrationOptions o;
  o.threads = 2;
  const CalibrationResult r =
      calibrate(c.robot, c.truth.sensors, start, c.obs, o, nullptr, &mirrored.q);
  ASSERT_TRUE(r.summary.converged);
  EXPECT_LT(r.theta.joint_sensor[1].gain * c.truth.theta.joint_sensor[1].gain, 0)
      << "not the mirror";
  EXPECT_TRUE(listsTheMirror(r.summary.unidentifiable));
  const ThetaSpace space(c.truth.sensors);
  const Eigen::VectorXd d = space.minus(r.theta, c.truth.theta);
  int infinite = 0;
  auto within = [&](double error, double std_, const std::string& what) {
    infinite += std::isinf(std_);
    EXPECT_LE(std::abs(error), 4 * std_) << what;
  };
  for (int s = 0; s < 4; ++s) {
    within(d[space.jointOffset(s)], r.std.joint_sensor[s].gain, "gain " + std::to_string(s));
    within(d[space.jointOffset(s) + 1], r.std.joint_sensor[s].bias, "bias " + std::to_string(s));
  }
  for (size_t m = 0; m < c.truth.sensors.markers.size(); ++m)
    for (int i = 0; i < 3; ++i)
      within(d[space.markerOffset(static_cast<int>(m)) + i], r.std.marker_position[m][i],
             c.truth.sensors.markers[m].name);
  EXPECT_GE(infinite, 5);  // j1's bias, j2's gain and bias, j3's bias, m_l1 and m_l2
  EXPECT_TRUE(std::isfinite(r.std.joint_sensor[3].gain));
}

TEST(MirrorAmbiguity, AMarkerHeldOnALinkInBetweenTellsThemApart) {
  const CalibrationResult r = calibrateFromTheTruth(Chain(true));
  EXPECT_FALSE(listsTheMirror(r.summary.unidentifiable));
  EXPECT_TRUE(r.summary.unidentifiable.empty()) << r.summary.unidentifiable[0].reason;
  EXPECT_FALSE(r.summary.suspect()) << r.summary.verdict[0];
}

}  // namespace
}  // namespace stac
