// stac_simulate end to end (SPEC §4): determinism, the joint-angle file,
// argument validation, never overwriting an input, and the round trip
// through readLog against the library's own simulate().
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <string>
#include <vector>

#include "stac/log.hpp"
#include "stac/measurement.hpp"
#include "stac/robot_model.hpp"
#include "stac/sensors_file.hpp"
#include "stac/simulate.hpp"
#include "support/test_util.hpp"

namespace stac {
namespace {

const char* kUrdf = R"(<?xml version="1.0"?>
<robot name="cli3">
  <link name="base"/><link name="l1"/><link name="l2"/><link name="l3"/><link name="tip"/>
  <joint name="j1" type="revolute"><parent link="base"/><child link="l1"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 0 1"/><limit lower="-1.5" upper="1.5" effort="1" velocity="1"/></joint>
  <joint name="j2" type="revolute"><parent link="l1"/><child link="l2"/>
    <origin xyz="0 0 0.05"/><axis xyz="0 1 0"/><limit lower="-1.0" upper="1.2" effort="1" velocity="1"/></joint>
  <joint name="j3" type="continuous"><parent link="l2"/><child link="l3"/>
    <origin xyz="0.25 0 0"/><axis xyz="1 0 0"/></joint>
  <joint name="tip_fixed" type="fixed"><parent link="l3"/><child link="tip"/>
    <origin xyz="0.1 0 0"/></joint>
</robot>
)";

const char* kSensors = R"(mocap:
  sigma: 0.002
  frame:
    translation: [0.5, -0.2, 1.0]
    rpy: [0.1, -0.2, 0.3]
  markers:
    - name: m_l1
      link: l1
      position: [0.03, 0.0, 0.02]
    - name: m.tip.0
      link: tip
      position: [0.0, 0.01, 0.0]
      sigma: 0.001
joint_sensors:
  - name: j1_pot
    joint: j1
    gain: 1.5
    bias: 0.2
    sigma: 0.01
  - name: j2_pot
    joint: j2
    gain: -0.8
    bias: 0.1
    sigma: 0.01
  - name: j3_enc
    joint: j3
    gain: 651.9
    bias: 12.0
    sigma: 1.0
tendon_sensors:
  - name: cyl
    gain: 30.0
    bias: -1.0
    sigma: 0.02
    path:
      - {link: l1, point: [0.03, 0.02, 0.0]}
      - {link: l3, point: [0.05, 0.0, 0.03]}
  - name: flex
    gain: 2.0
    bias: 0.1
    sigma: 0.005
    coupling: {j2: 0.01, j3: 0.02}
)";

class SimulateCli : public ::testing::Test {
 protected:
  void SetUp() override {
    ASSERT_TRUE(std::ifstream(test::appPath("stac_simulate")).good())
        << "build the stac_simulate target first: " << test::appPath("stac_simulate");
    test::writeFile(urdf(), kUrdf);
    test::writeFile(sensors(), kSensors);
  }
  std::string urdf() const { return dir_.file("robot.urdf"); }
  std::string sensors() const { return dir_.file("truth.yaml"); }
  std::string file(const std::string& name) const { return dir_.file(name); }
  // Runs stac_simulate with the robot and sensors plus `args`.
  test::CommandResult run(const std::string& args) const {
    return test::runCommand("'" + test::appPath("stac_simulate") + "' --urdf '" + urdf() +
                            "' --sensors '" + sensors() + "' " + args);
  }
  std::vector<std::string> inputsOnly() const { return {"robot.urdf", "truth.yaml"}; }
  test::TempDir dir_;
};

TEST_F(SimulateCli, SameSeedGivesByteIdenticalFilesAndAnotherSeedDoesNot) {
  const std::string common = " --frames 120 --dropout 0.1 --outliers 0.02 --noise-scale 1.5";
  auto r1 = run("--log '" + file("a.csv") + "' --joint-angles '" + file("qa.csv") +
                "' --seed 9" + common);
  ASSERT_EQ(r1.exit_code, 0) << r1.err;
  auto r2 = run("--log '" + file("b.csv") + "' --joint-angles '" + file("qb.csv") +
                "' --seed 9" + common);
  ASSERT_EQ(r2.exit_code, 0) << r2.err;
  auto r3 = run("--log '" + file("c.csv") + "' --joint-angles '" + file("qc.csv") +
                "' --seed 10" + common);
  ASSERT_EQ(r3.exit_code, 0) << r3.err;
  const std::string a = test::readFile(file("a.csv")), qa = test::readFile(file("qa.csv"));
  ASSERT_FALSE(a.empty());
  ASSERT_FALSE(qa.empty());
  EXPECT_EQ(a, test::readFile(file("b.csv")));
  EXPECT_EQ(qa, test::readFile(file("qb.csv")));
  EXPECT_NE(a, test::readFile(file("c.csv")));
  EXPECT_NE(qa, test::readFile(file("qc.csv")));
  // No temporary files left behind.
  EXPECT_EQ(dir_.list(), (std::vector<std::string>{"a.csv", "b.csv", "c.csv", "qa.csv", "qb.csv",
                                                    "qc.csv", "robot.urdf", "truth.yaml"}));
  // A one-line summary on stderr naming the frames and the output.
  EXPECT_NE(r1.err.find("120 frames"), std::string::npos) << r1.err;
  EXPECT_NE(r1.err.find(file("a.csv")), std::string::npos) << r1.err;
  EXPECT_EQ(std::count(r1.err.begin(), r1.err.end(), '\n'), 1) << r1.err;
}

