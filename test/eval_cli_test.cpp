// stac_eval end to end (SPEC §4): the table and the JSON on simulated data
// (true vs seed parameters, --truth errors), --mocap-units, argument and
// input validation, and never overwriting an input.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "stac/log.hpp"
#include "stac/measurement.hpp"
#include "stac/robot_model.hpp"
#include "stac/sensors_file.hpp"
#include "stac/simulate.hpp"
#include "support/arm_files.hpp"
#include "support/test_util.hpp"

namespace stac {
namespace {

using test::CommandResult;
using test::readFile;
using test::runCommand;
using test::writeFile;

class EvalCli : public ::testing::Test {
 protected:
  void SetUp() override {
    writeFile(urdf(), test::kArmUrdf);
    writeFile(truth(), test::kArmTruth);
    writeFile(seed(), test::kArmSeed);
    const RobotModel robot = RobotModel::fromString(test::kArmUrdf, "arm4");
    const SensorsFile sf = parseSensorsYaml(test::kArmTruth, "truth", robot);
    const MeasurementModel model(robot, sf.sensors);
    SimulationOptions so;
    so.frames = 400;
    so.seed = 21;
    Simulation sim = simulate(model, sf.theta, so);
    writeLog(log(), sim.data.log);
    // The same readings with the markers in millimetres.
    Log mm = sim.data.log;
    for (size_t c = 0; c < mm.columns.size(); ++c)
      if (mm.columns[c].find('.') != std::string::npos) mm.values.col(c) *= 1000.0;
    writeLog(dir_.file("test_mm.csv"), mm);
  }

  std::string urdf() const { return dir_.file("arm.urdf"); }
  std::string truth() const { return dir_.file("truth.yaml"); }
  std::string seed() const { return dir_.file("seed.yaml"); }
  std::string log() const { return dir_.file("test.csv"); }

  CommandResult eval(const std::string& args) const {
    return runCommand(test::appPath("stac_eval") + " " + args);
  }
  std::string base(const std::string& sensors) const {
    return "--urdf " + urdf() + " --sensors " + sensors + " --log " + log() + " --threads 2";
  }
  // One value of the JSON file by a Python expression on d; also proves it
  // parses as JSON.
  std::string jsonValue(const std::string& path, const std::string& expr) const {
    const std::string script = dir_.file("json_value.py");
    writeFile(script,
              "import json, sys\n"
              "d = json.load(open(sys.argv[1]))\n"
              "print(eval(sys.argv[2]))\n");
    const CommandResult r = runCommand("python3 " + script + " " + path + " \"" + expr + "\"");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    std::string out = r.out;
    while (!out.empty() && (out.back() == '\n' || out.back() == '\r')) out.pop_back();
    return out;
  }
  double jsonNumber(const std::string& path, const std::string& expr) const {
    return std::stod(jsonValue(path, expr));
  }

