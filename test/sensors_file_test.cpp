// The sensors file (SPEC §3): the schema and its defaults, the exact
// save -> load round trip (seed and calibration output), rpy/quaternion,
// every error with its file, line and key, and inference from a log header.
#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <string>

#include "stac/error.hpp"
#include "stac/file_io.hpp"
#include "stac/log.hpp"
#include "stac/robot_model.hpp"
#include "stac/sensors_file.hpp"
#include "support/test_util.hpp"

namespace stac {
namespace {

// Every link and joint the SPEC §3 example names, a fixed joint, a mimic
// follower and a prismatic joint.
const char* kUrdf = R"(<?xml version="1.0"?>
<robot name="tiny">
  <link name="torso"/><link name="head"/><link name="l_upper"/><link name="l_forearm"/>
  <link name="tool"/><link name="index_1"/><link name="index_2"/><link name="slider"/>
  <joint name="neck" type="revolute"><parent link="torso"/><child link="head"/>
    <origin xyz="0 0 0.3"/><axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <joint name="l_shoulder" type="revolute"><parent link="torso"/><child link="l_upper"/>
    <origin xyz="0 0.2 0.2"/><axis xyz="0 0 1"/><limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
  <joint name="l_elbow" type="revolute"><parent link="l_upper"/><child link="l_forearm"/>
    <origin xyz="0.3 0 0"/><axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
  <joint name="tool_joint" type="fixed"><parent link="l_forearm"/><child link="tool"/>
    <origin xyz="0.25 0 0"/></joint>
  <joint name="index_j1" type="revolute"><parent link="l_forearm"/><child link="index_1"/>
    <origin xyz="0.3 0 0"/><axis xyz="0 1 0"/><limit lower="0" upper="1.5" effort="1" velocity="1"/></joint>
  <joint name="index_j2" type="revolute"><parent link="index_1"/><child link="index_2"/>
    <origin xyz="0.04 0 0"/><axis xyz="0 1 0"/><limit lower="0" upper="1.5" effort="1" velocity="1"/>
    <mimic joint="index_j1" multiplier="0.7"/></joint>
  <joint name="slide" type="prismatic"><parent link="torso"/><child link="slider"/>
    <axis xyz="1 0 0"/><limit lower="0" upper="0.2" effort="1" velocity="1"/></joint>
</robot>)";

const RobotModel& model() {
  static const RobotModel m = RobotModel::fromString(kUrdf, "tiny.urdf");
  return m;
}

// SPEC §3's example, verbatim.
const char* kSpecExample = R"(mocap:
  sigma: 0.002                  # metres
  frame:                        # x_mocap = R x_base + t
    translation: [0.0, 0.0, 0.0]
    rpy: [0.0, 0.0, 0.0]        # URDF convention: R = Rz(yaw) Ry(pitch) Rx(roll)
    fixed: false                # or quaternion: [w, x, y, z] instead of rpy
  markers:
    - name: m_forearm
      link: l_forearm
      position: [0.0, 0.0, 0.0] # in the link's frame
      fixed: false
      # sigma: 0.001            # optional, overrides mocap.sigma for this marker
joint_sensors:
  - name: l_elbow_pot           # the log column
    joint: l_elbow
    gain: 1.0
    bias: 0.0
    sigma: 0.01
    fixed: false
tendon_sensors:
  - name: neck_cyl_1
    gain: 1.0
    bias: 0.0
    sigma: 0.01
    path:
      - {link: torso, point: [0.03, 0.02, 0.10]}
      - {link: head,  point: [0.03, 0.02, -0.02]}
  - name: index_flexor
    gain: 1.0
    bias: 0.0
    sigma: 0.01
    coupling: {index_j1: 0.009, index_j2: 0.009}
)";

bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

SensorsFile parse(const std::string& yaml) { return parseSensorsYaml(yaml, "s.yaml", model()); }

InputError yamlError(const std::string& yaml) {
  try {
    parse(yaml);
  } catch (const InputError& e) {
    return e;
  }
  ADD_FAILURE() << "no error for:\n" << yaml;
  return InputError("", "");
}

// The error names the file and `line` ("s.yaml:<line>: ...") and contains
// `key` (the key path, e.g. "joint_sensors[1].gain") and `what`.
void expectYamlError(const std::string& yaml, int line, const std::string& key,
                     const std::string& what = "") {
  const InputError e = yamlError(yaml);
  const std::string w = e.what();
  EXPECT_EQ(e.file(), "s.yaml") << w;
  EXPECT_EQ(e.line(), line) << w;
  EXPECT_EQ(w.rfind("s.yaml:" + std::to_string(line) + ":", 0), 0u) << w;
  EXPECT_NE(w.find(key), std::string::npos) << "expected '" << key << "' in: " << w;
  EXPECT_NE(w.find(what), std::string::npos) << "expected '" << what << "' in: " << w;
}

Eigen::Matrix3d rx(double a) {
  Eigen::Matrix3d r;
  r << 1, 0, 0, 0, std::cos(a), -std::sin(a), 0, std::sin(a), std::cos(a);
  return r;
}
Eigen::Matrix3d ry(double a) {
  Eigen::Matrix3d r;
  r << std::cos(a), 0, std::sin(a), 0, 1, 0, -std::sin(a), 0, std::cos(a);
  return r;
}
Eigen::Matrix3d rz(double a) {
  Eigen::Matrix3d r;
  r << std::cos(a), -std::sin(a), 0, std::sin(a), std::cos(a), 0, 0, 0, 1;
  return r;
}
Eigen::Matrix3d urdfRpy(const Eigen::Vector3d& rpy) { return rz(rpy[2]) * ry(rpy[1]) * rx(rpy[0]); }

const char* kOnePot = "joint_sensors:\n  - {name: pot, joint: l_elbow}\n";

// ---- the schema ----

