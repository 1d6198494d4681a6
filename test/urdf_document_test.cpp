// The one URDF reader (src/io/urdf_document.hpp): what it rejects, with the
// file and line, through the public loader; and that the patcher, given a
// text, reads it the same way (the same error) or says it is not the
// robot's text.
#include <gtest/gtest.h>

#include <string>

#include "io/urdf_document.hpp"
#include "stac/error.hpp"
#include "stac/robot_model.hpp"
#include "stac/urdf_patch.hpp"

namespace stac {
namespace {

// base -> a (revolute) -> b (fixed); %J2% is the second joint's tag body.
const char* kArm = R"(<?xml version="1.0"?>
<robot name="arm">
  <link name="base"/>
  <link name="a"/>
  <link name="b"/>
  <joint name="j1" type="revolute">
    <parent link="base"/>
    <child link="a"/>
    <origin xyz="0 0 0.1" rpy="0 0 0"/>
    <axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/>
  </joint>
  <joint name="j2" type="fixed">
    <parent link="a"/>
    <child link="b"/>
  </joint>
</robot>
)";

std::string replaced(std::string s, const std::string& from, const std::string& to) {
  const size_t at = s.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  if (at != std::string::npos) s.replace(at, from.size(), to);
  return s;
}

// The loader rejects `urdf` with `needle` in the message at `line`, and the
// patcher's text overload, handed the same text, says the same.
void expectRejected(const std::string& urdf, const std::string& needle, int line) {
  std::string loader_message;
  try {
    RobotModel::fromString(urdf, "bad.urdf");
    ADD_FAILURE() << "the loader accepted the text; expected: " << needle;
    return;
  } catch (const InputError& e) {
    loader_message = e.what();
    EXPECT_EQ(e.file(), "bad.urdf");
    EXPECT_EQ(e.line(), line) << e.what();
    EXPECT_NE(loader_message.find(needle), std::string::npos) << loader_message;
    EXPECT_EQ(loader_message.rfind("bad.urdf:" + std::to_string(line) + ": ", 0), 0u)
        << loader_message;
  }
  const RobotModel robot = RobotModel::fromString(kArm, "arm.urdf");
  try {
    patchUrdfMarkers(urdf, robot, SensorSet{}, SensorParameters{}, "bad.urdf");
    ADD_FAILURE() << "the patcher accepted the text; expected: " << needle;
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), loader_message);
  }
}

TEST(UrdfDocument, TheArmLoads) {
  const RobotModel robot = RobotModel::fromString(kArm, "arm.urdf");
  EXPECT_EQ(robot.dof(), 1);
  EXPECT_EQ(robot.urdfText(), kArm);
  EXPECT_EQ(robot.urdfDocument().joint("j1")->line, 6);
  EXPECT_EQ(robot.urdfDocument().joint("j2")->origin, -1);
}

TEST(UrdfDocument, MisNestedTagsNameTheLine) {
  // <child> closed after its joint: TinyXML reports it, and so do we.
  expectRejected(replaced(kArm, "<child link=\"b\"/>\n  </joint>", "<child link=\"b\">\n  </joint></child>"),
                 "</joint> closes <child> (opened at line 15)", 16);
  // A stray end tag after the root, and a '< x>' that TinyXML skips as an
  // "unknown" node: a reader that skips them sees another document.
  expectRejected(std::string(kArm) + "</joint>\n", "</joint> closes nothing", 18);
  expectRejected(replaced(kArm, "  <link name=\"b\"/>", "  < link name=\"b\"/>"),
                 "'<' without an element name", 5);
  expectRejected(std::string(kArm) + "<robot name=\"second\"/>\n",
                 "a second root element <robot>", 18);
  expectRejected(replaced(kArm, "</robot>", ""), "<robot> is never closed", 2);
}

TEST(UrdfDocument, AJointFromALinkToItselfIsRejected) {
  // Without the check, b would be a child (so not a second root) but never
  // reached from the root: the model would silently lose it.
  expectRejected(replaced(kArm, "<parent link=\"a\"/>", "<parent link=\"b\"/>"),
                 "joint 'j2' has link 'b' as both its parent and its child", 13);
}

