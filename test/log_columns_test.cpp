// Log columns apart from sensor names (SPEC §2, §3): `column:`, `columns:`,
// `ignore_columns:` and --ignore-columns' library side, the errors of each
// at their file, key and line, header inference of <marker>@<link> markers,
// and "did you mean" hints only for names that are close.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "io/closest_name.hpp"
#include "stac/error.hpp"
#include "stac/log.hpp"
#include "stac/measurement.hpp"
#include "stac/robot_model.hpp"
#include "stac/sensors_file.hpp"
#include "stac/simulate.hpp"

namespace stac {
namespace {

const char* kUrdf = R"(<?xml version="1.0"?>
<robot name="arm2">
  <link name="base_link"/><link name="upper_link"/><link name="hand_link"/><link name="tool_link"/>
  <joint name="shoulder_joint" type="revolute">
    <parent link="base_link"/><child link="upper_link"/><origin xyz="0 0 0.3"/>
    <axis xyz="0 0 1"/><limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
  <joint name="elbow_joint" type="revolute">
    <parent link="upper_link"/><child link="hand_link"/><origin xyz="0.3 0 0"/>
    <axis xyz="0 1 0"/><limit lower="-2" upper="2" effort="1" velocity="1"/></joint>
  <joint name="tool_joint" type="fixed"><parent link="hand_link"/><child link="tool_link"/>
    <origin xyz="0.1 0 0"/></joint>
</robot>)";

const RobotModel& model() {
  static const RobotModel m = RobotModel::fromString(kUrdf, "arm2.urdf");
  return m;
}

SensorsFile parse(const std::string& yaml) { return parseSensorsYaml(yaml, "s.yaml", model()); }

// A sensors file whose sensors read columns not named after them.
const char* kMapped = R"(mocap:
  markers:
    - name: hand_bl
      link: tool_link
      columns: [x1, y1, z1]
joint_sensors:
  - {name: shoulder, joint: shoulder_joint, column: enc_1, fixed: [gain]}
  - {name: elbow, joint: elbow_joint, column: enc_2}
ignore_columns: [x2, y2, z2, sample_id]
)";

const char* kLog =
    "time,enc_2,x1,y1,z1,x2,y2,z2,enc_1,sample_id\n"
    "0.0,0.2,1.0,2.0,3.0,9,9,9,0.1,0\n"
    "0.1,0.3,1.5,2.5,,9,9,9,0.4,1\n";

void expectInputError(const std::function<void()>& f, const std::string& file, int line,
                      const std::string& part) {
  try {
    f();
    ADD_FAILURE() << "no error; expected " << part;
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), file) << e.what();
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
  }
}

void expectYamlError(const std::string& yaml, int line, const std::string& part) {
  expectInputError([&] { parse(yaml); }, "s.yaml", line, part);
}

TEST(LogColumns, MappedColumnsAreReadAndIgnoredOnesLeftAlone) {
  const SensorsFile sf = parse(kMapped);
  EXPECT_EQ(sf.sensors.joint_sensors[0].logColumn(), "enc_1");
  EXPECT_EQ(sf.sensors.markers[0].logColumns()[2], "z1");
  const Observations obs =
      bindLog(parseLog(kLog, "d.csv"), sf.sensors, "s.yaml", 1.0, sf.column_keys);
  EXPECT_EQ(obs.joint(0, 0), 0.1);  // shoulder <- enc_1, the last column
  EXPECT_EQ(obs.joint(1, 1), 0.3);  // elbow <- enc_2
  EXPECT_EQ(obs.marker(0, 0), 1.0);
  EXPECT_EQ(obs.marker(0, 2), 3.0);
  EXPECT_TRUE(std::isnan(obs.marker(1, 0)));  // z1 missing: the marker is missing
}

TEST(LogColumns, AnIgnoredColumnTheLogLacksIsNoError) {
  const SensorsFile sf = parse(std::string(kMapped) + "");
  const Log log = parseLog("enc_1,enc_2,x1,y1,z1\n0,0,0,0,0\n", "d.csv");
  EXPECT_NO_THROW(bindLog(log, sf.sensors, "s.yaml", 1.0, sf.column_keys));
}