TEST(SensorsFile, ReadsTheSpecExample) {
  const SensorsFile f = parse(kSpecExample);
  const SensorSet& s = f.sensors;
  EXPECT_EQ(s.mocap_sigma, 0.002);
  EXPECT_FALSE(s.mocap_frame_fixed.any());
  ASSERT_EQ(s.markers.size(), 1u);
  EXPECT_EQ(s.markers[0].name, "m_forearm");
  EXPECT_EQ(s.markers[0].link_name, "l_forearm");
  EXPECT_EQ(s.markers[0].link, *model().linkIndex("l_forearm"));
  EXPECT_EQ(s.markers[0].sigma, 0.002);
  EXPECT_FALSE(s.markers[0].sigma_overridden);
  ASSERT_EQ(s.joint_sensors.size(), 1u);
  EXPECT_EQ(s.joint_sensors[0].name, "l_elbow_pot");
  EXPECT_EQ(s.joint_sensors[0].joint, *model().movableJointIndex("l_elbow"));
  EXPECT_EQ(s.joint_sensors[0].sigma, 0.01);
  ASSERT_EQ(s.tendon_sensors.size(), 2u);
  const TendonSensorConfig& cyl = s.tendon_sensors[0];
  EXPECT_EQ(cyl.kind, TendonSensorConfig::Kind::kPath);
  ASSERT_EQ(cyl.path.size(), 2u);
  EXPECT_EQ(cyl.path[0].link, *model().linkIndex("torso"));
  EXPECT_EQ(cyl.path[1].link, *model().linkIndex("head"));
  EXPECT_EQ(cyl.path[1].point, Eigen::Vector3d(0.03, 0.02, -0.02));
  const TendonSensorConfig& flexor = s.tendon_sensors[1];
  EXPECT_EQ(flexor.kind, TendonSensorConfig::Kind::kCoupling);
  ASSERT_EQ(flexor.coupling.size(), 2u);
  EXPECT_EQ(flexor.coupling[0].joint_name, "index_j1");
  EXPECT_EQ(flexor.coupling[1].joint, *model().movableJointIndex("index_j2"));  // a mimic follower
  EXPECT_EQ(flexor.coupling[1].coefficient, 0.009);
  ASSERT_EQ(f.theta.marker_position.size(), 1u);
  ASSERT_EQ(f.theta.joint_sensor.size(), 1u);
  ASSERT_EQ(f.theta.tendon_sensor.size(), 2u);
  EXPECT_EQ(f.theta.tendon_sensor[1].gain, 1.0);
  EXPECT_TRUE(f.theta.mocap.rotation.isApprox(Eigen::Quaterniond::Identity()));
}

TEST(SensorsFile, Defaults) {
  const SensorsFile f = parse(
      "mocap:\n  markers:\n    - {name: a, link: tool}\n    - {name: b, link: torso, sigma: 0.001}\n"
      "joint_sensors:\n  - {name: pot, joint: index_j2}\n"
      "tendon_sensors:\n  - {name: c, coupling: {slide: 2}}\n");
  const SensorSet& s = f.sensors;
  EXPECT_EQ(s.mocap_sigma, 0.002);
  EXPECT_FALSE(s.mocap_frame_fixed.any());
  EXPECT_EQ(s.markers[0].sigma, 0.002);
  EXPECT_FALSE(s.markers[0].sigma_overridden);
  EXPECT_FALSE(s.markers[0].fixed);
  EXPECT_EQ(s.markers[1].sigma, 0.001);
  EXPECT_TRUE(s.markers[1].sigma_overridden);
  EXPECT_EQ(f.theta.marker_position[0], Eigen::Vector3d::Zero());
  EXPECT_EQ(s.joint_sensors[0].joint, *model().movableJointIndex("index_j2"));
  EXPECT_EQ(s.joint_sensors[0].sigma, 0.01);
  EXPECT_FALSE(s.joint_sensors[0].fixed.any());
  EXPECT_EQ(f.theta.joint_sensor[0].gain, 1.0);
  EXPECT_EQ(f.theta.joint_sensor[0].bias, 0.0);
  EXPECT_EQ(s.tendon_sensors[0].sigma, 0.01);
  EXPECT_EQ(f.theta.tendon_sensor[0].bias, 0.0);
  EXPECT_EQ(s.tendon_sensors[0].coupling[0].coefficient, 2.0);  // an integer is a number
  EXPECT_EQ(f.theta.mocap.translation, Eigen::Vector3d::Zero());
  EXPECT_EQ(f.theta.mocap.rotation.coeffs(), Eigen::Quaterniond::Identity().coeffs());
}

TEST(SensorsFile, MocapSigmaAppliesWhereverItIsWritten) {
  const SensorsFile f =
      parse("mocap:\n  markers:\n    - {name: a, link: tool}\n  sigma: 0.005\n");
  EXPECT_EQ(f.sensors.markers[0].sigma, 0.005);
}

TEST(SensorsFile, FixedEverywhereAndNoMocapSection) {
  const SensorsFile f = parse(
      "mocap:\n  frame: {fixed: true}\n  markers:\n    - {name: a, link: tool, fixed: true}\n"
      "joint_sensors:\n  - {name: pot, joint: l_elbow, fixed: true}\n"
      "tendon_sensors:\n  - {name: c, coupling: {slide: 2}, fixed: true}\n");
  EXPECT_TRUE(f.sensors.mocap_frame_fixed.all());
  EXPECT_TRUE(f.sensors.markers[0].fixed);
  EXPECT_TRUE(f.sensors.joint_sensors[0].fixed.all());
  EXPECT_TRUE(f.sensors.tendon_sensors[0].fixed.all());
  const SensorsFile g = parse(kOnePot);
  EXPECT_FALSE(g.sensors.hasMarkers());
}

TEST(SensorsFile, YamlSpellingsOfNumbers) {
  const SensorsFile f = parse(
      "joint_sensors:\n  - {name: pot, joint: l_elbow, gain: 1e-05, bias: -3, sigma: +.5}\n");
  EXPECT_EQ(f.theta.joint_sensor[0].gain, 1e-05);
  EXPECT_EQ(f.theta.joint_sensor[0].bias, -3.0);
  EXPECT_EQ(f.sensors.joint_sensors[0].sigma, 0.5);
}

TEST(SensorsFile, CalibrationExtrasAreIgnored) {
  const SensorsFile f = parse(
      "mocap:\n  frame:\n    std: {translation: [.inf, .nan, 1], rotation: whatever}\n"
      "  markers:\n    - {name: a, link: tool, std: {position: [.inf, 0, 0]}, "
      "residual: {rms: .nan, mae: 1.0, count: 0}}\n"
      "joint_sensors:\n  - {name: pot, joint: l_elbow, std: {gain: .inf, bias: .nan}, "
      "residual: {rms: 1, anything: [1, 2]}}\n"
      "summary:\n  method: stac\n  final_cost: .inf\n  unknown_key: 1\n  unknown_key: 2\n");
  EXPECT_EQ(f.sensors.markers.size(), 1u);
  EXPECT_EQ(f.sensors.joint_sensors.size(), 1u);
}

