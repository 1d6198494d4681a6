// Small SVG plots for self-contained reports and figures: each function
// returns one <svg> element as a string. No scripts, no external resources;
// the output is well-formed XML (every tag closed, attributes quoted, text
// escaped), so it can be inlined in XHTML-compatible HTML or saved as a
// .svg file.
//
//   svg::Series cost{"cost", {0, 1, 2}, {10, 1, 0.1}};
//   svg::PlotOptions o;
//   o.x_label = "iteration"; o.y_label = "cost"; o.log_y = true;
//   std::string s = svg::linePlot({cost}, o);
//
// Elements carry classes a test or a stylesheet can select: "series" (one
// <polyline> per drawn series), "legend", "bar", "segment", "point".
#pragma once

#include <string>
#include <vector>

namespace stac::svg {

// & < > " ' as character entities.
std::string escape(const std::string& text);

// Series colours in drawing order (colour-blind-safe palette).
const std::string& color(int index);

struct Series {
  std::string name;           // legend entry ("" for none)
  std::vector<double> x, y;   // same length
};

struct PlotOptions {
  std::string title, x_label, y_label;
  bool log_y = false;  // y axis in decades; points with y <= 0 are skipped
  int width = 520, height = 320;
};

// A line plot with axes, ticks, grid and a legend of the named series.
// Non-finite points are skipped (the line is broken there); a series with
// a single point is drawn as a dot.
std::string linePlot(const std::vector<Series>& series, const PlotOptions& options);

struct Sample {
  std::string name;
  std::vector<double> values;
};

struct HistogramOptions {
  std::string title, x_label, y_label = "count";
  bool log_x = false;  // bins of equal width in log10(x); values <= 0 are dropped
  int bins = 30;
  int width = 520, height = 280;
};

// Histograms of several samples over common bins, drawn as translucent
// overlaid bars (one <rect class="bar"> per non-empty bin and sample).
std::string histogram(const std::vector<Sample>& samples, const HistogramOptions& options);

// A 2-D drawing at equal scale on both axes: line segments, then labelled
// points (e.g. an orthographic view of a robot's links).
struct Scene {
  struct Segment {
    double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
    std::string color = "#555555";
    double width = 1.5;     // stroke width, pixels
    std::string css_class;  // appended to "segment"
  };
  struct Point {
    double x = 0, y = 0;
    std::string label;      // "" for none
    std::string color = "#000000";
    bool filled = true;     // false: a ring
    double radius = 3.5;    // pixels
    std::string css_class;  // appended to "point"
  };
  std::vector<Segment> segments;
  std::vector<Point> points;
};

struct SceneOptions {
  std::string title, x_label, y_label;  // axis labels name the directions
  std::string unit;                     // of the scale bar, e.g. "m"
  int width = 320, height = 320;
  // Drawing units per pixel; 0 fits the scene. Give several views the same
  // value to draw them at one scale.
  double units_per_pixel = 0;
};

// Scene size in drawing units that fits in `options` (for a common scale).
double fitUnitsPerPixel(const Scene& scene, const SceneOptions& options);

std::string sceneView(const Scene& scene, const SceneOptions& options);

// "Nice" tick positions (1, 2, 5 × 10^k) covering [lo, hi], about `count`.
std::vector<double> niceTicks(double lo, double hi, int count);

}  // namespace stac::svg