  test::TempDir dir_;
};

TEST_F(EvalCli, TrueParametersPredictAtTheNoiseAndTheJsonHasTheContract) {
  const std::string json = dir_.file("result.json");
  const CommandResult r =
      eval(base(truth()) + " --use joint,tendon --truth " + truth() + " --json " + json);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("estimated from joint,tendon"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("mocap.rotation"), std::string::npos) << r.out;
  EXPECT_EQ(jsonValue(json, "sorted(d.keys())"),
            "['frames', 'frames_at_limit', 'mae', 'per_sensor', 'truth', 'use']");
  // The truth keeps every joint inside its limits: nothing clamped.
  EXPECT_EQ(jsonValue(json, "d['frames_at_limit']"), "{'frames': 0, 'joints': {}}");
  EXPECT_EQ(r.out.find("held at its limit"), std::string::npos) << r.out;
  EXPECT_EQ(jsonValue(json, "d['frames']"), "400");
  EXPECT_EQ(jsonValue(json, "d['use']"), "['joint', 'tendon']");
  EXPECT_EQ(jsonValue(json, "sorted(d['mae'].keys())"), "['joint', 'marker', 'tendon']");
  EXPECT_EQ(jsonValue(json, "len(d['per_sensor'])"), "10");
  EXPECT_EQ(jsonValue(json, "d['per_sensor']['m_l4b']['count']"), "400");
  // Marker noise alone: E‖N3‖ = 1.6σ = 3.2 mm, plus the lever arm times the
  // angle error of q from the pots.
  const double marker = jsonNumber(json, "d['mae']['marker']");
  EXPECT_GT(marker, 0.0029);
  EXPECT_LT(marker, 0.012);
  // The used scalar groups absorb noise: below E|N| = 0.8σ.
  EXPECT_LT(jsonNumber(json, "d['mae']['joint']"), 0.008);
  // The calibration is the truth: every parameter error is 0.
  EXPECT_EQ(jsonValue(json, "len(d['truth'])"), "17");
  EXPECT_LT(jsonNumber(json, "max(abs(v) for v in d['truth'].values())"), 1e-12);
}

// A pot whose gain is 5x too small asks for 5x the angles: the estimate of q
// stops at the joint's limit (widened by 5%), and the report says so rather
// than clamping silently.
TEST_F(EvalCli, FramesClampedAtAJointLimitAreReported) {
  std::string text = test::kArmTruth;
  const std::string from = "gain: -1.5,", to = "gain: -0.3,";
  ASSERT_NE(text.find(from), std::string::npos);
  text.replace(text.find(from), from.size(), to);
  const std::string bad = dir_.file("small_gain.yaml"), json = dir_.file("clamped.json");
  writeFile(bad, text);
  const CommandResult r = eval(base(bad) + " --use joint --json " + json);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const int clamped = std::stoi(jsonValue(json, "d['frames_at_limit']['frames']"));
  EXPECT_GT(clamped, 40) << r.out;   // the motion sweeps most of j1's range
  EXPECT_LE(clamped, 400);
  EXPECT_EQ(jsonValue(json, "list(d['frames_at_limit']['joints'].keys())"), "['j1']");
  EXPECT_NE(r.out.find("frames have a joint held at its limit"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(" j1 ("), std::string::npos) << r.out;
}

TEST_F(EvalCli, SeedParametersAreFarWorseAndTruthErrorsShowIt) {
  const std::string good = dir_.file("good.json"), bad = dir_.file("bad.json");
  ASSERT_EQ(eval(base(truth()) + " --use marker --json " + good).exit_code, 0);
  const CommandResult r = eval(base(seed()) + " --use marker --json " + bad + " --truth " + truth());
  ASSERT_EQ(r.exit_code, 0) << r.err;
  for (const char* g : {"joint", "tendon"}) {
    const std::string key = std::string("d['mae']['") + g + "']";
    EXPECT_GT(jsonNumber(bad, key), 10 * jsonNumber(good, key)) << g;
  }
  // Seed gains 1 vs true gain 30 on the cylinder.
  EXPECT_NEAR(jsonNumber(bad, "d['truth']['cyl.gain']"), 1.0 - 30.0, 1e-12);
  EXPECT_NEAR(jsonNumber(bad, "d['truth']['j2_pot.bias']"), 0.0 - (-0.7), 1e-12);
  EXPECT_NEAR(jsonNumber(bad, "d['truth']['m_l4a.position']"), 0.0, 1e-12);  // fixed
  EXPECT_GT(jsonNumber(bad, "d['truth']['mocap.translation']"), 0.9);
  EXPECT_NE(r.out.find("(" ), std::string::npos);
}

TEST_F(EvalCli, PredictSubsetAndMillimetres) {
  const std::string m = dir_.file("m.json"), mm = dir_.file("mm.json");
  ASSERT_EQ(eval(base(truth()) + " --use marker --predict joint --json " + m).exit_code, 0);
  const CommandResult r = eval("--urdf " + urdf() + " --sensors " + truth() + " --log " +
                               dir_.file("test_mm.csv") +
                               " --mocap-units mm --use marker --predict joint --json " + mm);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(jsonValue(m, "list(d['mae'].keys())"), "['joint']");
  EXPECT_EQ(jsonValue(m, "sorted(d['per_sensor'].keys())"),
            "['j1_pot', 'j2_pot', 'j3_pot', 'j4_pot']");
  EXPECT_NEAR(jsonNumber(mm, "d['mae']['joint']"), jsonNumber(m, "d['mae']['joint']"), 1e-6);
}

TEST_F(EvalCli, BadGroupNamesAreUsageErrors) {
  for (const char* use : {"joints", "joint,", "marker,,joint", "joint,joint", "''"}) {
    const CommandResult r = eval(base(truth()) + " --use " + use);
    EXPECT_EQ(r.exit_code, 2) << use << "\n" << r.err;
    EXPECT_NE(r.err.find("--use"), std::string::npos) << r.err;
  }
  const CommandResult p = eval(base(truth()) + " --use joint --predict tendons");
  EXPECT_EQ(p.exit_code, 2);
  EXPECT_NE(p.err.find("tendons"), std::string::npos) << p.err;
  EXPECT_NE(p.err.find("marker, joint, tendon"), std::string::npos) << p.err;
  EXPECT_EQ(eval(base(truth())).exit_code, 2);  // --use is required
  EXPECT_EQ(eval(base(truth()) + " --use joint --threads -1").exit_code, 2);
  EXPECT_EQ(eval(base(truth()) + " --use joint --mocap-units cm").exit_code, 2);
}

TEST_F(EvalCli, UsedGroupMustExistInTheSensorsFile) {
  // Joint sensors only: --use marker names a group the file lacks.
  const std::string pots = dir_.file("pots.yaml");
  writeFile(pots,
            "joint_sensors:\n"
            "  - {name: j1_pot, joint: j1, gain: -1.5, bias: 0.4, sigma: 0.01}\n"
            "  - {name: j2_pot, joint: j2, gain: 2.1, bias: -0.7, sigma: 0.01}\n"
            "  - {name: j3_pot, joint: j3, gain: 0.8, bias: 1.1, sigma: 0.01}\n"
            "  - {name: j4_pot, joint: j4, gain: -1.2, bias: 0.2, sigma: 0.01}\n");
  for (const char* args : {" --use marker", " --use joint --predict tendon"}) {
    const CommandResult r = eval(base(pots) + args);
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_NE(r.err.find("pots.yaml"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("has no"), std::string::npos) << r.err;
  }
}

TEST_F(EvalCli, MissingAndBadInputsNameTheFile) {
  const std::string missing = dir_.file("nope.csv");
  CommandResult r = eval("--urdf " + urdf() + " --sensors " + truth() + " --log " + missing +
                         " --use joint");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("nope.csv"), std::string::npos) << r.err;
  r = eval(base(dir_.file("absent.yaml")) + " --use joint");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("absent.yaml"), std::string::npos) << r.err;
  r = eval(base(truth()) + " --use joint --truth " + dir_.file("gone.yaml"));
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("gone.yaml"), std::string::npos) << r.err;
  // A truth with other sensors is bad input naming it.
  const std::string other = dir_.file("other.yaml");
  writeFile(other, "joint_sensors:\n  - {name: j1_pot, joint: j1}\n");
  r = eval(base(truth()) + " --use joint --truth " + other);
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("other.yaml"), std::string::npos) << r.err;
  // A log whose columns do not match the sensors.
  const std::string short_log = dir_.file("short.csv");
  writeFile(short_log, "time,j1_pot\n0,0.1\n");
  r = eval("--urdf " + urdf() + " --sensors " + truth() + " --log " + short_log + " --use joint");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("short.csv"), std::string::npos) << r.err;
}