// ---- rotations ----

TEST(SensorsFile, RpyIsTheUrdfConvention) {
  const Eigen::Vector3d rpy(0.1, -0.4, 2.5);
  const SensorsFile f = parse("mocap:\n  frame:\n    rpy: [0.1, -0.4, 2.5]\n"
                              "  markers:\n    - {name: a, link: tool}\n");
  EXPECT_LT((f.theta.mocap.rotation.toRotationMatrix() - urdfRpy(rpy)).norm(), 1e-15);
  // yaw = pi/2 takes x to y.
  const SensorsFile g = parse("mocap:\n  frame:\n    rpy: [0, 0, 1.5707963267948966]\n"
                              "  markers:\n    - {name: a, link: tool}\n");
  EXPECT_LT((g.theta.mocap.rotation * Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitY()).norm(),
            1e-15);
}

TEST(SensorsFile, QuaternionIsWxyzAndNormalized) {
  const SensorsFile f = parse("mocap:\n  frame:\n    quaternion: [2, 0, 0, 2]\n"
                              "  markers:\n    - {name: a, link: tool}\n");
  const Eigen::Quaterniond& q = f.theta.mocap.rotation;
  EXPECT_NEAR(q.norm(), 1.0, 1e-15);
  EXPECT_NEAR(q.w(), std::sqrt(0.5), 1e-15);
  EXPECT_NEAR(q.z(), std::sqrt(0.5), 1e-15);
}

TEST(SensorsFile, RpyAndQuaternionThatAgreeAreAccepted) {
  // q and -q are the same rotation; a difference below 1e-6 rad is rounding.
  const SensorsFile f = parse(
      "mocap:\n  frame:\n    rpy: [0.0, 0.0, 1.5707963267948966]\n"
      "    quaternion: [-0.7071067811865476, 0.0, 0.0, -0.7071067811865475]\n"
      "  markers:\n    - {name: a, link: tool}\n");
  EXPECT_EQ(f.theta.mocap.rotation.w(), -0.7071067811865476) << "the quaternion is used";
  parse("mocap:\n  frame:\n    rpy: [0.0, 0.0, 0.3000004]\n"
        "    quaternion: [0.9887710779360422, 0.0, 0.0, 0.14943813247359922]\n"
        "  markers:\n    - {name: a, link: tool}\n");
}

TEST(SensorsFileError, RpyAndQuaternionDisagree) {
  expectYamlError("mocap:\n  frame:\n    rpy: [0.0, 0.0, 0.3000030]\n"
                  "    quaternion: [0.9887710779360422, 0.0, 0.0, 0.14943813247359922]\n"
                  "  markers:\n    - {name: a, link: tool}\n",
                  3, "mocap.frame.rpy", "different rotations");
}

TEST(SensorsFileError, ZeroQuaternion) {
  expectYamlError("mocap:\n  frame:\n    quaternion: [0, 0, 0, 0]\n"
                  "  markers:\n    - {name: a, link: tool}\n",
                  3, "mocap.frame.quaternion", "zero quaternion");
}

// The writer's rpy agrees with its quaternion everywhere, gimbal lock
// included, so its output always loads.
TEST(SensorsFile, WrittenRpyMatchesTheRotationNearGimbalLock) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI);
  SensorSet s;
  MarkerConfig a;
  a.name = "a";
  a.link_name = "tool";
  a.link = *model().linkIndex("tool");
  s.markers.push_back(a);
  SensorParameters th;
  th.marker_position.push_back(Eigen::Vector3d::Zero());
  for (double sign : {1.0, -1.0}) {
    for (double delta : {0.0, 1e-16, 1e-13, 1e-10, 1e-8, 1e-7, 1e-6, 1e-5, 1e-4, 1e-3, 0.1}) {
      for (int k = 0; k < 20; ++k) {
        const Eigen::Vector3d rpy(angle(rng), sign * (M_PI / 2 - delta), angle(rng));
        th.mocap.rotation = Eigen::Quaterniond(urdfRpy(rpy)).normalized();
        const std::string yaml = sensorsToYaml(s, th);
        const YAML::Node n = YAML::Load(yaml);
        const Eigen::Vector3d back(n["mocap"]["frame"]["rpy"][0].as<double>(),
                                   n["mocap"]["frame"]["rpy"][1].as<double>(),
                                   n["mocap"]["frame"]["rpy"][2].as<double>());
        const double gap =
            Eigen::Quaterniond(urdfRpy(back)).angularDistance(th.mocap.rotation);
        EXPECT_LT(gap, 1e-7) << "delta " << delta << " rpy " << rpy.transpose();
        const SensorsFile f = parse(yaml);
        EXPECT_EQ(f.theta.mocap.rotation.coeffs(), th.mocap.rotation.coeffs());
      }
    }
  }
}

// ---- round trips ----

// Random values over many magnitudes, each of which must come back bit-equal.
double randomValue(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  switch (rng() % 5) {
    case 0: return std::ldexp(u(rng), static_cast<int>(rng() % 200) - 100);
    case 1: return std::numeric_limits<double>::denorm_min() * static_cast<double>(rng() % 100);
    case 2: {
      double v;
      const uint64_t bits = rng();
      std::memcpy(&v, &bits, sizeof v);
      return std::isfinite(v) ? v : 0.5;
    }
    default: return u(rng);
  }
}
double randomSigma(std::mt19937_64& rng) { return std::abs(randomValue(rng)) + 1e-300; }

struct RandomCalibration {
  SensorSet sensors;
  SensorParameters theta;
  CalibrationResult result;
};