TEST(UrdfDocument, LinksInALoopAwayFromTheRootAreRejected) {
  const std::string loop = replaced(
      kArm, "</robot>",
      "  <link name=\"c\"/>\n  <joint name=\"j3\" type=\"fixed\"><parent link=\"b\"/><child "
      "link=\"c\"/></joint>\n</robot>");
  // c -> b and b -> c: both are children, base stays the only root.
  const std::string cut = replaced(loop, "<parent link=\"a\"/>", "<parent link=\"c\"/>");
  expectRejected(cut, "link 'b' is not connected to the root link 'base'", 5);
}

TEST(UrdfDocument, NamesWithControlCharactersAreRejected) {
  // A raw control character is not XML at all.
  expectRejected(replaced(kArm, "name=\"j2\"", "name=\"j\x01" "2\""),
                 "control character 0x01", 13);
  // A tab, a line break (raw or as a reference) in a name: TinyXML keeps
  // them, XML would turn them into spaces; we take neither reading.
  expectRejected(replaced(kArm, "name=\"j2\"", "name=\"j\t2\""),
                 "<joint> name 'j\\x092' contains a control character (0x09)", 13);
  expectRejected(replaced(kArm, "name=\"j2\"", "name=\"j&#10;2\""),
                 "<joint> name 'j\\x0a2' contains a control character (0x0a)", 13);
  expectRejected(replaced(kArm, "<child link=\"b\"/>", "<child link=\"b&#x7f;\"/>"),
                 "<child> link name 'b\\x7f' contains a control character (0x7f)", 15);
  expectRejected(replaced(kArm, "<link name=\"b\"/>", "<link name=\"b&#1;\"/>"),
                 "character reference &#1; to a control character", 5);
}

TEST(UrdfDocument, WhatTinyXmlWouldReadDifferentlyIsRejected) {
  expectRejected(replaced(kArm, "name=\"j2\"", "name=\"j&eacute;2\""), "unknown entity &eacute;",
                 13);
  expectRejected(replaced(kArm, "name=\"j2\"", "name=\"j&#233;2\""),
                 "character reference &#233; beyond ASCII", 13);
  expectRejected(replaced(kArm, "<robot name", "<!DOCTYPE robot [<!ENTITY x \"y\">]>\n<robot name"),
                 "DOCTYPE with an internal subset", 2);
  expectRejected(replaced(kArm, "name=\"j2\"", "name=\"j2\" name=\"j3\""),
                 "attribute 'name' given twice in <joint>", 13);
  expectRejected(replaced(kArm, "name=\"j2\"", "name=j2"), "unquoted value of attribute 'name'",
                 13);
  expectRejected(replaced(kArm, "name=\"j2\"", "name=\"a<b\""), "'<' inside an attribute value",
                 13);
}

TEST(UrdfDocument, JointElementsUrdfdomReadsOnceAreRejectedTwice) {
  // urdfdom takes the first <origin>; a second one must not be a silent
  // alternative for the reader of the file or the writer.
  expectRejected(replaced(kArm, "<axis xyz=\"0 0 1\"/>", "<origin xyz=\"1 0 0\"/>"),
                 "joint 'j1' has a second <origin>", 10);
  expectRejected(replaced(kArm, "xyz=\"0 0 0.1\"", "xyz=\"0 0\""),
                 "<origin xyz=\"0 0\"> of joint 'j1' is not three numbers", 9);
  expectRejected(replaced(kArm, "rpy=\"0 0 0\"", "rpy=\"0 0 zero\""),
                 "<origin rpy=\"0 0 zero\"> of joint 'j1' is not three numbers", 9);
}

TEST(UrdfDocument, ThePatcherWantsTheRobotsOwnText) {
  const RobotModel robot = RobotModel::fromString(kArm, "arm.urdf");
  const std::string other = replaced(kArm, "xyz=\"0 0 0.1\"", "xyz=\"0 0 0.2\"");
  try {
    patchUrdfMarkers(other, robot, SensorSet{}, SensorParameters{}, "other.urdf");
    FAIL() << "expected an InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.file(), "other.urdf");
    EXPECT_EQ(e.line(), 9);
    EXPECT_NE(std::string(e.what()).find("not the text the robot model was loaded from (arm.urdf)"),
              std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("<origin xyz=\"0 0 0.2\""), std::string::npos) << e.what();
  }
  EXPECT_EQ(patchUrdfMarkers(robot, SensorSet{}, SensorParameters{}).urdf, kArm);
  EXPECT_EQ(patchUrdfMarkers(kArm, robot, SensorSet{}, SensorParameters{}).urdf, kArm);
}

}  // namespace
}  // namespace stac