TEST_F(SimulateCli, LogRoundTripsToWhatTheLibrarySimulates) {
  auto r = run("--frames 150 --seed 21 --rate 50 --dropout 0.2 --outliers 0.05 --log '" +
               file("d.csv") + "' --joint-angles '" + file("q.csv") + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;

  const RobotModel robot = RobotModel::fromFile(urdf());
  const SensorsFile truth = loadSensorsFile(sensors(), robot);
  const MeasurementModel model(robot, truth.sensors);
  SimulationOptions o;
  o.frames = 150;
  o.seed = 21;
  o.rate_hz = 50.0;
  o.dropout = 0.2;
  o.outliers = 0.05;
  const Simulation sim = simulate(model, truth.theta, o);

  const Log log = readLog(file("d.csv"));
  const std::vector<std::string> columns = {"j1_pot",     "j2_pot",     "j3_enc",    "cyl",
                                            "flex",       "m_l1.x",     "m_l1.y",    "m_l1.z",
                                            "m.tip.0.x", "m.tip.0.y", "m.tip.0.z"};
  EXPECT_EQ(log.columns, columns);
  EXPECT_EQ(log.time_name, "time");
  ASSERT_EQ(log.numFrames(), 150);
  EXPECT_EQ(log.time, sim.data.log.time);
  EXPECT_DOUBLE_EQ(log.time[3], 3 / 50.0);
  int missing = 0;
  for (int t = 0; t < 150; ++t)
    for (int c = 0; c < static_cast<int>(columns.size()); ++c) {
      const double x = log.values(t, c), y = sim.data.log.values(t, c);
      ASSERT_EQ(std::isnan(x), std::isnan(y)) << t << " " << columns[c];
      if (std::isnan(x)) {
        ++missing;
        continue;
      }
      EXPECT_EQ(x, y) << t << " " << columns[c];  // exact: numbers round-trip
    }
  EXPECT_GT(missing, 0);
  EXPECT_FALSE(sim.data.outliers.empty());

  // The joint-angle file: time, then the joints in q order.
  const Log q = readLog(file("q.csv"));
  EXPECT_EQ(q.time_name, "time");
  EXPECT_EQ(q.columns, (std::vector<std::string>{"j1", "j2", "j3"}));
  ASSERT_EQ(q.numFrames(), 150);
  for (int t = 0; t < 150; ++t)
    for (int j = 0; j < 3; ++j) EXPECT_EQ(q.values(t, j), sim.q(t, j));
  // The log is calibratable input: it binds to the sensors file.
  EXPECT_EQ(bindLog(log, truth.sensors, sensors(), 1.0).num_frames, 150);
}

struct BadCase {
  std::string args;     // appended after --urdf/--sensors (unless it says so)
  std::string message;  // must appear in stderr
};

TEST_F(SimulateCli, BadArgumentsExitTwoWithAMessageAndWriteNothing) {
  const std::string log = " --log '" + file("out.csv") + "' --joint-angles '" + file("q.csv") + "'";
  const std::vector<BadCase> cases = {
      {"--frames 0" + log, "--frames"},
      {"--frames -5" + log, "--frames"},
      {"--frames abc" + log, "--frames"},
      {"--frames 10 --dropout 1.5" + log, "--dropout"},
      {"--frames 10 --dropout -0.1" + log, "--dropout"},
      {"--frames 10 --outliers 2" + log, "--outliers"},
      {"--frames 10 --rate 0" + log, "--rate"},
      {"--frames 10 --rate nan" + log, "--rate"},
      {"--frames 10 --noise-scale -1" + log, "--noise-scale"},
      {"--frames 10 --seed -3" + log, "--seed"},
      {"--frames 10 --seed 1.5" + log, "--seed"},
      {"--frames 10 --bogus 3" + log, "--bogus"},
      {"--frames 10", "--log"},
      {"--log '" + file("out.csv") + "'", "--frames"},
      {"--frames 10 --log '" + file("no_such_dir") + "/out.csv'", "no_such_dir"},
  };
  for (const BadCase& c : cases) {
    auto r = run(c.args);
    EXPECT_EQ(r.exit_code, 2) << c.args << "\n" << r.err;
    EXPECT_NE(r.err.find(c.message), std::string::npos) << c.args << "\n" << r.err;
    EXPECT_EQ(dir_.list(), inputsOnly()) << c.args;
  }
  // Missing --urdf (run without the fixture's inputs).
  auto r = test::runCommand("'" + test::appPath("stac_simulate") + "' --sensors '" + sensors() +
                            "' --frames 10" + log);
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("--urdf"), std::string::npos) << r.err;
  EXPECT_EQ(dir_.list(), inputsOnly());
}