RandomCalibration randomCalibration(std::mt19937_64& rng) {
  const RobotModel& m = model();
  RandomCalibration r;
  SensorSet& s = r.sensors;
  SensorParameters& th = r.theta;
  s.mocap_sigma = randomSigma(rng);
  s.mocap_frame_fixed = {rng() % 2 == 1, rng() % 2 == 1};
  const char* links[] = {"torso", "head", "l_forearm", "tool", "index_2"};
  for (int i = 0; i < 5; ++i) {
    MarkerConfig mc;
    mc.name = i == 3 ? "link_3.0_tip" : "m" + std::to_string(i);
    mc.link_name = links[i];
    mc.link = *m.linkIndex(mc.link_name);
    mc.fixed = rng() % 2;
    mc.sigma_overridden = i % 2 == 1;
    mc.sigma = mc.sigma_overridden ? randomSigma(rng) : s.mocap_sigma;
    if (i == 2) mc.columns = {"x1", "y1", "p@l_forearm.z"};  // SPEC §3 `columns:`
    s.markers.push_back(mc);
    th.marker_position.emplace_back(randomValue(rng), randomValue(rng), randomValue(rng));
  }
  const char* joints[] = {"l_elbow", "index_j2", "slide", "neck"};
  for (int i = 0; i < 4; ++i) {
    JointSensorConfig c;
    c.name = std::string(joints[i]) + "_pot";
    c.joint_name = joints[i];
    c.joint = *m.movableJointIndex(c.joint_name);
    c.sigma = randomSigma(rng);
    c.fixed = {rng() % 2 == 1, rng() % 2 == 1};
    if (i == 1) c.column = "enc 2";  // SPEC §3 `column:`
    s.joint_sensors.push_back(c);
    th.joint_sensor.push_back({randomValue(rng), randomValue(rng)});
  }
  for (int i = 0; i < 3; ++i) {
    TendonSensorConfig c;
    c.name = "cyl_" + std::to_string(i);
    c.sigma = randomSigma(rng);
    c.fixed = {rng() % 2 == 1, rng() % 2 == 1};
    if (i == 0) c.column = "cylinder_0";
    if (i < 2) {
      for (const char* l : {"torso", "head", "l_upper"}) {
        PathAnchor a;
        a.link_name = l;
        a.link = *m.linkIndex(l);
        a.point = Eigen::Vector3d(randomValue(rng), randomValue(rng), randomValue(rng));
        c.path.push_back(a);
      }
    } else {
      c.kind = TendonSensorConfig::Kind::kCoupling;
      for (const char* j : {"index_j1", "index_j2", "slide"})
        c.coupling.push_back({j, *m.movableJointIndex(j), randomValue(rng)});
    }
    s.tendon_sensors.push_back(c);
    th.tendon_sensor.push_back({randomValue(rng), randomValue(rng)});
  }
  s.ignore_columns = {"sample_id", "t_robot"};
  th.mocap.translation = Eigen::Vector3d(randomValue(rng), randomValue(rng), randomValue(rng));
  std::normal_distribution<double> n;
  th.mocap.rotation = Eigen::Quaterniond(n(rng), n(rng), n(rng), n(rng)).normalized();

  CalibrationResult& res = r.result;
  res.sensors = s;
  res.theta = th;
  res.std.mocap_translation = Eigen::Vector3d(0.1, std::numeric_limits<double>::infinity(), 0);
  res.std.mocap_rotation = Eigen::Vector3d(1e-5, 2e-5, 3e-5);
  res.std.marker_position.assign(5, Eigen::Vector3d(1e-4, 2e-4, 0));
  res.std.joint_sensor.assign(4, {0.01, std::numeric_limits<double>::infinity()});
  res.std.tendon_sensor.assign(3, {0.02, 0.03});
  res.marker_residual.assign(5, {0.001, 0.0008, 120});
  res.joint_residual.assign(4, {std::numeric_limits<double>::quiet_NaN(), 0.0, 0});
  res.tendon_residual.assign(3, {0.02, 0.015, 119});
  CalibrationSummary& sm = res.summary;
  sm.method = "stac";
  sm.q_phase = "lm-iter";
  sm.iterations = 17;
  sm.converged = true;
  sm.initial_cost = 1234.5;
  sm.final_cost = 56.25;
  sm.frames = 120;
  sm.wall_time = 0.75;
  sm.group_sigma[0] = 0.0021;
  sm.group_sigma[1] = 0.011;
  sm.group_present[0] = sm.group_present[1] = true;
  sm.unidentifiable.push_back(
      {{"joint_sensors.neck_pot.bias", "mocap.frame.rotation.z"},
       "the \"frame\" rotation about the first joint's axis: trades off\nwith its \\bias\\",
       Undetermined::kNull});
  sm.downweighted.push_back({7, "m1", 0.25});
  sm.downweighted.push_back({9, "a \"quoted\" name", 0.5});
  return r;
}

