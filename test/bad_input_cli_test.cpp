// Bad input end to end, each with its exact message and exit code 2 and no
// output left behind: logs without data (no rows, no usable frame, a
// sensor never read, a wide header over empty lines), option values out
// of range in every app, and sensors files that would hang yaml-cpp.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "stac/log.hpp"
#include "stac/measurement.hpp"
#include "stac/robot_model.hpp"
#include "stac/sensors_file.hpp"
#include "stac/simulate.hpp"
#include "support/arm_files.hpp"
#include "support/test_util.hpp"

namespace stac {
namespace {

const double kNaN = std::numeric_limits<double>::quiet_NaN();

class BadInputCli : public ::testing::Test {
 protected:
  void SetUp() override {
    test::writeFile(file("arm.urdf"), test::kArmUrdf);
    test::writeFile(file("truth.yaml"), test::kArmTruth);
    test::writeFile(file("seed.yaml"), test::kArmSeed);
    const RobotModel robot = RobotModel::fromString(test::kArmUrdf, "arm4");
    const SensorsFile sf = parseSensorsYaml(test::kArmTruth, "truth", robot);
    SimulationOptions so;
    so.frames = 30;
    so.seed = 5;
    log_ = simulate(MeasurementModel(robot, sf.sensors), sf.theta, so).data.log;
    writeLog(file("data.csv"), log_);
  }
  std::string file(const std::string& n) const { return dir_.file(n); }
  // Runs `app` on the arm (through `timeout 5`, so that a hang fails the
  // test instead of stalling it).
  test::CommandResult run(const std::string& app, const std::string& args) const {
    return test::runCommand("timeout 5 " + test::appPath(app) + " --urdf " + file("arm.urdf") +
                            " " + args);
  }
  test::CommandResult calib(const std::string& log, const std::string& extra = "") const {
    return run("stac_calib", "--log " + log + " --sensors " + file("seed.yaml") + " --output " +
                                 file("out.yaml") + " --quiet " + extra);
  }
  // Exit 2, exactly `err` on stderr, and no file added to the folder.
  void expectRefused(const test::CommandResult& r, const std::string& err,
                     const std::vector<std::string>& before) const {
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_EQ(r.err, err);
    EXPECT_EQ(dir_.list(), before);
  }
  // stac_calib and stac_eval both refuse `log` with "<app>: error: <what>".
  void expectBothRefuse(const std::string& log, const std::string& what) const {
    const auto before = dir_.list();
    expectRefused(calib(log), "stac_calib: error: " + what, before);
    expectRefused(run("stac_eval",
                      "--sensors " + file("truth.yaml") + " --log " + log + " --use joint"),
                  "stac_eval: error: " + what, before);
  }
  // The simulated log with the columns named in `blank` emptied.
  void writeBlanked(const std::string& path, const std::vector<std::string>& blank) const {
    Log log = log_;
    for (size_t c = 0; c < log.columns.size(); ++c)
      for (const std::string& b : blank)
        if (log.columns[c] == b)
          for (int t = 0; t < log.numFrames(); ++t) log.values(t, c) = kNaN;
    writeLog(path, log);
  }
  test::TempDir dir_;
  Log log_;
};

TEST_F(BadInputCli, LogWithNoUsableFrame) {
  writeBlanked(file("empty.csv"), log_.columns);  // the time is kept
  expectBothRefuse(file("empty.csv"), file("empty.csv") +
                                          ": no usable frame: every reading of the 30 frame(s) "
                                          "is empty (or nan)\n");
}

// A sensor or marker without a single reading cannot be estimated: an
// error naming each of them and the log, not a calibration of nothing.
TEST_F(BadInputCli, SensorOrMarkerNeverReadIsAnError) {
  writeBlanked(file("blind.csv"), {"j2_pot", "m_l4b.x", "m_l4b.y", "m_l4b.z"});
  const auto before = dir_.list();
  expectRefused(calib(file("blind.csv")),
                "stac_calib: error: " + file("blind.csv") +
                    ": no reading at all in the 30 frame(s) for marker 'm_l4b', joint sensor "
                    "'j2_pot': a calibration cannot estimate what nothing measures (give it "
                    "readings, or remove it from the sensors)\n",
                before);
  // A marker seen only with one coordinate is never seen.
  writeBlanked(file("half.csv"), {"m_l2a.z"});
  const auto r = calib(file("half.csv"));
  EXPECT_EQ(r.exit_code, 2) << r.err;
  EXPECT_NE(r.err.find("for marker 'm_l2a':"), std::string::npos) << r.err;
}

TEST_F(BadInputCli, HeaderOnlyLogHasNoDataRows) {
  const std::string text = test::readFile(file("data.csv"));
  test::writeFile(file("header.csv"), text.substr(0, text.find('\n') + 1));
  expectBothRefuse(file("header.csv"),
                   file("header.csv") +
                       ":1: the log has no data rows (a header and nothing after it)\n");
}

// 100 KB (a 15,000-column header, 40,000 empty lines) once asked for
// 4.8 GB: under a 1 GB address-space limit it must still answer, fast.
TEST_F(BadInputCli, WideHeaderOverEmptyLinesIsRefusedQuickly) {
  std::string csv;
  for (int c = 0; c < 15000; ++c) csv += (c ? ",c" : "c") + std::to_string(c);
  test::writeFile(file("wide.csv"), csv + std::string(40000, '\n'));
  const auto before = dir_.list();
  // AddressSanitizer reserves terabytes of address space for its shadow
  // memory, so the limit applies to the plain build only (ASan reports an
  // allocation of that size by itself).
#if defined(__SANITIZE_ADDRESS__)
  const std::string limit;
#else
  const std::string limit = "ulimit -v 1000000; ";
#endif
  const auto r = test::runCommand(limit + "timeout 5 " + test::appPath("stac_calib") +
                                  " --urdf " + file("arm.urdf") + " --log " + file("wide.csv") +
                                  " --output " + file("out.yaml"));
  expectRefused(r,
                "stac_calib: error: " + file("wide.csv") +
                    ":1: the log has no data rows (a header and nothing after it)\n",
                before);
}

// Every app reports an option value out of range with the flag and the
// value as typed.
TEST_F(BadInputCli, OptionValuesOutOfRangeNameFlagAndValue) {
  struct Case {
    std::string app, args, message;
  };
  const std::string calib_args = "--log " + file("data.csv") + " --output " + file("o.yaml") + " ";
  const std::string eval_args =
      "--sensors " + file("truth.yaml") + " --log " + file("data.csv") + " --use joint ";
  const std::string sim_args = "--sensors " + file("truth.yaml") + " --log " + file("s.csv") + " ";
  const std::vector<Case> cases = {
      {"stac_calib", calib_args + "--loss-scale -1",
       "--loss-scale -1: must be positive and finite"},
      {"stac_calib", calib_args + "--loss-scale=-1",
       "--loss-scale=-1: must be positive and finite"},
      {"stac_calib", calib_args + "--tolerance -1", "--tolerance -1: must be finite and >= 0"},
      {"stac_calib", calib_args + "--tolerance inf", "--tolerance inf: expects a finite number"},
      {"stac_calib", calib_args + "--threads -2",
       "--threads -2: must be at least 0 (0 = all cores)"},
      {"stac_calib", calib_args + "--max-iterations 0", "--max-iterations 0: must be at least 1"},
      {"stac_calib", calib_args + "--max-iterations x", "--max-iterations x: expects an integer"},
      {"stac_calib", calib_args + "--holdout 2",
       "--holdout 2: must be a fraction strictly between 0 and 1"},
      {"stac_calib", calib_args + "--method ekf --ekf-q-speed 0",
       "--ekf-q-speed 0: must be positive and finite"},
      {"stac_calib", calib_args + "--method ekf --ekf-iterations 0",
       "--ekf-iterations 0: must be at least 1"},
      {"stac_calib", calib_args + "--method ekf --ekf-theta-std -3",
       "--ekf-theta-std -3: must be positive and finite"},
      {"stac_calib", calib_args + "--loss fair", "--loss fair: must be one of none|huber|cauchy"},
      {"stac_eval", eval_args + "--threads -2", "--threads -2: must be at least 0 (0 = all cores)"},
      {"stac_eval", eval_args + "--predict joint,bogus",
       "--predict joint,bogus: unknown sensor group 'bogus' (expected a comma-separated list "
       "of marker, joint, tendon)"},
      {"stac_eval", eval_args + "--predict joint,,tendon",
       "--predict joint,,tendon: an empty sensor group"},
      {"stac_calib", calib_args + "--sensors " + file("truth.yaml") + " --joint-origins j1,",
       "--joint-origins j1,: an empty joint name"},
      {"stac_calib", calib_args + "--sensors " + file("truth.yaml") + " --joint-origins all --origin-prior 0.01,",
       "--origin-prior 0.01,: an empty number"},
      {"stac_simulate", sim_args + "--frames 0", "--frames 0: must be at least 1"},
      {"stac_simulate", sim_args + "--frames 9 --noise-scale -1",
       "--noise-scale -1: must be finite and >= 0"},
      {"stac_simulate", sim_args + "--frames 9 --dropout 2",
       "--dropout 2: must be a fraction in [0, 1]"},
      {"stac_simulate", sim_args + "--frames 9 --outliers -0.5",
       "--outliers -0.5: must be a fraction in [0, 1]"},
      {"stac_simulate", sim_args + "--frames 9 --rate 0", "--rate 0: must be positive and finite"},
      {"stac_simulate", sim_args + "--frames 9 --seed -3",
       "--seed -3: expects a non-negative integer (at most 2^64-1)"},
  };
  const auto before = dir_.list();
  for (const Case& c : cases) {
    const auto r = run(c.app, c.args);
    EXPECT_EQ(r.exit_code, 2) << c.args << "\n" << r.err;
    EXPECT_EQ(r.err.substr(0, r.err.find('\n')), c.app + ": error: " + c.message) << c.args;
    EXPECT_EQ(dir_.list(), before) << c.args;
  }
}

// Each loops yaml-cpp 0.7 for ever, memory climbing: refused in time
// (timeout's 124 would mean a hang), naming the file and the line.
TEST_F(BadInputCli, SensorsFilesThatWouldHangTheYamlParser) {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {",]", ":1:1:"},          {", 1]", ":1:1:"},  {" ,]", ":1:2:"},
      {"[1], 2", ":1:4:"},      {"- [1]\n,", ":2:1:"}, {"mocap:\n  sigma: 1\n,", ":3:1:"},
      {"---\n,", ":2:1:"},
  };
  const auto before = dir_.list();
  for (const auto& [yaml, where] : cases) {
    test::writeFile(file("bad.yaml"), yaml);
    const auto r = run("stac_calib", "--log " + file("data.csv") + " --sensors " +
                                         file("bad.yaml") + " --output " + file("out.yaml"));
    EXPECT_NE(r.exit_code, 124) << "hung on: " << yaml;
    EXPECT_EQ(r.exit_code, 2) << yaml << "\n" << r.err;
    EXPECT_EQ(r.err.rfind("stac_calib: error: " + file("bad.yaml") + where +
                              " malformed YAML: a ',' outside any [ ] or { } collection",
                          0),
              0u)
        << r.err;
    EXPECT_EQ(dir_.list().size(), before.size() + 1) << "only bad.yaml was added";
  }
}

}  // namespace
}  // namespace stac