TEST_F(SimulateCli, BadInputFilesExitTwoNamingTheFile) {
  test::writeFile(file("broken.urdf"), "<robot name='x'><link name='a'/>");
  auto r = test::runCommand("'" + test::appPath("stac_simulate") + "' --urdf '" +
                            file("broken.urdf") + "' --sensors '" + sensors() +
                            "' --frames 10 --log '" + file("out.csv") + "'");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("broken.urdf"), std::string::npos) << r.err;
  r = test::runCommand("'" + test::appPath("stac_simulate") + "' --urdf '" + file("nope.urdf") +
                       "' --sensors '" + sensors() + "' --frames 10 --log '" + file("out.csv") +
                       "'");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("nope.urdf"), std::string::npos) << r.err;
  test::writeFile(file("bad.yaml"), "joint_sensors:\n  - name: p\n    joint: no_such_joint\n");
  r = test::runCommand("'" + test::appPath("stac_simulate") + "' --urdf '" + urdf() +
                       "' --sensors '" + file("bad.yaml") + "' --frames 10 --log '" +
                       file("out.csv") + "'");
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("bad.yaml"), std::string::npos) << r.err;
  EXPECT_FALSE(std::ifstream(file("out.csv")).good());
}

TEST_F(SimulateCli, RefusesToOverwriteAnInput) {
  const std::string urdf_before = test::readFile(urdf());
  const std::string yaml_before = test::readFile(sensors());
  const std::vector<std::string> cases = {
      "--log '" + urdf() + "'",
      "--log '" + sensors() + "'",
      // The same file under another spelling.
      "--log '" + dir_.path() + "/./truth.yaml'",
      "--log '" + file("out.csv") + "' --joint-angles '" + sensors() + "'",
      "--log '" + file("out.csv") + "' --joint-angles '" + urdf() + "'",
      // Both outputs to one file.
      "--log '" + file("out.csv") + "' --joint-angles '" + dir_.path() + "/../" +
          dir_.path().substr(dir_.path().rfind('/') + 1) + "/out.csv'",
  };
  for (const std::string& c : cases) {
    auto r = run("--frames 10 " + c);
    EXPECT_EQ(r.exit_code, 2) << c << "\n" << r.err;
    EXPECT_FALSE(r.err.empty()) << c;
    EXPECT_EQ(test::readFile(urdf()), urdf_before) << c;
    EXPECT_EQ(test::readFile(sensors()), yaml_before) << c;
    EXPECT_EQ(dir_.list(), inputsOnly()) << c;
  }
}

TEST_F(SimulateCli, HelpAndVersionExitZero) {
  auto h = test::runCommand("'" + test::appPath("stac_simulate") + "' --help");
  EXPECT_EQ(h.exit_code, 0);
  for (const char* opt : {"--urdf", "--sensors", "--frames", "--log", "--joint-angles", "--seed",
                          "--rate", "--noise-scale", "--dropout", "--outliers"})
    EXPECT_NE(h.out.find(opt), std::string::npos) << opt;
  auto v = test::runCommand("'" + test::appPath("stac_simulate") + "' --version");
  EXPECT_EQ(v.exit_code, 0);
  EXPECT_NE(v.out.find("stac_simulate"), std::string::npos);
}

TEST_F(SimulateCli, OverwritesAPreviousOutputAtomically) {
  test::writeFile(file("out.csv"), "old contents\n");
  auto r = run("--frames 5 --log '" + file("out.csv") + "'");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const Log log = readLog(file("out.csv"));
  EXPECT_EQ(log.numFrames(), 5);
  EXPECT_EQ(dir_.list(), (std::vector<std::string>{"out.csv", "robot.urdf", "truth.yaml"}));
}

}  // namespace
}  // namespace stac