void expectSameSensors(const SensorsFile& f, const SensorSet& s, const SensorParameters& th) {
  const SensorSet& b = f.sensors;
  EXPECT_TRUE(sameBits(b.mocap_sigma, s.mocap_sigma));
  EXPECT_EQ(b.mocap_frame_fixed.rotation, s.mocap_frame_fixed.rotation);
  EXPECT_EQ(b.mocap_frame_fixed.translation, s.mocap_frame_fixed.translation);
  EXPECT_EQ(b.ignore_columns, s.ignore_columns);
  ASSERT_EQ(b.markers.size(), s.markers.size());
  for (size_t i = 0; i < s.markers.size(); ++i) {
    EXPECT_EQ(b.markers[i].name, s.markers[i].name);
    EXPECT_EQ(b.markers[i].link_name, s.markers[i].link_name);
    EXPECT_EQ(b.markers[i].link, s.markers[i].link);
    EXPECT_TRUE(sameBits(b.markers[i].sigma, s.markers[i].sigma)) << i;
    EXPECT_EQ(b.markers[i].sigma_overridden, s.markers[i].sigma_overridden) << i;
    EXPECT_EQ(b.markers[i].fixed, s.markers[i].fixed);
    EXPECT_EQ(b.markers[i].logColumns(), s.markers[i].logColumns()) << i;
    for (int k = 0; k < 3; ++k)
      EXPECT_TRUE(sameBits(f.theta.marker_position[i][k], th.marker_position[i][k]));
  }
  ASSERT_EQ(b.joint_sensors.size(), s.joint_sensors.size());
  for (size_t i = 0; i < s.joint_sensors.size(); ++i) {
    EXPECT_EQ(b.joint_sensors[i].name, s.joint_sensors[i].name);
    EXPECT_EQ(b.joint_sensors[i].joint_name, s.joint_sensors[i].joint_name);
    EXPECT_EQ(b.joint_sensors[i].joint, s.joint_sensors[i].joint);
    EXPECT_EQ(b.joint_sensors[i].logColumn(), s.joint_sensors[i].logColumn());
    EXPECT_TRUE(sameBits(b.joint_sensors[i].sigma, s.joint_sensors[i].sigma));
    EXPECT_EQ(b.joint_sensors[i].fixed.gain, s.joint_sensors[i].fixed.gain);
    EXPECT_EQ(b.joint_sensors[i].fixed.bias, s.joint_sensors[i].fixed.bias);
    EXPECT_TRUE(sameBits(f.theta.joint_sensor[i].gain, th.joint_sensor[i].gain));
    EXPECT_TRUE(sameBits(f.theta.joint_sensor[i].bias, th.joint_sensor[i].bias));
  }
  ASSERT_EQ(b.tendon_sensors.size(), s.tendon_sensors.size());
  for (size_t i = 0; i < s.tendon_sensors.size(); ++i) {
    const TendonSensorConfig &x = b.tendon_sensors[i], &y = s.tendon_sensors[i];
    EXPECT_EQ(x.name, y.name);
    EXPECT_EQ(x.logColumn(), y.logColumn());
    EXPECT_EQ(x.kind, y.kind);
    EXPECT_TRUE(sameBits(x.sigma, y.sigma));
    EXPECT_EQ(x.fixed.gain, y.fixed.gain);
    EXPECT_EQ(x.fixed.bias, y.fixed.bias);
    EXPECT_TRUE(sameBits(f.theta.tendon_sensor[i].gain, th.tendon_sensor[i].gain));
    EXPECT_TRUE(sameBits(f.theta.tendon_sensor[i].bias, th.tendon_sensor[i].bias));
    ASSERT_EQ(x.path.size(), y.path.size());
    for (size_t k = 0; k < y.path.size(); ++k) {
      EXPECT_EQ(x.path[k].link, y.path[k].link);
      EXPECT_EQ(x.path[k].link_name, y.path[k].link_name);
      for (int d = 0; d < 3; ++d) EXPECT_TRUE(sameBits(x.path[k].point[d], y.path[k].point[d]));
    }
    ASSERT_EQ(x.coupling.size(), y.coupling.size());
    for (size_t k = 0; k < y.coupling.size(); ++k) {
      EXPECT_EQ(x.coupling[k].joint, y.coupling[k].joint);
      EXPECT_EQ(x.coupling[k].joint_name, y.coupling[k].joint_name);
      EXPECT_TRUE(sameBits(x.coupling[k].coefficient, y.coupling[k].coefficient));
    }
  }
  for (int k = 0; k < 3; ++k)
    EXPECT_TRUE(sameBits(f.theta.mocap.translation[k], th.mocap.translation[k]));
  for (int k = 0; k < 4; ++k)
    EXPECT_TRUE(sameBits(f.theta.mocap.rotation.coeffs()[k], th.mocap.rotation.coeffs()[k]))
        << f.theta.mocap.rotation.coeffs().transpose() << " vs "
        << th.mocap.rotation.coeffs().transpose();
}

TEST(SensorsFile, SeedRoundTripIsBitExact) {
  std::mt19937_64 rng(11);
  for (int trial = 0; trial < 50; ++trial) {
    const RandomCalibration r = randomCalibration(rng);
    const std::string yaml = sensorsToYaml(r.sensors, r.theta);
    EXPECT_EQ(yaml.find("summary"), std::string::npos);
    EXPECT_EQ(yaml.find("std:"), std::string::npos);
    const SensorsFile f = parse(yaml);
    expectSameSensors(f, r.sensors, r.theta);
    // And once more: writing what was read gives the same text.
    EXPECT_EQ(sensorsToYaml(f.sensors, f.theta), yaml);
  }
}

TEST(SensorsFile, CalibrationOutputRoundTripsAndFeedsBack) {
  std::mt19937_64 rng(12);
  RandomCalibration r = randomCalibration(rng);
  // σ come from the result.
  r.result.sensors.joint_sensors[2].sigma = 0.0375;
  r.result.sensors.mocap_sigma = 0.004;
  for (MarkerConfig& mc : r.result.sensors.markers)
    if (!mc.sigma_overridden) mc.sigma = 0.004;
  test::TempDir dir;
  writeFileAtomically(dir.file("cal.yaml"),
                      sensorsToYaml(r.result.sensors, r.result.theta, &r.result));
  const SensorsFile f = loadSensorsFile(dir.file("cal.yaml"), model());
  expectSameSensors(f, r.result.sensors, r.result.theta);
  EXPECT_EQ(f.sensors.joint_sensors[2].sigma, 0.0375);

  // The extras are well-formed YAML with the values and strings written.
  const YAML::Node n = YAML::LoadFile(dir.file("cal.yaml"));
  const YAML::Node sm = n["summary"];
  EXPECT_EQ(sm["method"].as<std::string>(), "stac");
  EXPECT_EQ(sm["q_phase"].as<std::string>(), "lm-iter");
  EXPECT_EQ(sm["iterations"].as<int>(), 17);
  EXPECT_TRUE(sm["converged"].as<bool>());
  EXPECT_EQ(sm["final_cost"].as<double>(), 56.25);
  EXPECT_EQ(sm["frames"].as<int>(), 120);
  EXPECT_EQ(sm["sigma"]["marker"].as<double>(), 0.0021);
  EXPECT_EQ(sm["sigma"]["joint"].as<double>(), 0.011);
  EXPECT_FALSE(sm["sigma"]["tendon"]) << "only groups present";
  ASSERT_EQ(sm["unidentifiable"].size(), 1u);
  EXPECT_EQ(sm["unidentifiable"][0]["parameters"][1].as<std::string>(), "mocap.frame.rotation.z");
  EXPECT_EQ(sm["unidentifiable"][0]["reason"].as<std::string>(),
            r.result.summary.unidentifiable[0].reason);
  EXPECT_EQ(sm["unidentifiable"][0]["kind"].as<std::string>(), "null_direction");
  ASSERT_EQ(sm["downweighted"].size(), 2u);
  EXPECT_EQ(sm["downweighted"][1]["sensor"].as<std::string>(), "a \"quoted\" name");
  EXPECT_EQ(sm["downweighted"][1]["frame"].as<int>(), 9);
  EXPECT_EQ(n["mocap"]["frame"]["std"]["translation"][1].as<double>(),
            std::numeric_limits<double>::infinity());
  EXPECT_EQ(n["mocap"]["markers"][0]["residual"]["count"].as<int>(), 120);
  EXPECT_EQ(n["joint_sensors"][0]["std"]["gain"].as<double>(), 0.01);
  EXPECT_EQ(n["tendon_sensors"][2]["std"]["bias"].as<double>(), 0.03);
  EXPECT_TRUE(n["mocap"]["frame"]["rpy"]);
  EXPECT_TRUE(n["mocap"]["frame"]["quaternion"]);
  EXPECT_TRUE(n["mocap"]["frame"]["fixed"]);
}

