// stac_calib end to end: success, determinism, and every bad-input path of
// SPEC §2 (log) and §3 (sensors file) with its exit code and message.
#include <gtest/gtest.h>

#include <regex>

#include "stac/log.hpp"
#include "support/arm_files.hpp"
#include "support/test_util.hpp"

namespace stac {
namespace {

class CalibCli : public ::testing::Test {
 protected:
  void SetUp() override {
    test::writeFile(dir_.file("arm.urdf"), test::kArmUrdf);
    test::writeFile(dir_.file("truth.yaml"), test::kArmTruth);
    test::writeFile(dir_.file("seed.yaml"), test::kArmSeed);
    const auto r = test::runCommand(test::appPath("stac_simulate") + " --urdf " + file("arm.urdf") +
                                    " --sensors " + file("truth.yaml") + " --frames 300 --log " +
                                    file("data.csv") + " --seed 4");
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  std::string file(const std::string& n) const { return dir_.file(n); }
  test::CommandResult calib(const std::string& extra) const {
    return test::runCommand(test::appPath("stac_calib") + " --urdf " + file("arm.urdf") + " " + extra);
  }
  // Runs with a sensors file `yaml` and expects exit 2 naming file, line and `key`.
  void expectSensorsError(const std::string& yaml, int line, const std::string& key) {
    test::writeFile(file("bad.yaml"), yaml);
    const auto before = dir_.list();
    const auto r = calib("--log " + file("data.csv") + " --sensors " + file("bad.yaml") +
                         " --output " + file("out.yaml"));
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find(file("bad.yaml") + ":" + std::to_string(line)), std::string::npos)
        << "expected line " << line << " in: " << r.err;
    EXPECT_NE(r.err.find(key), std::string::npos) << "expected '" << key << "' in: " << r.err;
    EXPECT_EQ(dir_.list(), before) << "an output file was left behind";
  }
  void expectLogError(const std::string& csv, const std::string& where, const std::string& what) {
    test::writeFile(file("bad.csv"), csv);
    const auto before = dir_.list();
    const auto r = calib("--log " + file("bad.csv") + " --sensors " + file("seed.yaml") +
                         " --output " + file("out.yaml"));
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find(file("bad.csv") + ":" + where), std::string::npos) << r.err;
    EXPECT_NE(r.err.find(what), std::string::npos) << r.err;
    EXPECT_EQ(dir_.list(), before);
  }
  test::TempDir dir_;
};

TEST_F(CalibCli, CalibratesAndTheOutputFeedsBack) {
  auto r = calib("--log " + file("data.csv") + " --sensors " + file("seed.yaml") + " --output " +
                 file("cal.yaml") + " --joint-angles " + file("q.csv"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("unidentifiable: none"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("before"), std::string::npos);
  EXPECT_NE(r.err.find("stac     1"), std::string::npos) << "progress lines on stderr: " << r.err;
  const std::string q = test::readFile(file("q.csv"));
  EXPECT_EQ(q.substr(0, q.find('\n')), "time,j1,j2,j3,j4");
  r = calib("--log " + file("data.csv") + " --sensors " + file("cal.yaml") + " --output " +
            file("cal2.yaml") + " --quiet");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_TRUE(r.err.empty()) << r.err;
}

// Suspect results still write the calibration but exit 4 (SPEC §4) with the
// reasons in summary.verdict and on stderr, --quiet or not: a marker σ seeded
// 20x too small, and a solve cut off by --max-iterations.
TEST_F(CalibCli, SuspectResultsAreWarnedAbout) {
  std::string seed = test::readFile(file("seed.yaml"));
  const size_t at = seed.find("sigma: 0.002");
  ASSERT_NE(at, std::string::npos);
  seed.replace(at, 12, "sigma: 0.0001");
  test::writeFile(file("tight.yaml"), seed);
  auto r = calib("--log " + file("data.csv") + " --sensors " + file("tight.yaml") + " --output " +
                 file("cal.yaml") + " --quiet");
  EXPECT_EQ(r.exit_code, 4) << r.err;
  const std::string yaml = test::readFile(file("cal.yaml"));
  EXPECT_NE(yaml.find("  verdict:\n    - \"the marker readings fit"), std::string::npos) << yaml;
  EXPECT_NE(r.err.find("warning: the marker readings fit"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("not converged"), std::string::npos) << r.err;

  r = calib("--log " + file("data.csv") + " --sensors " + file("seed.yaml") + " --output " +
            file("cal1.yaml") + " --max-iterations 1 --quiet");
  EXPECT_EQ(r.exit_code, 4) << r.err;
  EXPECT_NE(test::readFile(file("cal1.yaml")).find("not converged after 1 iterations"),
            std::string::npos);
  EXPECT_NE(r.err.find("warning: not converged after 1 iterations"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("readings fit"), std::string::npos) << r.err;
}

// A calibration that reaches the truth passes its own checks.
TEST_F(CalibCli, SoundCalibrationHasVerdictOk) {
  const auto r = calib("--log " + file("data.csv") + " --sensors " + file("seed.yaml") +
                       " --output " + file("ok.yaml") + " --quiet");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(test::readFile(file("ok.yaml")).find("  verdict: ok\n"), std::string::npos);
  EXPECT_NE(r.out.find("verdict: ok"), std::string::npos) << r.out;
}

// Every output byte but the timing is the same with 1 and 2 threads.
TEST_F(CalibCli, ThreadCountDoesNotChangeTheOutput) {
  for (int threads : {1, 2}) {
    const std::string t = std::to_string(threads);
    const auto r = calib("--log " + file("data.csv") + " --sensors " + file("seed.yaml") +
                         " --threads " + t + " --output " + file("cal" + t + ".yaml") +
                         " --joint-angles " + file("q" + t + ".csv") + " --quiet");
    ASSERT_EQ(r.exit_code, 0) << r.err;
  }
  const std::regex timing("wall_time: [^\n]*");
  EXPECT_EQ(std::regex_replace(test::readFile(file("cal1.yaml")), timing, ""),
            std::regex_replace(test::readFile(file("cal2.yaml")), timing, ""));
  EXPECT_EQ(test::readFile(file("q1.csv")), test::readFile(file("q2.csv")));
}

TEST_F(CalibCli, UsageErrors) {
  EXPECT_EQ(test::runCommand(test::appPath("stac_calib") + " --help").exit_code, 0);
  EXPECT_EQ(test::runCommand(test::appPath("stac_calib") + " --version").exit_code, 0);
  auto r = test::runCommand(test::appPath("stac_calib") + " --log x.csv");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--urdf"), std::string::npos) << r.err;
  r = calib("--log " + file("data.csv") + " --bogus 3");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--bogus"), std::string::npos);
  r = calib("--log " + file("data.csv") + " --method fast");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("stac|joint"), std::string::npos);
  r = calib("--log " + file("data.csv") + " --threads -1");
  EXPECT_EQ(r.exit_code, 2);
  // A forgotten value is not taken from the next flag (no file "--quiet").
  r = calib("--log " + file("data.csv") + " --output --quiet");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("--output needs a value"), std::string::npos) << r.err;
  r = calib("--log " + file("missing.csv"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("missing.csv"), std::string::npos);
}

TEST_F(CalibCli, RefusesToOverwriteAnInput) {
  const std::string seed = test::readFile(file("seed.yaml"));
  const auto r = calib("--log " + file("data.csv") + " --sensors " + file("seed.yaml") +
                       " --output " + file("seed.yaml"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("refusing to overwrite"), std::string::npos) << r.err;
  EXPECT_EQ(test::readFile(file("seed.yaml")), seed);
}

// ---- SPEC §2: the log ----

TEST_F(CalibCli, LogInfIsAnError) {
  expectLogError("time,j1_pot\n0.0,inf\n", "2:2", "not finite");
}
TEST_F(CalibCli, LogTextIsAnError) {
  expectLogError("# comment\ntime,j1_pot\n0.0,0.5\n0.01,abc\n", "4:2", "'abc' is not a number");
}
TEST_F(CalibCli, LogRaggedRowIsAnError) {
  expectLogError("time,j1_pot,j2_pot\n0.0,0.5,0.1\n0.01,0.5\n", "3:", "2 cells");
}
TEST_F(CalibCli, LogColumnWithoutSensorNamesBothFiles) {
  std::string csv = test::readFile(file("data.csv"));
  csv.replace(csv.find("j1_pot"), 6, "j9_pot");
  test::writeFile(file("renamed.csv"), csv);
  const auto r = calib("--log " + file("renamed.csv") + " --sensors " + file("seed.yaml") +
                       " --output " + file("out.yaml"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find(file("renamed.csv") + ":1"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find(file("seed.yaml")), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("j1_pot"), std::string::npos) << r.err;
}

TEST_F(CalibCli, MocapUnitsMillimetres) {
  // The same log in millimetres gives the same calibration.
  Log log = readLog(file("data.csv"));
  for (size_t c = 0; c < log.columns.size(); ++c)
    if (log.columns[c].find('.') != std::string::npos) log.values.col(c) *= 1000.0;
  writeLog(file("mm.csv"), log);
  auto a = calib("--log " + file("data.csv") + " --sensors " + file("seed.yaml") + " --output " +
                 file("a.yaml") + " --quiet");
  auto b = calib("--log " + file("mm.csv") + " --mocap-units mm --sensors " + file("seed.yaml") +
                 " --output " + file("b.yaml") + " --quiet");
  ASSERT_EQ(a.exit_code, 0);
  ASSERT_EQ(b.exit_code, 0) << b.err;
  const std::string ya = test::readFile(file("a.yaml")), yb = test::readFile(file("b.yaml"));
  const auto pos = [](const std::string& y) { return y.substr(y.find("m_l2a"), 120); };
  EXPECT_EQ(pos(ya).substr(0, 40), pos(yb).substr(0, 40));
}

// ---- Without a sensors file ----

TEST_F(CalibCli, InferenceNamesTheClosestJointOrLink) {
  test::writeFile(file("infer.csv"),
                  "time,j1,j2,j3,l4.x,l4.y,l4.z,elbow2,j_4\n0,0,0,0,0,0,0,0,0\n");
  const auto r = calib("--log " + file("infer.csv") + " --output " + file("out.yaml"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find(file("infer.csv") + ":1"), std::string::npos) << r.err;
  // A hint only when a name is close (issue 15: no "x1 -> base_link").
  EXPECT_NE(r.err.find("elbow2 (no joint or link name is close)"), std::string::npos) << r.err;
  EXPECT_NE(r.err.find("j_4 (closest joint or link: joint 'j4'; did you mean 'j4'?)"),
            std::string::npos)
      << r.err;
}

// ---- SPEC §3: the sensors file ----

const std::string kHead = "joint_sensors:\n";  // line 1
const std::string kPots =
    "  - {name: j1_pot, joint: j1}\n  - {name: j2_pot, joint: j2}\n"
    "  - {name: j3_pot, joint: j3}\n  - {name: j4_pot, joint: j4}\n";  // lines 2-5

TEST_F(CalibCli, SensorsUnknownKey) {
  expectSensorsError(kHead + kPots + "  - name: x\n    joint: j1\n    gian: 2.0\n", 8, "gian");
}
TEST_F(CalibCli, SensorsKeyGivenTwice) {
  expectSensorsError(kHead + kPots + "  - name: x\n    joint: j1\n    joint: j2\n", 8,
                     "joint_sensors[4].joint");
}
TEST_F(CalibCli, SensorsWrongType) {
  expectSensorsError(kHead + kPots + "  - name: x\n    joint: j1\n    gain: fast\n", 8,
                     "joint_sensors[4].gain");
}
TEST_F(CalibCli, SensorsUnknownLink) {
  expectSensorsError("mocap:\n  markers:\n    - name: m\n      link: nolink\n", 4,
                     "mocap.markers[0].link");
}
TEST_F(CalibCli, SensorsUnknownJoint) {
  expectSensorsError(kHead + "  - name: j1_pot\n    joint: elbow\n", 3, "joint_sensors[0].joint");
}
TEST_F(CalibCli, SensorsNameUsedTwice) {
  expectSensorsError(kHead + kPots + "  - name: j2_pot\n    joint: j2\n", 6, "used twice");
}
TEST_F(CalibCli, SensorsPathTooShort) {
  expectSensorsError("tendon_sensors:\n  - name: cyl\n    path:\n      - {link: l1, point: [0, 0, 0]}\n",
                     4, "at least two points");
}
TEST_F(CalibCli, SensorsCouplingUnknownJoint) {
  expectSensorsError("tendon_sensors:\n  - name: cyl\n    coupling: {j1: 0.01, wrist: 0.02}\n", 3,
                     "tendon_sensors[0].coupling.wrist");
}
TEST_F(CalibCli, SensorsSigmaNotPositive) {
  expectSensorsError(kHead + "  - name: j1_pot\n    joint: j1\n    sigma: 0.0\n", 4,
                     "joint_sensors[0].sigma");
}
TEST_F(CalibCli, SensorsNonFiniteNumber) {
  expectSensorsError(kHead + "  - name: j1_pot\n    joint: j1\n    bias: .nan\n", 4,
                     "joint_sensors[0].bias");
}
TEST_F(CalibCli, SensorsRpyAndQuaternionDisagree) {
  expectSensorsError("mocap:\n  frame:\n    rpy: [0.0, 0.0, 0.5]\n    quaternion: [1.0, 0.0, 0.0, 0.0]\n"
                     "  markers:\n    - {name: m, link: l2}\n", 3, "mocap.frame.rpy");
}
TEST_F(CalibCli, SensorsMalformedYaml) {
  expectSensorsError("joint_sensors:\n  - {name: j1_pot, joint: j1\n", 3, "malformed YAML");
}

// A Cauchy loss evaluates ρ(s) = c² log(1 + s/c²) as 0 for a reading fitted
// to ~1e-8 σ (a frame left with one reading by the dropout): the robust
// rescaling then divided 0 by 0 and every std was NaN, with verdict ok.
TEST(CalibCliLoss, CauchyOnReadingsFittedExactlyGivesFiniteStd) {
  test::TempDir dir;
  const std::string data = STAC_DATA_DIR;
  const auto sim = test::runCommand(test::appPath("stac_simulate") + " --urdf " + data +
                                    "/gimbal2.urdf --sensors " + data +
                                    "/gimbal2_truth.yaml --frames 300 --outliers 0.05 "
                                    "--dropout 0.3 --seed 1 --log " + dir.file("g.csv"));
  ASSERT_EQ(sim.exit_code, 0) << sim.err;
  const auto r = test::runCommand(test::appPath("stac_calib") + " --urdf " + data +
                                  "/gimbal2.urdf --sensors " + data + "/gimbal2_seed.yaml --log " +
                                  dir.file("g.csv") + " --loss cauchy --quiet --output " +
                                  dir.file("cal.yaml"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string yaml = test::readFile(dir.file("cal.yaml"));
  EXPECT_EQ(yaml.find("nan"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("std: {gain: "), std::string::npos) << yaml;
}

}  // namespace
}  // namespace stac
