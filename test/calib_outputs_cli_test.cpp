// stac_calib --urdf-out and --report end to end on the bundled gimbal2
// example: the calibrated URDF's marker links sit on the calibrated markers,
// the rest of the file is untouched, unplaceable markers are named; the HTML
// report is well-formed XML with every section and the expected drawing;
// bad output paths are refused before anything is written.
#include <gtest/gtest.h>
#include <tinyxml.h>

#include <functional>
#include <random>
#include <regex>
#include <sstream>

#include "stac/kinematics.hpp"
#include "stac/log.hpp"
#include "stac/robot_model.hpp"
#include "stac/sensors_file.hpp"
#include "support/test_util.hpp"

namespace stac {
namespace {

// data/gimbal2.urdf plus marker links for the head markers (m_base has none):
// m_head_1 with no <origin>, m_head_2 below a mount link, odd formatting.
std::string markerUrdf() {
  std::string urdf = test::readFile(test::dataPath("gimbal2.urdf"));
  const std::string extra = R"(  <!-- marker links: the calibration moves these -->
  <link name="m_head_1"/>
  <link name="m_head_2_mount"/>
  <link name="m_head_2"/>
  <link name="m_head_3"/>
  <link name="m_head_4"/>
  <joint name="m_head_1_joint" type="fixed">
    <parent link="head"/>
    <child link="m_head_1"/>
  </joint>
  <joint name="m_head_2_mount_joint" type="fixed">
    <parent link="head"/>
    <child link="m_head_2_mount"/>
    <origin xyz="0.01 0 0.05" rpy="0 0.3 0"/>
  </joint>
  <joint name="m_head_2_joint" type="fixed">
    <parent link="m_head_2_mount"/>   <child link="m_head_2"/>
    <origin rpy="0.1 0.2 0.3"   xyz='0 0 0.02'/>
  </joint>
  <joint name="m_head_3_joint" type="fixed">
	<parent link="head"/>
	<child link="m_head_3"/>
	<origin xyz="0 0 0.1"/>
  </joint>
  <joint name="m_head_4_joint" type="fixed">
    <parent link="head"/>
    <child link="m_head_4"/>
    <origin xyz="0 0 0" rpy="0 0 0"/>
  </joint>
)";
  urdf.insert(urdf.rfind("</robot>"), extra);
  return urdf;
}

// Every element below root with this tag whose attribute `key` contains
// `value`.
std::vector<const TiXmlElement*> find(const TiXmlElement* root, const std::string& tag,
                                      const std::string& key = "", const std::string& value = "") {
  std::vector<const TiXmlElement*> out;
  std::function<void(const TiXmlElement*)> walk = [&](const TiXmlElement* parent) {
    for (const TiXmlElement* e = parent->FirstChildElement(); e; e = e->NextSiblingElement()) {
      const char* a = key.empty() ? nullptr : e->Attribute(key.c_str());
      if (e->ValueStr() == tag && (key.empty() || (a && std::string(a).find(value) != std::string::npos)))
        out.push_back(e);
      walk(e);
    }
  };
  walk(root);  // descendants only
  return out;
}

std::string allText(const TiXmlNode* n) {
  std::string s;
  for (const TiXmlNode* c = n->FirstChild(); c; c = c->NextSibling())
    s += c->ToText() ? std::string(c->Value()) : allText(c);
  return s;
}

class CalibOutputs : public ::testing::Test {
 protected:
  void SetUp() override { test::writeFile(file("markers.urdf"), markerUrdf()); }
  std::string file(const std::string& n) const { return dir_.file(n); }
  test::CommandResult calib(const std::string& extra,
                            const std::string& seed = test::dataPath("gimbal2_seed.yaml")) const {
    return test::runCommand(test::appPath("stac_calib") + " --log " +
                            test::dataPath("gimbal2_example.csv") + " --sensors " + seed +
                            " --threads 2 " + extra);
  }
  test::TempDir dir_;
};

// m_head_3 on its own marker link (the joint origin becomes T_J d), the
// other head markers on `head` with marker links named after them.
TEST_F(CalibOutputs, CalibratedUrdfPutsMarkerLinksOnTheCalibratedMarkers) {
  std::string seed = test::readFile(test::dataPath("gimbal2_seed.yaml"));
  const std::string from = "name: m_head_3\n      link: head";
  ASSERT_NE(seed.find(from), std::string::npos);
  seed.replace(seed.find(from), from.size(), "name: m_head_3\n      link: m_head_3");
  test::writeFile(file("seed.yaml"), seed);
  const auto r = calib("--urdf " + file("markers.urdf") + " --output " + file("cal.yaml") +
                           " --urdf-out " + file("cal.urdf") + " --quiet",
                       file("seed.yaml"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("4 marker link(s) on the calibrated markers"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("at [0, 0, 0] of their link: m_head_3\n"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("calibrated URDF written to " + file("cal.urdf")), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("markers not written to the URDF"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("  m_base: link 'base' is the root, and the URDF has no link named 'm_base'"),
            std::string::npos)
      << r.out;
  EXPECT_EQ(r.out.find("  m_head_"), std::string::npos) << r.out;

  const RobotModel original = RobotModel::fromFile(file("markers.urdf"));
  const RobotModel patched = RobotModel::fromFile(file("cal.urdf"));
  const SensorsFile cal = loadSensorsFile(file("cal.yaml"), original);
  std::mt19937 rng(11);
  KinematicsWorkspace wa(original), wb(patched);
  int checked = 0;
  for (int trial = 0; trial < 10; ++trial) {
    const Eigen::VectorXd q = test::randomQ(original, rng);
    forwardKinematics(original, q, &wa);
    forwardKinematics(patched, q, &wb);
    for (size_t m = 0; m < cal.sensors.markers.size(); ++m) {
      const std::string& name = cal.sensors.markers[m].name;
      if (name == "m_base") continue;
      // h_k(q) d_m of the calibration, vs. the marker link's origin.
      const Eigen::Vector3d expected =
          wa.link_pose[cal.sensors.markers[m].link] * cal.theta.marker_position[m];
      EXPECT_LT((wb.link_pose[*patched.linkIndex(name)].translation() - expected).norm(), 1e-9)
          << name;
      ++checked;
    }
  }
  EXPECT_EQ(checked, 40);

  // The text differs only in xyz values, plus m_head_1's new <origin>.
  const std::regex xyz(R"(xyz=(['"])[^'"]*\1)");
  std::string a = std::regex_replace(test::readFile(file("markers.urdf")), xyz, "xyz=$1$1");
  std::string b = std::regex_replace(test::readFile(file("cal.urdf")), xyz, "xyz=$1$1");
  const std::string inserted = "\n    <origin xyz=\"\"/>";
  const size_t at = b.find(inserted);
  ASSERT_NE(at, std::string::npos) << b;
  b.erase(at, inserted.size());
  EXPECT_EQ(a, b);
}

TEST_F(CalibOutputs, ReportHasEverySectionAndTheDrawing) {
  const auto r = calib("--urdf " + file("markers.urdf") + " --output " + file("cal.yaml") +
                       " --report " + file("report.html"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("report written to " + file("report.html")), std::string::npos);
  const std::string html = test::readFile(file("report.html"));
  // Self-contained: no scripts, no links; the only URLs are XML namespaces.
  EXPECT_EQ(html.find("<script"), std::string::npos);
  EXPECT_EQ(html.find("href="), std::string::npos);
  EXPECT_EQ(html.find("src="), std::string::npos);
  auto count = [&](const std::string& what) {
    int n = 0;
    for (size_t p = html.find(what); p != std::string::npos; p = html.find(what, p + 1)) ++n;
    return n;
  };
  EXPECT_EQ(count("http"), count("xmlns=\"http://www.w3.org/"));
  TiXmlDocument doc;
  doc.Parse(html.c_str(), nullptr, TIXML_ENCODING_UTF8);
  ASSERT_FALSE(doc.Error()) << doc.ErrorDesc() << " at line " << doc.ErrorRow();
  const TiXmlElement* root = doc.RootElement();
  ASSERT_EQ(root->ValueStr(), "html");
  std::map<std::string, const TiXmlElement*> section;
  for (const TiXmlElement* s : find(root, "section")) section[s->Attribute("id")] = s;
  for (const char* id :
       {"summary", "convergence", "residuals", "sensors", "markers", "unidentifiable"})
    ASSERT_TRUE(section.count(id)) << id;

  // Convergence: one cost curve; one RMS curve per group (marker, tendon),
  // each point a progress line on stderr.
  const auto plots = find(section["convergence"], "svg");
  ASSERT_EQ(plots.size(), 2u);
  const auto cost = find(plots[0], "path", "class", "series");
  ASSERT_EQ(cost.size(), 1u);
  EXPECT_EQ(find(plots[1], "path", "class", "series").size(), 2u);
  int progress_lines = 0;
  std::istringstream err(r.err);
  for (std::string line; std::getline(err, line);) ++progress_lines;
  const std::string d = cost[0]->Attribute("d");
  EXPECT_EQ(static_cast<int>(std::count(d.begin(), d.end(), 'L')) + 1, progress_lines) << r.err;

  // Residual histograms: one per group, before and after bars.
  const auto hists = find(section["residuals"], "svg");
  ASSERT_EQ(hists.size(), 2u);
  for (const TiXmlElement* h : hists) EXPECT_GE(find(h, "rect", "class", "bar").size(), 4u);

  // Per-sensor table: a row per sensor, the RMS the calibration file has.
  const auto rows = find(section["sensors"], "tr");
  ASSERT_EQ(rows.size(), 1u + 5 + 2);
  const std::string yaml = test::readFile(file("cal.yaml"));
  std::smatch m;
  ASSERT_TRUE(std::regex_search(yaml, m, std::regex(R"(name: m_head_3[\s\S]*?rms: ([-0-9.e+]+))")));
  const double rms_yaml = std::stod(m[1]);
  bool found = false;
  for (const TiXmlElement* row : rows) {
    const auto cells = find(row, "td");
    if (cells.size() < 5 || allText(cells[1]) != "m_head_3") continue;
    found = true;
    EXPECT_NEAR(std::stod(allText(cells[4])), rms_yaml, 1e-3 * rms_yaml);
  }
  EXPECT_TRUE(found);

  // Marker views: xy, xz, yz, each with one seed ring and one calibrated
  // dot per marker, joined by a line, and the robot's 4 links.
  const auto views = find(section["markers"], "svg");
  ASSERT_EQ(views.size(), 3u);
  for (const TiXmlElement* v : views) {
    EXPECT_EQ(find(v, "circle", "class", "marker-seed").size(), 5u);
    EXPECT_EQ(find(v, "circle", "class", "marker-final").size(), 5u);
    EXPECT_EQ(find(v, "line", "class", "marker-shift").size(), 5u);
    // 9 links: the 4 of gimbal2 and the 5 marker links of this URDF.
    EXPECT_EQ(find(v, "circle", "class", "link").size(), 9u);
    EXPECT_EQ(find(v, "line", "class", "link").size(), 8u);
  }
  EXPECT_NE(allText(section["unidentifiable"]).find("None"), std::string::npos);
}

// Sensor names are free text: & and < must come through escaped.
TEST_F(CalibOutputs, ReportEscapesNames) {
  std::string seed = test::readFile(test::dataPath("gimbal2_seed.yaml"));
  std::string log = test::readFile(test::dataPath("gimbal2_example.csv"));
  auto rename = [](std::string& s, const std::string& from, const std::string& to) {
    for (size_t p; (p = s.find(from)) != std::string::npos;) s.replace(p, from.size(), to);
  };
  rename(seed, "neck_cyl_1", "cyl<1>&co");
  rename(log, "neck_cyl_1", "cyl<1>&co");
  rename(seed, "m_head_3", "m_<3>&");
  rename(log, "m_head_3", "m_<3>&");
  test::writeFile(file("seed.yaml"), seed);
  test::writeFile(file("data.csv"), log);
  const auto r = test::runCommand(test::appPath("stac_calib") + " --urdf " +
                                  test::dataPath("gimbal2.urdf") + " --log " + file("data.csv") +
                                  " --sensors " + file("seed.yaml") + " --output " +
                                  file("cal.yaml") + " --report " + file("r.html") + " --quiet");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string html = test::readFile(file("r.html"));
  TiXmlDocument doc;
  doc.Parse(html.c_str(), nullptr, TIXML_ENCODING_UTF8);
  ASSERT_FALSE(doc.Error()) << doc.ErrorDesc() << " at line " << doc.ErrorRow();
  const std::string text = allText(doc.RootElement());
  EXPECT_NE(text.find("cyl<1>&co"), std::string::npos);
  EXPECT_NE(text.find("m_<3>&"), std::string::npos);
}

TEST_F(CalibOutputs, BadOutputPathsAreRefusedBeforeAnythingIsWritten) {
  const std::string urdf_before = test::readFile(file("markers.urdf"));
  const auto before = dir_.list();
  auto expectRefused = [&](const std::string& args, const std::string& what) {
    const auto r = calib("--urdf " + file("markers.urdf") + " --output " + file("cal.yaml") +
                         " --quiet " + args);
    EXPECT_EQ(r.exit_code, 2) << args << "\n" << r.err;
    EXPECT_NE(r.err.find(what), std::string::npos) << r.err;
    EXPECT_EQ(dir_.list(), before) << args;
  };
  expectRefused("--urdf-out " + file("markers.urdf"),
                "--urdf-out '" + file("markers.urdf") + "' is one of the inputs");
  expectRefused("--urdf-out " + file("sub/../markers.urdf"), "is one of the inputs");
  expectRefused("--report " + file("cal.yaml"), "--report and --output name the same file");
  expectRefused("--report " + file("no/such/folder/r.html"), "does not exist");
  expectRefused("--urdf-out " + file("missing/cal.urdf"), "does not exist");
  expectRefused("--report " + test::dataPath("gimbal2_seed.yaml"), "is one of the inputs");
  expectRefused("--urdf-out", "--urdf-out");
  EXPECT_EQ(test::readFile(file("markers.urdf")), urdf_before);
}

}  // namespace
}  // namespace stac