TEST(SensorsFile, NamesNeedingQuotesRoundTrip) {
  SensorSet s;
  SensorParameters th;
  for (const char* name : {"yes", "No", "null", "1abc", "a b", "x: y", "-m", "on", "#5"}) {
    JointSensorConfig c;
    c.name = name;
    c.joint_name = "l_elbow";
    c.joint = *model().movableJointIndex("l_elbow");
    s.joint_sensors.push_back(c);
    th.joint_sensor.push_back({});
  }
  s.joint_sensors.back().name = "hash#5";
  const SensorsFile f = parse(sensorsToYaml(s, th));
  ASSERT_EQ(f.sensors.joint_sensors.size(), s.joint_sensors.size());
  for (size_t i = 0; i < s.joint_sensors.size(); ++i)
    EXPECT_EQ(f.sensors.joint_sensors[i].name, s.joint_sensors[i].name);
}

// ---- every error of SPEC §3: file, line, key ----

TEST(SensorsFileError, UnknownKeyAtEveryLevel) {
  expectYamlError("joint_sensor:\n  - {name: pot, joint: l_elbow}\n", 1, "joint_sensor",
                  "unknown key");
  expectYamlError("mocap:\n  sigmaa: 0.002\n  markers:\n    - {name: a, link: tool}\n", 2,
                  "mocap.sigmaa", "unknown key");
  expectYamlError("mocap:\n  frame:\n    xyz: [0, 0, 0]\n  markers:\n    - {name: a, link: tool}\n",
                  3, "mocap.frame.xyz", "unknown key");
  expectYamlError("mocap:\n  markers:\n    - name: a\n      link: tool\n      offset: [0, 0, 0]\n",
                  5, "mocap.markers[0].offset", "unknown key");
  expectYamlError(std::string(kOnePot) + "  - name: x\n    joint: l_elbow\n    gian: 2.0\n", 5,
                  "joint_sensors[1].gian", "unknown key");
  expectYamlError("tendon_sensors:\n  - name: c\n    path:\n      - {link: torso, point: [0, 0, 0]}\n"
                  "      - {link: head, pt: [0, 0, 0]}\n",
                  5, "tendon_sensors[0].path[1].pt", "unknown key");
}

TEST(SensorsFileError, KeyGivenTwice) {
  expectYamlError(std::string(kOnePot) + "  - name: x\n    joint: l_elbow\n    joint: neck\n", 5,
                  "joint_sensors[1].joint", "given twice (first on line 4)");
  expectYamlError("joint_sensors:\n  - {name: pot, joint: l_elbow, gain: 1, gain: 2}\n", 2,
                  "joint_sensors[0].gain", "given twice");
  expectYamlError(std::string(kOnePot) + "joint_sensors:\n  - {name: pot2, joint: neck}\n", 3,
                  "joint_sensors", "given twice");
  expectYamlError("mocap:\n  sigma: 0.001\n  sigma: 0.002\n  markers:\n    - {name: a, link: tool}\n",
                  3, "mocap.sigma", "given twice");
  expectYamlError("tendon_sensors:\n  - name: c\n    coupling: {slide: 1, neck: 2, slide: 3}\n", 3,
                  "tendon_sensors[0].coupling.slide", "given twice");
}

TEST(SensorsFileError, WrongType) {
  expectYamlError(std::string(kOnePot) + "  - name: x\n    joint: neck\n    gain: fast\n", 5,
                  "joint_sensors[1].gain", "expected a number, got 'fast'");
  expectYamlError("joint_sensors:\n  - {name: pot, joint: l_elbow, bias: '0.5'}\n", 2,
                  "joint_sensors[0].bias", "quoted string");
  expectYamlError("joint_sensors:\n  - {name: pot, joint: l_elbow, bias: [0.5]}\n", 2,
                  "joint_sensors[0].bias", "expected a number");
  expectYamlError("joint_sensors:\n  - name: pot\n    joint: l_elbow\n    bias:\n", 4,
                  "joint_sensors[0].bias", "got nothing");
  expectYamlError("mocap:\n  markers:\n    - {name: a, link: tool, position: [0.1, 0.2]}\n", 3,
                  "mocap.markers[0].position", "expected a list of 3 numbers, got 2");
  expectYamlError("mocap:\n  markers:\n    - {name: a, link: tool, position: 0.1}\n", 3,
                  "mocap.markers[0].position", "expected a list of 3 numbers");
  expectYamlError("mocap:\n  markers:\n    - {name: a, link: tool, position: [0.1, x, 0]}\n", 3,
                  "mocap.markers[0].position[1]", "expected a number");
  expectYamlError("joint_sensors:\n  - {name: pot, joint: l_elbow, fixed: 1}\n", 2,
                  "joint_sensors[0].fixed", "expected true or false");
  expectYamlError("mocap:\n  frame:\n    fixed: maybe\n  markers:\n    - {name: a, link: tool}\n", 3,
                  "mocap.frame.fixed", "expected true or false");
  expectYamlError("mocap:\n  frame:\n    quaternion: [1, 0, 0]\n  markers:\n    - {name: a, link: tool}\n",
                  3, "mocap.frame.quaternion", "expected a list of 4 numbers");
  expectYamlError("joint_sensors:\n  name: pot\n  joint: l_elbow\n", 2, "joint_sensors",
                  "expected a list");
  expectYamlError("mocap:\n  markers:\n    name: a\n", 3, "mocap.markers", "expected a list");
  expectYamlError("mocap: 3\n", 1, "mocap", "expected a mapping");
  expectYamlError("- 1\n- 2\n", 1, "(top level)", "expected a mapping");
  expectYamlError("joint_sensors:\n  - {name: [a], joint: l_elbow}\n", 2, "joint_sensors[0].name",
                  "expected a name");
  expectYamlError("tendon_sensors:\n  - {name: c, coupling: [slide, 1]}\n", 2,
                  "tendon_sensors[0].coupling", "expected a mapping");
}

