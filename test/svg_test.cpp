// The apps' SVG plotting primitives (apps/common/svg.hpp): well-formed XML,
// escaped text, the right number of elements, and coordinates that follow
// the data (monotone maps, equal scale, skipped points).
#include <gtest/gtest.h>
#include <tinyxml.h>

#include <cmath>
#include <functional>
#include <sstream>
#include <string>
#include <vector>

#include "common/svg.hpp"

namespace stac::svg {
namespace {

// Parses an SVG string; fails the test if it is not well-formed XML.
struct Doc {
  TiXmlDocument doc;
  explicit Doc(const std::string& text) {
    doc.Parse(text.c_str(), nullptr, TIXML_ENCODING_UTF8);
    EXPECT_FALSE(doc.Error()) << doc.ErrorDesc() << " at " << doc.ErrorRow() << ":"
                              << doc.ErrorCol() << "\n" << text;
  }
  // Every element with this tag (and, if given, this word in its class).
  std::vector<const TiXmlElement*> all(const std::string& tag, const std::string& cls = "") const {
    std::vector<const TiXmlElement*> out;
    std::function<void(const TiXmlElement*)> walk = [&](const TiXmlElement* e) {
      for (; e; e = e->NextSiblingElement()) {
        const char* c = e->Attribute("class");
        std::istringstream words(c ? c : "");
        bool match = cls.empty();
        for (std::string w; words >> w;) match = match || w == cls;
        if (e->ValueStr() == tag && match) out.push_back(e);
        walk(e->FirstChildElement());
      }
    };
    walk(doc.RootElement());
    return out;
  }
  std::vector<std::string> texts() const {
    std::vector<std::string> out;
    for (const TiXmlElement* e : all("text")) out.push_back(e->GetText() ? e->GetText() : "");
    return out;
  }
};

double attr(const TiXmlElement* e, const char* name) {
  double v = std::nan("");
  e->QueryDoubleAttribute(name, &v);
  return v;
}

// The (x, y) pairs of a path's "M x y L x y ..." data, and its M count.
std::vector<std::pair<double, double>> pathPoints(const TiXmlElement* path, int* moves) {
  std::istringstream in(path->Attribute("d"));
  std::vector<std::pair<double, double>> out;
  *moves = 0;
  for (std::string cmd; in >> cmd;) {
    if (cmd[0] == 'M') ++*moves;
    const double x = std::stod(cmd.substr(1));
    double y;
    in >> y;
    out.emplace_back(x, y);
  }
  return out;
}

bool contains(const std::vector<std::string>& v, const std::string& s) {
  for (const std::string& x : v)
    if (x == s) return true;
  return false;
}

TEST(Svg, EscapesMarkup) {
  EXPECT_EQ(escape("a&b<c>\"d'"), "a&amp;b&lt;c&gt;&quot;d&#39;");
  const std::string name = "m<1> & \"tip\"";
  PlotOptions o;
  o.title = name;
  o.x_label = "x & y";
  const Doc d(linePlot({{name, {0, 1}, {0, 1}}}, o));
  const std::vector<std::string> t = d.texts();
  EXPECT_TRUE(contains(t, name));  // the parser decodes what escape() encoded
  EXPECT_TRUE(contains(t, "x & y"));
}

TEST(Svg, LinePlotDrawsEachSeriesAlongItsData) {
  const Series up{"up", {0, 1, 2, 3}, {1, 2, 3, 4}};
  const Series down{"down", {0, 1, 2, 3}, {4, 3, 2, 1}};
  const Series unnamed{"", {0, 3}, {2, 2}};
  const Doc d(linePlot({up, down, unnamed}, PlotOptions{}));
  const auto paths = d.all("path", "series");
  ASSERT_EQ(paths.size(), 3u);
  int moves = 0;
  const auto p = pathPoints(paths[0], &moves);
  ASSERT_EQ(p.size(), 4u);
  EXPECT_EQ(moves, 1);
  for (size_t i = 1; i < p.size(); ++i) {
    EXPECT_GT(p[i].first, p[i - 1].first);   // x to the right
    EXPECT_LT(p[i].second, p[i - 1].second);  // larger y is higher up
    // Equal steps in the data, equal steps in pixels.
    EXPECT_NEAR(p[i].first - p[i - 1].first, p[1].first - p[0].first, 0.02);
  }
  const auto q = pathPoints(paths[1], &moves);
  EXPECT_NEAR(q[0].second, p[3].second, 0.011);  // same value, same height
  // Legend: the named series only.
  const auto legend = d.all("g", "legend");
  ASSERT_EQ(legend.size(), 1u);
  int entries = 0;
  for (const TiXmlElement* e = legend[0]->FirstChildElement("text"); e;
       e = e->NextSiblingElement("text"))
    ++entries;
  EXPECT_EQ(entries, 2);
}

TEST(Svg, LogAxisSkipsUnplottablePointsAndLabelsDecades) {
  PlotOptions o;
  o.log_y = true;
  const Series s{"cost", {0, 1, 2, 3, 4, 5}, {1, 0.1, std::nan(""), 0.01, -1, 1e-4}};
  const Doc d(linePlot({s}, o));
  const auto paths = d.all("path", "series");
  ASSERT_EQ(paths.size(), 1u);
  int moves = 0;
  const auto p = pathPoints(paths[0], &moves);
  EXPECT_EQ(p.size(), 4u);  // NaN and -1 dropped
  EXPECT_EQ(moves, 3);      // the line breaks at each
  // Equal ratios are equal distances on a log axis.
  EXPECT_NEAR(p[1].second - p[0].second, p[2].second - p[1].second, 0.02);
  EXPECT_NEAR(2 * (p[1].second - p[0].second), p[3].second - p[2].second, 0.02);
  const std::vector<std::string> t = d.texts();
  for (const char* label : {"1e-4", "0.001", "0.01", "0.1", "1"})
    EXPECT_TRUE(contains(t, label)) << label;
}

TEST(Svg, HistogramCountsIntoCommonBins) {
  HistogramOptions o;
  o.bins = 4;
  // Bins of [0, 4]: [0,1) [1,2) [2,3) [3,4].
  const Sample a{"a", {0, 0.5, 1.5, 4}};  // 2, 1, 0, 1 -> three bars
  const Sample b{"b", {2.5, 2.5, 2.5}};   // 0, 0, 3, 0 -> one bar
  const Doc d(histogram({a, b}, o));
  const auto bars = d.all("rect", "bar");
  ASSERT_EQ(bars.size(), 4u);
  // Heights proportional to counts (bars in sample, then bin order).
  const double h1 = attr(bars[1], "height");
  EXPECT_NEAR(attr(bars[0], "height"), 2 * h1, 0.02);
  EXPECT_NEAR(attr(bars[2], "height"), h1, 0.02);
  EXPECT_NEAR(attr(bars[3], "height"), 3 * h1, 0.03);
  // Equal widths, adjacent bins touching.
  EXPECT_NEAR(attr(bars[0], "width"), attr(bars[1], "width"), 0.02);
  EXPECT_NEAR(attr(bars[0], "x") + attr(bars[0], "width"), attr(bars[1], "x"), 0.02);

  // Log bins: values <= 0 dropped; one decade per bin here.
  o.log_x = true;
  o.bins = 3;
  const Doc l(histogram({{"r", {0.001, 0.0011, 0.01, 0.1, 0.0, -2.0}}}, o));
  const auto lbars = l.all("rect", "bar");
  ASSERT_EQ(lbars.size(), 3u);
  EXPECT_NEAR(attr(lbars[0], "height"), 2 * attr(lbars[1], "height"), 0.02);
}

TEST(Svg, SceneIsDrawnAtEqualScale) {
  Scene s;
  s.segments.push_back({0, 0, 1, 0, "#000", 1, "link"});
  s.segments.push_back({0, 0, 0, 0.5, "#000", 1, "link"});
  Scene::Point p;
  p.x = 1, p.y = 0.5, p.label = "m<1>", p.css_class = "marker";
  s.points.push_back(p);
  p.x = 0, p.y = 0, p.label = "", p.filled = false, p.css_class = "seed";
  s.points.push_back(p);
  SceneOptions o;
  o.unit = "m";
  const Doc d(sceneView(s, o));
  const auto segs = d.all("line", "link");
  ASSERT_EQ(segs.size(), 2u);
  const double w = attr(segs[0], "x2") - attr(segs[0], "x1");
  const double h = attr(segs[1], "y1") - attr(segs[1], "y2");
  EXPECT_GT(w, 0);
  EXPECT_NEAR(h, w / 2, 0.02);  // 0.5 up is half of 1 across
  ASSERT_EQ(d.all("circle", "marker").size(), 1u);
  ASSERT_EQ(d.all("circle", "seed").size(), 1u);
  EXPECT_EQ(std::string(d.all("circle", "seed")[0]->Attribute("fill")), "#ffffff");
  EXPECT_TRUE(contains(d.texts(), "m<1>"));
  // A given scale is used as is: twice the units per pixel, half the size.
  o.units_per_pixel = 2 * fitUnitsPerPixel(s, o);
  const Doc half(sceneView(s, o));
  const auto hs = half.all("line", "link");
  EXPECT_NEAR(attr(hs[0], "x2") - attr(hs[0], "x1"), w / 2, 0.02);
}

TEST(Svg, NiceTicks) {
  const std::vector<double> u = niceTicks(0, 1, 5);
  ASSERT_EQ(u.size(), 6u);
  for (int i = 0; i < 6; ++i) EXPECT_NEAR(u[i], 0.2 * i, 1e-12);
  const std::vector<double> t = niceTicks(-3.7, 12.2, 4);
  EXPECT_EQ(t, (std::vector<double>{0, 5, 10}));
  EXPECT_TRUE(niceTicks(1, 1, 5).empty());
}

TEST(Svg, EmptyInputsStillMakeAPicture) {
  EXPECT_NE(linePlot({}, PlotOptions{}).find("no data"), std::string::npos);
  EXPECT_NE(histogram({{"x", {}}}, HistogramOptions{}).find("no data"), std::string::npos);
  const Doc d(sceneView(Scene{}, SceneOptions{}));
  EXPECT_TRUE(d.all("circle").empty());
}

}  // namespace
}  // namespace stac::svg