TEST(LogColumns, MappedColumnsRoundTrip) {
  const SensorsFile a = parse(kMapped);
  const std::string yaml = sensorsToYaml(a.sensors, a.theta);
  EXPECT_NE(yaml.find("columns: [x1, y1, z1]"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("column: enc_1"), std::string::npos) << yaml;
  EXPECT_NE(yaml.find("ignore_columns: [x2, y2, z2, sample_id]"), std::string::npos) << yaml;
  const SensorsFile b = parse(yaml);
  EXPECT_EQ(b.sensors.ignore_columns, a.sensors.ignore_columns);
  EXPECT_EQ(b.sensors.markers[0].logColumns(), a.sensors.markers[0].logColumns());
  EXPECT_EQ(b.sensors.joint_sensors[1].logColumn(), "enc_2");
  EXPECT_EQ(sensorsToYaml(b.sensors, b.theta), yaml);
  // Default columns write no key.
  const SensorsFile plain = parse("joint_sensors:\n  - {name: elbow_joint, joint: elbow_joint}\n");
  EXPECT_EQ(sensorsToYaml(plain.sensors, plain.theta).find("column"), std::string::npos);
}

TEST(LogColumns, SimulatedLogsUseTheMappedColumns) {
  const SensorsFile sf = parse(kMapped);
  SimulationOptions so;
  so.frames = 3;
  const Log log = simulate(MeasurementModel(model(), sf.sensors), sf.theta, so).data.log;
  EXPECT_EQ(log.columns, (std::vector<std::string>{"enc_1", "enc_2", "x1", "y1", "z1"}));
  EXPECT_NO_THROW(bindLog(log, sf.sensors, "s.yaml", 1.0, sf.column_keys));
}

TEST(LogColumns, ColumnKeyErrors) {
  const std::string head = "joint_sensors:\n  - {name: a, joint: shoulder_joint, column: enc}\n";
  // Read and ignored, in the file.
  expectYamlError(head + "ignore_columns: [x, enc]\n", 3,
                  "key 'ignore_columns[1]': column 'enc' is read by joint_sensors[0].column "
                  "(line 2): a column is a sensor's or ignored, not both");
  // Ignored twice.
  expectYamlError(head + "ignore_columns:\n  - x\n  - x\n", 5,
                  "key 'ignore_columns[1]': column 'x' is listed twice "
                  "(ignore_columns[0], line 4)");
  // Two sensors on one column, mapped or by name.
  expectYamlError(head + "  - {name: b, joint: elbow_joint, column: enc}\n", 3,
                  "key 'joint_sensors[1].column': column 'enc' is read by another sensor too "
                  "(joint_sensors[0].column, line 2)");
  expectYamlError(head + "  - {name: enc, joint: elbow_joint}\n", 3,
                  "name 'enc' gives log column 'enc', which another sensor has");
  // A marker's columns: three, none the time.
  expectYamlError("mocap:\n  markers:\n    - {name: m, link: tool_link, columns: [x, y]}\n", 3,
                  "key 'mocap.markers[0].columns': expected the list of the x, y and z columns");
  expectYamlError("mocap:\n  markers:\n    - {name: m, link: tool_link, columns: [time, y, z]}\n",
                  3, "key 'mocap.markers[0].columns[0]': column 'time' is the log's time column");
  expectYamlError("joint_sensors:\n  - {name: a, joint: elbow_joint, column: 'a,b'}\n", 2,
                  "column 'a,b' cannot be a CSV column");
  expectYamlError("ignore_columns: x\njoint_sensors:\n  - {name: a, joint: elbow_joint}\n", 1,
                  "key 'ignore_columns': expected a list of log columns");
}

TEST(LogColumns, AColumnTheLogLacksIsTheSensorsFilesErrorAtItsKey) {
  const SensorsFile sf =
      parse("joint_sensors:\n  - {name: shoulder, joint: shoulder_joint, column: enc_1}\n"
            "  - name: elbow\n    joint: elbow_joint\n    column: enc_3\n"
            "ignore_columns: [x1, y1, z1, x2, y2, z2, sample_id]\n");
  expectInputError(
      [&] { bindLog(parseLog(kLog, "d.csv"), sf.sensors, "s.yaml", 1.0, sf.column_keys); },
      "s.yaml", 5, "key 'joint_sensors[1].column': the log d.csv has no column 'enc_3'; did you "
                   "mean 'enc_2'?");  // the column nobody reads
}

TEST(LogColumns, IgnoreColumnsFromTheCommandLine) {
  SensorsFile sf = parse(kMapped);
  ignoreColumns(&sf, {"sample_id", "t_robot"}, "--ignore-columns", "s.yaml");
  EXPECT_EQ(sf.sensors.ignore_columns.back(), "t_robot");
  EXPECT_EQ(sf.sensors.ignore_columns.size(), 5u);  // sample_id once
  expectInputError([&] { ignoreColumns(&sf, {"enc_2"}, "--ignore-columns", "s.yaml"); }, "s.yaml",
                   0,
                   "--ignore-columns lists column 'enc_2', which key 'joint_sensors[1].column' "
                   "(line 8) reads");
}

TEST(InferColumns, AtColumnsMakeSeveralNamedMarkersOnALink) {
  const Log log = parseLog(
      "p1@tool_link.x,p1@tool_link.y,p1@tool_link.z,elbow_joint,p2@tool_link.x,"
      "p2@tool_link.y,p2@tool_link.z,upper_link.x,upper_link.y,upper_link.z,row\n"
      "1,2,3,0.5,4,5,6,7,8,9,0\n",
      "d.csv");
  const SensorsFile sf = inferSensorsFromLog(log, model(), {"row"});
  ASSERT_EQ(sf.sensors.markers.size(), 3u);
  EXPECT_EQ(sf.sensors.markers[0].name, "p1");
  EXPECT_EQ(sf.sensors.markers[0].link_name, "tool_link");
  EXPECT_EQ(sf.sensors.markers[1].name, "p2");
  EXPECT_EQ(sf.sensors.markers[1].link, *model().linkIndex("tool_link"));
  EXPECT_EQ(sf.sensors.markers[2].name, "upper_link");
  EXPECT_EQ(sf.sensors.ignore_columns, std::vector<std::string>{"row"});
  const Observations obs = bindLog(log, sf.sensors, "d.csv", 1.0);
  EXPECT_EQ(obs.marker(0, 3), 4.0);  // p2.x
  EXPECT_EQ(obs.joint(0, 0), 0.5);
  // Written as a seed, it reads back with the same columns.
  const SensorsFile back = parse(sensorsToYaml(sf.sensors, sf.theta));
  EXPECT_EQ(back.sensors.markers[1].logColumns()[2], "p2@tool_link.z");
  EXPECT_NO_THROW(bindLog(log, back.sensors, "s.yaml", 1.0, back.column_keys));
}

std::string inferenceError(const std::string& header) {
  try {
    inferSensorsFromLog(parseLog(header + "\n", "d.csv"), model());
  } catch (const InputError& e) {
    return e.what();
  }
  return "(no error)";
}

TEST(InferColumns, AnAtColumnOnAnUnknownLinkIsAnError) {
  const std::string w =
      inferenceError("p1@tol_link.x,p1@tol_link.y,p1@tol_link.z,p2@gripper.x,p2@gripper.y,"
                     "p2@gripper.z");
  EXPECT_NE(w.find("d.csv:1: 6 column(s)"), std::string::npos) << w;
  EXPECT_NE(w.find("p1@tol_link.y (no link 'tol_link' in arm2.urdf; did you mean "
                   "'p1@tool_link.y'?)"),
            std::string::npos)
      << w;
  EXPECT_NE(w.find("p2@gripper.x (no link 'gripper' in arm2.urdf)"), std::string::npos) << w;
  // A marker name used twice.
  const std::string twice =
      inferenceError("p@tool_link.x,p@tool_link.y,p@tool_link.z,p@upper_link.x,p@upper_link.y,"
                     "p@upper_link.z");
  EXPECT_NE(twice.find("p@upper_link.x (marker name 'p' is another sensor's or marker's already)"),
            std::string::npos)
      << twice;
}

TEST(InferColumns, HintsOnlyWhenCloseAndJointsFirst) {
  const std::string w = inferenceError("x1,t_start_robot,elbow_jiont,upper_lnk,hand_lnk.x");
  // Nothing close: no hint, but the way out.
  EXPECT_NE(w.find("x1 (no joint or link name is close)"), std::string::npos) << w;
  EXPECT_NE(w.find("\nA column that belongs to no sensor (bookkeeping) can be ignored: "
                   "--ignore-columns"),
            std::string::npos)
      << w;
  EXPECT_NE(w.find("t_start_robot (no joint or link name is close"), std::string::npos) << w;
  // A misspelt joint column points at the joint.
  EXPECT_NE(w.find("elbow_jiont (closest joint or link: joint 'elbow_joint'; did you mean "
                   "'elbow_joint'?)"),
            std::string::npos)
      << w;
  // A column without .x/.y/.z that is close to a link only.
  EXPECT_NE(w.find("upper_lnk (closest joint or link: link 'upper_link', whose marker takes"),
            std::string::npos)
      << w;
  EXPECT_NE(w.find("hand_lnk.x (closest joint or link: link 'hand_link'; did you mean "
                   "'hand_link.x'?)"),
            std::string::npos)
      << w;
}

TEST(ClosestName, WithinAThirdOfTheNameLength) {
  EXPECT_EQ(closestName("elbow_jiont", {"tool_link", "elbow_joint"}), "elbow_joint");
  EXPECT_EQ(closestName("x1", {"base_link", "x11"}), "x11");
  EXPECT_FALSE(closestName("x1", {"base_link", "arm_1_joint"}));
  EXPECT_FALSE(closestName("t_start_robot", {"torso_lift_joint", "arm_1_joint"}));
  EXPECT_FALSE(closestName("abcdef", {"abcxyz"}));  // 3 edits in 6 letters
  EXPECT_EQ(closestName("abcdef", {"abcxyf"}), "abcxyf");  // 2 edits
  EXPECT_EQ(editDistance("kitten", "sitting"), 3u);
}

}  // namespace
}  // namespace stac