TEST(SensorsFileError, MissingRequiredKey) {
  expectYamlError("mocap:\n  markers:\n    - {link: tool}\n", 3, "mocap.markers[0].name", "missing");
  expectYamlError("mocap:\n  markers:\n    - {name: a}\n", 3, "mocap.markers[0].link", "missing");
  expectYamlError("joint_sensors:\n  - {name: pot}\n", 2, "joint_sensors[0].joint", "missing");
  expectYamlError("joint_sensors:\n  - {joint: l_elbow}\n", 2, "joint_sensors[0].name", "missing");
  expectYamlError("tendon_sensors:\n  - {coupling: {slide: 1}}\n", 2, "tendon_sensors[0].name",
                  "missing");
  expectYamlError("tendon_sensors:\n  - name: c\n    path:\n      - {link: torso}\n"
                  "      - {link: head, point: [0, 0, 0]}\n",
                  4, "tendon_sensors[0].path[0].point", "missing");
}

TEST(SensorsFileError, UnknownLink) {
  expectYamlError("mocap:\n  markers:\n    - name: m\n      link: forearm\n", 4,
                  "mocap.markers[0].link", "unknown link 'forearm'");
  expectYamlError("tendon_sensors:\n  - name: c\n    path:\n      - {link: torso, point: [0, 0, 0]}\n"
                  "      - {link: neck, point: [0, 0, 0]}\n",
                  5, "tendon_sensors[0].path[1].link", "unknown link 'neck'");
}

TEST(SensorsFileError, UnknownJoint) {
  expectYamlError("joint_sensors:\n  - name: pot\n    joint: elbow\n", 3, "joint_sensors[0].joint",
                  "unknown joint 'elbow'");
  expectYamlError("joint_sensors:\n  - name: pot\n    joint: tool_joint\n", 3,
                  "joint_sensors[0].joint", "is fixed");
}

TEST(SensorsFileError, NameUsedTwice) {
  expectYamlError(std::string(kOnePot) + "  - {name: pot, joint: neck}\n", 3,
                  "joint_sensors[1].name", "'pot' is used twice");
  expectYamlError(std::string(kOnePot) + "tendon_sensors:\n  - {name: pot, coupling: {slide: 1}}\n",
                  4, "tendon_sensors[0].name", "used twice");
  expectYamlError("mocap:\n  markers:\n    - {name: a, link: tool}\n    - {name: a, link: head}\n", 4,
                  "mocap.markers[1].name", "used twice");
  // A marker and a sensor share a name: the marker's columns are a.x/.y/.z,
  // but one name for two things is still an error.
  expectYamlError("mocap:\n  markers:\n    - {name: a, link: tool}\n"
                  "joint_sensors:\n  - {name: a, joint: neck}\n",
                  5, "joint_sensors[0].name", "used twice");
  // A sensor whose column is one of a marker's.
  expectYamlError("mocap:\n  markers:\n    - {name: a, link: tool}\n"
                  "joint_sensors:\n  - {name: a.x, joint: neck}\n",
                  5, "joint_sensors[0].name", "'a.x'");
}

TEST(SensorsFileError, NameCannotBeALogColumn) {
  expectYamlError("joint_sensors:\n  - {name: time, joint: neck}\n", 2, "joint_sensors[0].name",
                  "time column");
  expectYamlError("joint_sensors:\n  - {name: 'a,b', joint: neck}\n", 2, "joint_sensors[0].name",
                  "CSV column");
}

TEST(SensorsFileError, PathWithFewerThanTwoPoints) {
  expectYamlError("tendon_sensors:\n  - name: c\n    path:\n      - {link: torso, point: [0, 0, 0]}\n",
                  4, "tendon_sensors[0].path", "at least two points, got 1");
  expectYamlError("tendon_sensors:\n  - name: c\n    path: []\n", 3, "tendon_sensors[0].path",
                  "at least two points");
}

TEST(SensorsFileError, TendonNeedsExactlyOneOfPathAndCoupling) {
  expectYamlError("tendon_sensors:\n  - name: c\n    gain: 2\n", 2, "tendon_sensors[0]",
                  "needs a path");
  expectYamlError("tendon_sensors:\n  - name: c\n    coupling: {slide: 1}\n    path:\n"
                  "      - {link: torso, point: [0, 0, 0]}\n      - {link: head, point: [0, 0, 0]}\n",
                  3, "tendon_sensors[0].coupling", "not both");
}

TEST(SensorsFileError, CouplingOverAnUnknownJoint) {
  expectYamlError("tendon_sensors:\n  - name: c\n    coupling: {index_j1: 0.01, wrist: 0.02}\n", 3,
                  "tendon_sensors[0].coupling.wrist", "unknown joint 'wrist'");
  expectYamlError("tendon_sensors:\n  - name: c\n    coupling:\n      index_j1: 0.01\n"
                  "      tool_joint: 0.02\n",
                  5, "tendon_sensors[0].coupling.tool_joint", "is fixed");
  expectYamlError("tendon_sensors:\n  - name: c\n    coupling: {index_j1: .inf}\n", 3,
                  "tendon_sensors[0].coupling.index_j1", "not a finite number");
}

TEST(SensorsFileError, SigmaNotPositiveAndFinite) {
  expectYamlError(std::string(kOnePot) + "  - {name: x, joint: neck, sigma: 0.0}\n", 3,
                  "joint_sensors[1].sigma", "positive");
  expectYamlError("tendon_sensors:\n  - {name: c, coupling: {slide: 1}, sigma: -0.01}\n", 2,
                  "tendon_sensors[0].sigma", "positive");
  expectYamlError("mocap:\n  sigma: .inf\n  markers:\n    - {name: a, link: tool}\n", 2,
                  "mocap.sigma", "not a finite number");
  expectYamlError("mocap:\n  markers:\n    - {name: a, link: tool, sigma: -.Inf}\n", 3,
                  "mocap.markers[0].sigma", "not a finite number");
}