TEST_F(EvalCli, NeverOverwritesAnInputNorLeavesPartialOutput) {
  const std::string before = readFile(log());
  for (const std::string& target : {log(), truth(), urdf()}) {
    const CommandResult r =
        eval(base(truth()) + " --use joint --truth " + truth() + " --json " + target);
    EXPECT_EQ(r.exit_code, 2) << target;
    EXPECT_NE(r.err.find("refusing to overwrite"), std::string::npos) << r.err;
  }
  EXPECT_EQ(readFile(log()), before);
  EXPECT_EQ(readFile(truth()), test::kArmTruth);
  // Bad input after the outputs were checked: no JSON file appears.
  const std::string json = dir_.file("out.json");
  EXPECT_EQ(eval(base(truth()) + " --use joint --truth " + dir_.file("gone.yaml") + " --json " +
                 json).exit_code,
            2);
  EXPECT_EQ(runCommand("test -e " + json).exit_code, 1);
  EXPECT_EQ(eval(base(truth()) + " --use joint --json " + dir_.file("no/such/dir/x.json"))
                .exit_code,
            2);
  // No temporary files left behind by a successful run either.
  ASSERT_EQ(eval(base(truth()) + " --use joint --json " + json).exit_code, 0);
  for (const std::string& f : dir_.list()) EXPECT_EQ(f.find(".tmp"), std::string::npos) << f;
}

TEST_F(EvalCli, HelpAndVersion) {
  CommandResult r = eval("--help");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.out.find("--use"), std::string::npos);
  EXPECT_NE(r.out.find("--predict"), std::string::npos);
  r = eval("--version");
  EXPECT_EQ(r.exit_code, 0);
  EXPECT_NE(r.out.find("stac_eval"), std::string::npos);
  EXPECT_EQ(eval("--bogus").exit_code, 2);
}

}  // namespace
}  // namespace stac
