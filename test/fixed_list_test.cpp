// `fixed` as a list (SPEC §3): the reader's forms and errors (file, line,
// key), the writer writing back what was read, θ's free mask, and the
// θ-phase closed forms with one part held.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "solve/theta_phase.hpp"
#include "stac/error.hpp"
#include "stac/sensors_file.hpp"
#include "stac/theta_space.hpp"
#include "support/arm_files.hpp"

namespace stac {
namespace {

const RobotModel& arm() {
  static const RobotModel m = RobotModel::fromString(test::kArmUrdf, "arm4.urdf");
  return m;
}

SensorsFile parse(const std::string& yaml) { return parseSensorsYaml(yaml, "s.yaml", arm()); }

// A file with the mocap frame's, a marker's, a joint sensor's and a tendon
// sensor's `fixed` given as frame, marker, joint and tendon.
std::string file(const std::string& frame, const std::string& marker, const std::string& joint,
                 const std::string& tendon) {
  return "mocap:\n"
         "  frame:\n"
         "    fixed: " + frame + "\n"
         "  markers:\n"
         "    - name: m\n"
         "      link: l2\n"
         "      fixed: " + marker + "\n"
         "joint_sensors:\n"
         "  - name: pot\n"
         "    joint: j2\n"
         "    gain: 1.0\n"
         "    bias: 0.25\n"
         "    fixed: " + joint + "\n"
         "tendon_sensors:\n"
         "  - name: cyl\n"
         "    fixed: " + tendon + "\n"
         "    coupling: {j3: 0.01}\n";
}

// Lines of the `fixed` keys in file(): frame 3, marker 7, joint 13, tendon 16.
void expectError(const std::string& yaml, int line, const std::string& key,
                 const std::string& what) {
  try {
    parse(yaml);
    ADD_FAILURE() << "no error for:\n" << yaml;
  } catch (const InputError& e) {
    const std::string w = e.what();
    EXPECT_EQ(e.file(), "s.yaml") << w;
    EXPECT_EQ(e.line(), line) << w;
    EXPECT_EQ(w.rfind("s.yaml:" + std::to_string(line) + ":", 0), 0u) << w;
    EXPECT_NE(w.find("'" + key + "'"), std::string::npos) << "expected '" << key << "' in: " << w;
    EXPECT_NE(w.find(what), std::string::npos) << "expected '" << what << "' in: " << w;
  }
}

TEST(FixedList, ReadsEveryForm) {
  const SensorsFile a = parse(file("[rotation]", "true", "[gain]", "[bias]"));
  EXPECT_TRUE(a.sensors.mocap_frame_fixed.rotation);
  EXPECT_FALSE(a.sensors.mocap_frame_fixed.translation);
  EXPECT_TRUE(a.sensors.markers[0].fixed);
  EXPECT_TRUE(a.sensors.joint_sensors[0].fixed.gain);
  EXPECT_FALSE(a.sensors.joint_sensors[0].fixed.bias);
  EXPECT_FALSE(a.sensors.tendon_sensors[0].fixed.gain);
  EXPECT_TRUE(a.sensors.tendon_sensors[0].fixed.bias);

  const SensorsFile b = parse(file("[translation]", "false", "[bias, gain]", "[]"));
  EXPECT_FALSE(b.sensors.mocap_frame_fixed.rotation);
  EXPECT_TRUE(b.sensors.mocap_frame_fixed.translation);
  EXPECT_TRUE(b.sensors.joint_sensors[0].fixed.all());
  EXPECT_FALSE(b.sensors.tendon_sensors[0].fixed.any());

  const SensorsFile c = parse(file("[rotation, translation]", "false", "true", "false"));
  EXPECT_TRUE(c.sensors.mocap_frame_fixed.all());
  EXPECT_TRUE(c.sensors.joint_sensors[0].fixed.all());

  // Block style.
  const SensorsFile d = parse(
      "joint_sensors:\n  - name: pot\n    joint: j1\n    fixed:\n      - bias\n");
  EXPECT_TRUE(d.sensors.joint_sensors[0].fixed.bias);
  EXPECT_FALSE(d.sensors.joint_sensors[0].fixed.gain);
}

TEST(FixedList, ParameterTheItemDoesNotHave) {
  expectError(file("false", "false", "[rotation]", "false"), 13, "joint_sensors[0].fixed",
              "a joint sensor has no rotation (its parameters: gain, bias)");
  expectError(file("false", "false", "false", "[translation]"), 16, "tendon_sensors[0].fixed",
              "a tendon sensor has no translation");
  expectError(file("[gain]", "false", "false", "false"), 3, "mocap.frame.fixed",
              "the mocap frame has no gain (its parameters: rotation, translation)");
  expectError(file("false", "[gain]", "false", "false"), 7, "mocap.markers[0].fixed",
              "a marker has no gain");
  expectError(file("false", "[position]", "false", "false"), 7, "mocap.markers[0].fixed",
              "held or free as a whole");
  expectError(file("false", "[]", "false", "false"), 7, "mocap.markers[0].fixed",
              "expected true or false, not a list");
}

TEST(FixedList, UnknownNameAndNameGivenTwice) {
  expectError(file("false", "false", "[gian]", "false"), 13, "joint_sensors[0].fixed",
              "unknown parameter 'gian' (expected some of: gain, bias)");
  expectError(file("[rot]", "false", "false", "false"), 3, "mocap.frame.fixed",
              "unknown parameter 'rot'");
  expectError(file("false", "false", "[gain, gain]", "false"), 13, "joint_sensors[0].fixed",
              "'gain' given twice (first on line 13)");
  expectError(file("[rotation, rotation]", "false", "false", "false"), 3, "mocap.frame.fixed",
              "'rotation' given twice");
  expectError(file("false", "false", "[[gain]]", "false"), 13, "joint_sensors[0].fixed",
              "expected true, false or a list of parameter names");
  // A block list reports the line of the offending name.
  expectError("joint_sensors:\n  - name: pot\n    joint: j1\n    fixed:\n      - bias\n"
              "      - bias\n",
              6, "joint_sensors[0].fixed", "'bias' given twice (first on line 5)");
  expectError(file("false", "false", "maybe", "false"), 13, "joint_sensors[0].fixed",
              "expected true or false");
}

// Writing what was read gives a file that reads back the same: lists where
// one part is held, true/false otherwise.
TEST(FixedList, WriterWritesBackWhatWasRead) {
  const struct {
    const char *frame, *joint, *tendon, *frame_out, *joint_out, *tendon_out;
  } cases[] = {
      {"[rotation]", "[gain]", "[bias]", "[rotation]", "[gain]", "[bias]"},
      {"[translation]", "[bias]", "[gain]", "[translation]", "[bias]", "[gain]"},
      {"[translation, rotation]", "[bias, gain]", "[]", "true", "true", "false"},
      {"false", "true", "false", "false", "true", "false"},
  };
  for (const auto& c : cases) {
    const SensorsFile a = parse(file(c.frame, "true", c.joint, c.tendon));
    const std::string yaml = sensorsToYaml(a.sensors, a.theta);
    EXPECT_NE(yaml.find("    fixed: " + std::string(c.frame_out) + "\n  markers:"),
              std::string::npos)
        << yaml;
    EXPECT_NE(yaml.find("    fixed: " + std::string(c.joint_out) + "\ntendon_sensors:"),
              std::string::npos)
        << yaml;
    EXPECT_NE(yaml.find("    fixed: " + std::string(c.tendon_out) + "\n    coupling:"),
              std::string::npos)
        << yaml;
    const SensorsFile b = parse(yaml);
    EXPECT_TRUE(b.sensors.mocap_frame_fixed == a.sensors.mocap_frame_fixed) << yaml;
    EXPECT_TRUE(b.sensors.joint_sensors[0].fixed == a.sensors.joint_sensors[0].fixed) << yaml;
    EXPECT_TRUE(b.sensors.tendon_sensors[0].fixed == a.sensors.tendon_sensors[0].fixed) << yaml;
    EXPECT_EQ(b.sensors.markers[0].fixed, a.sensors.markers[0].fixed);
    EXPECT_EQ(ThetaSpace(b.sensors).free(), ThetaSpace(a.sensors).free()) << yaml;
    EXPECT_EQ(ThetaSpace(b.sensors).minus(b.theta, a.theta).norm(), 0.0);
    EXPECT_EQ(sensorsToYaml(b.sensors, b.theta), yaml);
  }
}

TEST(FixedList, FreeMaskFollowsEachPart) {
  const SensorsFile f = parse(file("[rotation]", "false", "[gain]", "[bias]"));
  const ThetaSpace space(f.sensors);
  for (int i = 0; i < 3; ++i) {
    EXPECT_FALSE(space.free()[ThetaSpace::kRotationOffset + i]);
    EXPECT_TRUE(space.free()[ThetaSpace::kTranslationOffset + i]);
  }
  EXPECT_FALSE(space.free()[space.jointOffset(0)]);
  EXPECT_TRUE(space.free()[space.jointOffset(0) + 1]);
  EXPECT_TRUE(space.free()[space.tendonOffset(0)]);
  EXPECT_FALSE(space.free()[space.tendonOffset(0) + 1]);
  EXPECT_EQ(space.freeSize(), space.size() - 5);
  // A step over the free entries leaves the held parts exactly alone.
  const SensorParameters moved = space.plusFree(f.theta, Eigen::VectorXd::Ones(space.freeSize()));
  EXPECT_EQ(moved.joint_sensor[0].gain, f.theta.joint_sensor[0].gain);
  EXPECT_NE(moved.joint_sensor[0].bias, f.theta.joint_sensor[0].bias);
  EXPECT_TRUE(moved.mocap.rotation.coeffs() == f.theta.mocap.rotation.coeffs());
  EXPECT_NE(moved.mocap.translation, f.theta.mocap.translation);
}

// ---- Closed forms with one part held ----

TEST(FixedList, LineFitWithOnePartHeld) {
  std::vector<double> x = {0.1, -0.4, 0.9, 1.3, -1.1}, p(5), w = {1, 2, 1, 3, 1};
  for (int i = 0; i < 5; ++i) p[i] = -2.5 * x[i] + 0.75 + (i % 2 ? 0.01 : -0.01);
  p[2] = NAN;
  // Gain held: the bias is the weighted mean of p - g x.
  const LineFit g = fitGainBias(x.data(), p.data(), w.data(), 5, {-2.5, 0.0}, {true, false});
  double sw = 0, sr = 0;
  for (int i : {0, 1, 3, 4}) sw += w[i], sr += w[i] * (p[i] + 2.5 * x[i]);
  EXPECT_EQ(g.value.gain, -2.5);
  EXPECT_NEAR(g.value.bias, sr / sw, 1e-15);
  EXPECT_TRUE(g.gain_identifiable);
  // Bias held: the gain minimises Σ w (g x + b - p)², so the residuals are
  // orthogonal to x.
  const LineFit b = fitGainBias(x.data(), p.data(), w.data(), 5, {1.0, 0.75}, {false, true});
  EXPECT_EQ(b.value.bias, 0.75);
  double dot = 0;
  for (int i : {0, 1, 3, 4}) dot += w[i] * x[i] * (b.value.gain * x[i] + 0.75 - p[i]);
  EXPECT_NEAR(dot, 0.0, 1e-14);
  EXPECT_NEAR(b.value.gain, -2.5, 0.02);
  // A bias-held sensor whose input never left 0 keeps its gain.
  std::vector<double> zero(5, 0.0);
  const LineFit z = fitGainBias(zero.data(), p.data(), nullptr, 5, {1.5, 0.75}, {false, true});
  EXPECT_FALSE(z.gain_identifiable);
  EXPECT_EQ(z.value.gain, 1.5);
}

TEST(FixedList, ProcrustesWithOnePartHeld) {
  const Eigen::Quaterniond q(Eigen::AngleAxisd(2.5, Eigen::Vector3d(1, -1, 2).normalized()));
  const Eigen::Vector3d t(0.4, -1.0, 2.0);
  std::vector<Eigen::Vector3d> a, b;
  std::vector<double> w;
  for (int i = 0; i < 6; ++i) {
    a.emplace_back(std::sin(i), std::cos(2.0 * i), 0.3 * i);
    b.push_back(q * a.back() + t);
    w.push_back(1.0 + i);
  }
  MocapFrame wrong;
  wrong.rotation = q;
  wrong.translation = Eigen::Vector3d(5, 5, 5);
  const auto r = procrustes(a, b, w, wrong, {true, false});
  ASSERT_TRUE(r);
  EXPECT_TRUE(r->rotation.coeffs() == q.coeffs());
  EXPECT_LT((r->translation - t).norm(), 1e-12);
  wrong.rotation = Eigen::Quaterniond::Identity();
  wrong.translation = t;
  const auto s = procrustes(a, b, w, wrong, {false, true});
  ASSERT_TRUE(s);
  EXPECT_EQ(s->translation, t);
  EXPECT_LT(s->rotation.angularDistance(q), 1e-12);
  const auto both = procrustes(a, b, w, wrong, {true, true});
  ASSERT_TRUE(both);
  EXPECT_TRUE(both->rotation.coeffs() == wrong.rotation.coeffs());
}

}  // namespace
}  // namespace stac