TEST(SensorsFileError, NonFiniteNumber) {
  expectYamlError("joint_sensors:\n  - name: pot\n    joint: l_elbow\n    bias: .nan\n", 4,
                  "joint_sensors[0].bias", "not a finite number");
  expectYamlError("joint_sensors:\n  - {name: pot, joint: l_elbow, gain: -.inf}\n", 2,
                  "joint_sensors[0].gain", "not a finite number");
  expectYamlError("mocap:\n  frame:\n    translation: [0, .NaN, 0]\n"
                  "  markers:\n    - {name: a, link: tool}\n",
                  3, "mocap.frame.translation[1]", "not a finite number");
  expectYamlError("mocap:\n  frame:\n    rpy: [0, 0, .inf]\n  markers:\n    - {name: a, link: tool}\n",
                  3, "mocap.frame.rpy[2]", "not a finite number");
  expectYamlError("mocap:\n  markers:\n    - {name: a, link: tool, position: [0, 0, 1e999]}\n", 3,
                  "mocap.markers[0].position[2]", "not a finite number");
  expectYamlError("tendon_sensors:\n  - name: c\n    path:\n      - {link: torso, point: [0, 0, 0]}\n"
                  "      - {link: head, point: [.inf, 0, 0]}\n",
                  5, "tendon_sensors[0].path[1].point[0]", "not a finite number");
}

TEST(SensorsFileError, MalformedYaml) {
  expectYamlError("joint_sensors:\n  - {name: pot, joint: l_elbow\n", 3, "malformed YAML");
  expectYamlError("joint_sensors:\n  - name: pot\n   joint: l_elbow\n", 3, "malformed YAML");
}

TEST(SensorsFileError, MoreThanOneDocument) {
  expectYamlError(std::string(kOnePot) + "---\n" + kOnePot, 4, "(top level)",
                  "more than one YAML document");
}

TEST(SensorsFileError, NoSensors) {
  for (const char* yaml : {"", "# nothing\n", "mocap:\n  sigma: 0.002\n", "joint_sensors: []\n",
                           "summary: {method: stac}\n"}) {
    const InputError e = yamlError(yaml);
    EXPECT_EQ(e.file(), "s.yaml");
    EXPECT_NE(std::string(e.what()).find("no sensors"), std::string::npos) << e.what();
  }
}

TEST(SensorsFileError, MissingFile) {
  test::TempDir dir;
  try {
    loadSensorsFile(dir.file("seed.yaml"), model());
    FAIL();
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), dir.file("seed.yaml"));
  }
}

// ---- inference from the log header (SPEC §3 "Without a sensors file") ----

TEST(InferSensors, JointColumnsAndLinkMarkers) {
  const Log log = parseLog(
      "time,l_elbow,l_forearm.x,l_forearm.y,l_forearm.z,index_j2,tool.z,tool.x,tool.y\n"
      "0,0.1,1,2,3,0.2,4,5,6\n",
      "d.csv");
  const SensorsFile f = inferSensorsFromLog(log, model());
  const SensorSet& s = f.sensors;
  ASSERT_EQ(s.joint_sensors.size(), 2u);
  EXPECT_EQ(s.joint_sensors[0].name, "l_elbow");
  EXPECT_EQ(s.joint_sensors[0].joint, *model().movableJointIndex("l_elbow"));
  EXPECT_EQ(s.joint_sensors[1].joint, *model().movableJointIndex("index_j2"));
  EXPECT_EQ(s.joint_sensors[1].sigma, 0.01);
  EXPECT_EQ(f.theta.joint_sensor[1].gain, 1.0);
  EXPECT_EQ(f.theta.joint_sensor[1].bias, 0.0);
  ASSERT_EQ(s.markers.size(), 2u);
  EXPECT_EQ(s.markers[0].name, "l_forearm");
  EXPECT_EQ(s.markers[1].name, "tool");  // a link on a fixed joint
  EXPECT_EQ(s.markers[1].link, *model().linkIndex("tool"));
  EXPECT_EQ(s.markers[1].sigma, 0.002);
  EXPECT_EQ(s.mocap_sigma, 0.002);
  EXPECT_EQ(f.theta.marker_position[1], Eigen::Vector3d::Zero());
  EXPECT_EQ(f.theta.mocap.rotation.coeffs(), Eigen::Quaterniond::Identity().coeffs());
  EXPECT_EQ(f.theta.mocap.translation, Eigen::Vector3d::Zero());
  EXPECT_TRUE(s.tendon_sensors.empty());
  // The inferred sensors take every column.
  const Observations obs = bindLog(log, s, "d.csv", 1.0);
  EXPECT_EQ(obs.marker(0, 3), 5.0);
  EXPECT_EQ(obs.joint(0, 1), 0.2);
  // And they can be written as a seed and read back.
  expectSameSensors(parse(sensorsToYaml(s, f.theta)), s, f.theta);
}

TEST(InferSensors, ListsEveryUnplaceableColumnWithTheClosestName) {
  const Log log = parseLog(
      "# header on line 2\n"
      "time,l_elbw,l_forarm.x,l_forarm.y,l_forarm.z,tool.x,tool.y,tool_joint,neck,head.x,"
      "head.y,head.z\n",
      "d.csv");
  try {
    inferSensorsFromLog(log, model());
    FAIL();
  } catch (const InputError& e) {
    const std::string w = e.what();
    EXPECT_EQ(e.file(), "d.csv");
    EXPECT_EQ(e.line(), 2);
    EXPECT_NE(w.find("7 column(s)"), std::string::npos) << w;
    EXPECT_NE(w.find("l_elbw (closest joint or link: joint 'l_elbow'; did you mean 'l_elbow'?)"),
              std::string::npos)
        << w;
    EXPECT_NE(w.find("l_forarm.y (closest joint or link: link 'l_forearm'; did you mean "
                     "'l_forearm.y'?)"),
              std::string::npos)
        << w;
    EXPECT_NE(w.find("tool.x (a marker on link 'tool' needs all of tool.x, tool.y and tool.z)"),
              std::string::npos)
        << w;
    EXPECT_NE(w.find("tool_joint (joint 'tool_joint' is fixed"), std::string::npos) << w;
    EXPECT_EQ(w.find("\n  neck"), std::string::npos) << "neck is placed: " << w;
    EXPECT_EQ(w.find("head.x"), std::string::npos) << "head.x is placed: " << w;
  }
}

}  // namespace
}  // namespace stac
