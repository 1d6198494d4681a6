#include "common/svg.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

namespace stac::svg {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Pixel coordinates with two decimals: plenty, and keeps files small.
std::string px(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.2f", v);
  return buf;
}

std::string fmt(const char* f, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}

// A tick label for v on a linear axis with tick spacing `step`.
std::string linearLabel(double v, double step, double magnitude) {
  if (std::abs(v) < step * 1e-9) return "0";
  if (magnitude >= 1e5 || step < 1e-4) return fmt("%.3g", v);
  const int decimals = std::max(0, -static_cast<int>(std::floor(std::log10(step) + 1e-9)));
  char f[16];
  std::snprintf(f, sizeof f, "%%.%df", decimals);
  return fmt(f, v);
}

// A tick label for v = m * 10^e on a log axis: plain near 1, else "1e-5".
std::string logLabel(double v) {
  const double e = std::floor(std::log10(v) + 1e-9);
  if (e >= -3 && e <= 4) return linearLabel(v, std::pow(10.0, e), v);
  // "2e-05" -> "2e-5", "1e+06" -> "1e6"
  const std::string s = fmt("%.0e", v);
  const size_t p = s.find('e');
  std::string exponent = s.substr(p + 1);
  const bool negative = exponent[0] == '-';
  exponent.erase(0, exponent.find_first_not_of("+-0"));
  return s.substr(0, p + 1) + (negative ? "-" : "") + (exponent.empty() ? "0" : exponent);
}

// One axis: the data range mapped onto pixels, and its ticks.
struct Axis {
  bool log = false;
  double lo = 0, hi = 1;            // axis range (data units)
  double p0 = 0, p1 = 1;            // pixels of lo and hi
  std::vector<double> ticks;        // data units
  std::vector<std::string> labels;

  double map(double v) const {
    const double a = log ? std::log10(lo) : lo, b = log ? std::log10(hi) : hi;
    const double t = ((log ? std::log10(v) : v) - a) / (b - a);
    return p0 + t * (p1 - p0);
  }
};

// integer: ticks on whole numbers only (e.g. iteration counts).
Axis linearAxis(double lo, double hi, int count, bool integer = false) {
  Axis a;
  if (!(lo <= hi)) lo = 0, hi = 1;
  if (hi - lo < 1e-300 + 1e-12 * std::abs(hi)) {
    const double pad = std::abs(lo) > 0 ? 0.1 * std::abs(lo) : 1.0;
    lo -= pad;
    hi += pad;
  }
  if (integer) count = std::max(1, std::min(count, static_cast<int>(std::ceil(hi - lo))));
  const std::vector<double> t = niceTicks(lo, hi, count);
  const double step = t.size() > 1 ? t[1] - t[0] : hi - lo;
  a.lo = std::min(lo, std::floor(lo / step + 1e-9) * step);
  a.hi = std::max(hi, std::ceil(hi / step - 1e-9) * step);
  a.ticks = niceTicks(a.lo, a.hi, count);
  const double magnitude = std::max(std::abs(a.lo), std::abs(a.hi));
  for (double v : a.ticks) a.labels.push_back(linearLabel(v, step, magnitude));
  return a;
}

Axis logAxis(double lo, double hi) {
  Axis a;
  a.log = true;
  if (!(lo > 0 && hi >= lo)) lo = 1, hi = 10;
  double e0 = std::floor(std::log10(lo) + 1e-12), e1 = std::ceil(std::log10(hi) - 1e-12);
  if (e1 <= e0) e1 = e0 + 1;
  a.lo = std::pow(10.0, e0);
  a.hi = std::pow(10.0, e1);
  const int decades = static_cast<int>(e1 - e0);
  const int every = std::max(1, (decades + 5) / 6);
  for (int e = static_cast<int>(e0); e <= e1; ++e) {
    if ((e - static_cast<int>(e0)) % every) continue;
    const double v = std::pow(10.0, e);
    a.ticks.push_back(v);
    a.labels.push_back(logLabel(v));
    if (decades <= 2 && e < e1)
      for (double m : {2.0, 5.0}) {
        a.ticks.push_back(m * v);
        a.labels.push_back(logLabel(m * v));
      }
  }
  return a;
}

struct Frame {
  double left, top, width, height;  // plot area in pixels
};

void open(std::ostringstream& o, int width, int height, const char* css_class) {
  o << "<svg xmlns=\"http://www.w3.org/2000/svg\" class=\"" << css_class << "\" width=\"" << width
    << "\" height=\"" << height << "\" viewBox=\"0 0 " << width << " " << height
    << "\" font-family=\"sans-serif\" font-size=\"11\">";
  o << "<rect x=\"0\" y=\"0\" width=\"" << width << "\" height=\"" << height
    << "\" fill=\"#ffffff\"/>";
}

void titleAndLabels(std::ostringstream& o, const Frame& f, int width, int height,
                    const std::string& title, const std::string& x_label,
                    const std::string& y_label) {
  if (!title.empty())
    o << "<text class=\"title\" x=\"" << px(width / 2.0) << "\" y=\"16\" text-anchor=\"middle\" "
      << "font-size=\"13\" font-weight=\"bold\">" << escape(title) << "</text>";
  if (!x_label.empty())
    o << "<text class=\"x-label\" x=\"" << px(f.left + f.width / 2) << "\" y=\"" << height - 6
      << "\" text-anchor=\"middle\">" << escape(x_label) << "</text>";
  if (!y_label.empty())
    o << "<text class=\"y-label\" transform=\"rotate(-90)\" x=\"" << px(-(f.top + f.height / 2))
      << "\" y=\"13\" text-anchor=\"middle\">" << escape(y_label) << "</text>";
}

// Grid, ticks and tick labels of both axes, and the frame.
void drawAxes(std::ostringstream& o, const Frame& f, const Axis& x, const Axis& y) {
  o << "<g class=\"axes\" stroke=\"#e4e4e4\" stroke-width=\"1\">";
  for (double t : x.ticks)
    o << "<line x1=\"" << px(x.map(t)) << "\" y1=\"" << px(f.top) << "\" x2=\"" << px(x.map(t))
      << "\" y2=\"" << px(f.top + f.height) << "\"/>";
  for (double t : y.ticks)
    o << "<line x1=\"" << px(f.left) << "\" y1=\"" << px(y.map(t)) << "\" x2=\""
      << px(f.left + f.width) << "\" y2=\"" << px(y.map(t)) << "\"/>";
  o << "</g>";
  o << "<rect x=\"" << px(f.left) << "\" y=\"" << px(f.top) << "\" width=\"" << px(f.width)
    << "\" height=\"" << px(f.height) << "\" fill=\"none\" stroke=\"#444444\"/>";
  o << "<g class=\"tick-labels\" fill=\"#333333\">";
  for (size_t i = 0; i < x.ticks.size(); ++i)
    o << "<text x=\"" << px(x.map(x.ticks[i])) << "\" y=\"" << px(f.top + f.height + 14)
      << "\" text-anchor=\"middle\">" << escape(x.labels[i]) << "</text>";
  for (size_t i = 0; i < y.ticks.size(); ++i)
    o << "<text x=\"" << px(f.left - 5) << "\" y=\"" << px(y.map(y.ticks[i]) + 4)
      << "\" text-anchor=\"end\">" << escape(y.labels[i]) << "</text>";
  o << "</g>";
}

// What is drawn in the plot area, as pixel boxes (x0, y0, x1, y1), so the
// legend can go where it hides least.
using Box = std::array<double, 4>;

double overlap(const Box& a, const Box& b) {
  const double w = std::min(a[2], b[2]) - std::max(a[0], b[0]);
  const double h = std::min(a[3], b[3]) - std::max(a[1], b[1]);
  return w > 0 && h > 0 ? w * h : 0.0;
}

// Legend in the corner of the plot area that covers the least of `drawn`
// (top right on a tie).
void drawLegend(std::ostringstream& o, const Frame& f, const std::vector<std::string>& names,
                const std::vector<int>& colors, bool bars, const std::vector<Box>& drawn) {
  if (names.empty()) return;
  size_t longest = 0;
  for (const std::string& n : names) longest = std::max(longest, n.size());
  const double w = 34 + 6.2 * longest, h = 6 + 15.0 * names.size();
  const double right = f.left + f.width - w - 6, left = f.left + 6;
  const double top = f.top + 6, bottom = f.top + f.height - h - 6;
  double x = right, y = top, best = -1;
  for (const auto& [cx, cy] : {std::pair{right, top}, {left, top}, {right, bottom}, {left, bottom}}) {
    double covered = 0;
    for (const Box& b : drawn) covered += overlap({cx, cy, cx + w, cy + h}, b);
    if (best < 0 || covered < best - 1e-9) best = covered, x = cx, y = cy;
  }
  o << "<g class=\"legend\"><rect x=\"" << px(x) << "\" y=\"" << px(y) << "\" width=\"" << px(w)
    << "\" height=\"" << px(h) << "\" fill=\"#ffffff\" fill-opacity=\"0.85\" stroke=\"#bbbbbb\"/>";
  for (size_t i = 0; i < names.size(); ++i) {
    const double cy = y + 11 + 15.0 * i;
    const std::string& c = color(colors[i]);
    if (bars)
      o << "<rect x=\"" << px(x + 6) << "\" y=\"" << px(cy - 5) << "\" width=\"16\" height=\"9\" fill=\""
        << c << "\" fill-opacity=\"0.45\" stroke=\"" << c << "\"/>";
    else
      o << "<line x1=\"" << px(x + 6) << "\" y1=\"" << px(cy) << "\" x2=\"" << px(x + 22)
        << "\" y2=\"" << px(cy) << "\" stroke=\"" << c << "\" stroke-width=\"2\"/>";
    o << "<text x=\"" << px(x + 28) << "\" y=\"" << px(cy + 4) << "\">" << escape(names[i])
      << "</text>";
  }
  o << "</g>";
}

void noData(std::ostringstream& o, const Frame& f) {
  o << "<text x=\"" << px(f.left + f.width / 2) << "\" y=\"" << px(f.top + f.height / 2)
    << "\" text-anchor=\"middle\" fill=\"#888888\">no data</text>";
}

}  // namespace

std::string escape(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += c;
    }
  }
  return out;
}

const std::string& color(int index) {
  // Okabe & Ito's palette, distinguishable with colour-blindness.
  static const std::vector<std::string> kColors = {"#0072B2", "#D55E00", "#009E73", "#E69F00",
                                                   "#CC79A7", "#56B4E9", "#000000", "#F0E442"};
  return kColors[static_cast<size_t>(std::abs(index)) % kColors.size()];
}

std::vector<double> niceTicks(double lo, double hi, int count) {
  std::vector<double> ticks;
  if (!(hi > lo) || !std::isfinite(lo) || !std::isfinite(hi)) return ticks;
  const double raw = (hi - lo) / std::max(1, count);
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  const double norm = raw / mag;
  const double step = (norm < 1.5 ? 1 : norm < 3 ? 2 : norm < 7 ? 5 : 10) * mag;
  for (double k = std::ceil(lo / step - 1e-9); k * step <= hi + 1e-9 * step; k += 1)
    ticks.push_back(std::abs(k) < 1e-9 ? 0.0 : k * step);
  return ticks;
}

std::string linePlot(const std::vector<Series>& series, const PlotOptions& options) {
  const Frame f{64, options.title.empty() ? 12.0 : 26.0, options.width - 64 - 16.0,
                options.height - (options.title.empty() ? 12.0 : 26.0) - 42.0};
  auto usable = [&](double x, double y) {
    return std::isfinite(x) && std::isfinite(y) && (!options.log_y || y > 0);
  };
  double x0 = kInf, x1 = -kInf, y0 = kInf, y1 = -kInf;
  for (const Series& s : series)
    for (size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i)
      if (usable(s.x[i], s.y[i])) {
        x0 = std::min(x0, s.x[i]), x1 = std::max(x1, s.x[i]);
        y0 = std::min(y0, s.y[i]), y1 = std::max(y1, s.y[i]);
      }
  const bool empty = x0 > x1;
  bool integer_x = true;
  for (const Series& s : series)
    for (double v : s.x) integer_x = integer_x && (!std::isfinite(v) || v == std::round(v));
  Axis x = linearAxis(empty ? 0 : x0, empty ? 1 : x1, 8, integer_x);
  Axis y = options.log_y ? logAxis(empty ? 1 : y0, empty ? 10 : y1)
                         : linearAxis(empty ? 0 : y0, empty ? 1 : y1, 6);
  x.p0 = f.left, x.p1 = f.left + f.width;
  y.p0 = f.top + f.height, y.p1 = f.top;

  std::ostringstream o;
  open(o, options.width, options.height, "plot line-plot");
  titleAndLabels(o, f, options.width, options.height, options.title, options.x_label,
                 options.y_label);
  drawAxes(o, f, x, y);
  if (empty) noData(o, f);
  std::vector<std::string> names;
  std::vector<int> colors;
  std::vector<Box> drawn;
  for (size_t k = 0; k < series.size(); ++k) {
    const Series& s = series[k];
    std::string d;
    int points = 0;
    bool pen_down = false;
    double last_x = 0, last_y = 0;
    for (size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i) {
      if (!usable(s.x[i], s.y[i])) {
        pen_down = false;
        continue;
      }
      // The line as small boxes every few pixels.
      const double px1 = x.map(s.x[i]), py1 = y.map(s.y[i]);
      const int steps = pen_down ? 1 + static_cast<int>(std::hypot(px1 - last_x, py1 - last_y) / 4) : 1;
      for (int k2 = 1; k2 <= steps; ++k2) {
        const double bx = pen_down ? last_x + (px1 - last_x) * k2 / steps : px1;
        const double by = pen_down ? last_y + (py1 - last_y) * k2 / steps : py1;
        drawn.push_back({bx - 2, by - 2, bx + 2, by + 2});
      }
      last_x = px1, last_y = py1;
      d += (pen_down ? " L" : (d.empty() ? "M" : " M")) + px(x.map(s.x[i])) + " " +
           px(y.map(s.y[i]));
      pen_down = true;
      ++points;
    }
    if (points == 0) continue;
    const std::string& c = color(static_cast<int>(k));
    o << "<path class=\"series\" d=\"" << d << "\" fill=\"none\" stroke=\"" << c
      << "\" stroke-width=\"2\" stroke-linejoin=\"round\"/>";
    if (points <= 60) {  // few points: mark each (and a lone point is visible)
      o << "<g fill=\"" << c << "\">";
      for (size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i)
        if (usable(s.x[i], s.y[i]))
          o << "<circle cx=\"" << px(x.map(s.x[i])) << "\" cy=\"" << px(y.map(s.y[i]))
            << "\" r=\"2.5\"/>";
      o << "</g>";
    }
    if (!s.name.empty()) {
      names.push_back(s.name);
      colors.push_back(static_cast<int>(k));
    }
  }
  drawLegend(o, f, names, colors, false, drawn);
  o << "</svg>";
  return o.str();
}

std::string histogram(const std::vector<Sample>& samples, const HistogramOptions& options) {
  const Frame f{64, options.title.empty() ? 12.0 : 26.0, options.width - 64 - 16.0,
                options.height - (options.title.empty() ? 12.0 : 26.0) - 42.0};
  const int bins = std::max(1, options.bins);
  auto usable = [&](double v) { return std::isfinite(v) && (!options.log_x || v > 0); };
  auto key = [&](double v) { return options.log_x ? std::log10(v) : v; };
  double k0 = kInf, k1 = -kInf;
  for (const Sample& s : samples)
    for (double v : s.values)
      if (usable(v)) k0 = std::min(k0, key(v)), k1 = std::max(k1, key(v));
  const bool empty = k0 > k1;
  if (empty) k0 = 0, k1 = 1;
  if (k1 - k0 < 1e-12 * std::max(1.0, std::abs(k1))) {
    const double pad = options.log_x ? 0.5 : std::max(0.5, 0.1 * std::abs(k0));
    k0 -= pad, k1 += pad;
  }
  const double width = (k1 - k0) / bins;
  std::vector<std::vector<int>> counts(samples.size(), std::vector<int>(bins, 0));
  int max_count = 0;
  for (size_t s = 0; s < samples.size(); ++s)
    for (double v : samples[s].values) {
      if (!usable(v)) continue;
      const int b = std::clamp(static_cast<int>((key(v) - k0) / width), 0, bins - 1);
      max_count = std::max(max_count, ++counts[s][b]);
    }
  // A bin's width of margin on both sides, so the end bars stand clear of
  // the frame.
  Axis x = options.log_x ? logAxis(std::pow(10.0, k0 - width), std::pow(10.0, k1 + width))
                         : linearAxis(k0 - width, k1 + width, 8);
  if (options.log_x) {
    // Log axes snap to whole decades; keep the bins' own range instead and
    // the decade ticks that fall inside it.
    Axis tight;
    tight.log = true;
    tight.lo = std::pow(10.0, k0 - width);
    tight.hi = std::pow(10.0, k1 + width);
    for (size_t i = 0; i < x.ticks.size(); ++i)
      if (x.ticks[i] >= tight.lo * (1 - 1e-9) && x.ticks[i] <= tight.hi * (1 + 1e-9)) {
        tight.ticks.push_back(x.ticks[i]);
        tight.labels.push_back(x.labels[i]);
      }
    if (tight.ticks.size() < 2) {  // less than a decade: ticks at nice values
      for (double t : niceTicks(tight.lo, tight.hi, 4)) {
        if (t <= 0) continue;
        tight.ticks.push_back(t);
        tight.labels.push_back(logLabel(t));
      }
    }
    x = tight;
  }
  Axis y = linearAxis(0, std::max(1, max_count), 5);
  x.p0 = f.left, x.p1 = f.left + f.width;
  y.p0 = f.top + f.height, y.p1 = f.top;

  std::ostringstream o;
  open(o, options.width, options.height, "plot histogram");
  titleAndLabels(o, f, options.width, options.height, options.title, options.x_label,
                 options.y_label);
  drawAxes(o, f, x, y);
  if (empty) noData(o, f);
  auto edge = [&](int b) {
    const double k = k0 + b * width;
    return x.map(options.log_x ? std::pow(10.0, k) : k);
  };
  std::vector<std::string> names;
  std::vector<int> colors;
  std::vector<Box> drawn;
  for (size_t s = 0; s < samples.size(); ++s) {
    const std::string& c = color(static_cast<int>(s));
    o << "<g fill=\"" << c << "\" fill-opacity=\"0.45\" stroke=\"" << c << "\" stroke-width=\"0.8\">";
    for (int b = 0; b < bins; ++b) {
      if (counts[s][b] == 0) continue;
      const double top = y.map(counts[s][b]);
      drawn.push_back({edge(b), top, edge(b + 1), y.p0});
      o << "<rect class=\"bar\" x=\"" << px(edge(b)) << "\" y=\"" << px(top) << "\" width=\""
        << px(edge(b + 1) - edge(b)) << "\" height=\"" << px(y.p0 - top) << "\"/>";
    }
    o << "</g>";
    if (!samples[s].name.empty()) {
      names.push_back(samples[s].name);
      colors.push_back(static_cast<int>(s));
    }
  }
  drawLegend(o, f, names, colors, true, drawn);
  o << "</svg>";
  return o.str();
}

double fitUnitsPerPixel(const Scene& scene, const SceneOptions& options) {
  double x0 = kInf, x1 = -kInf, y0 = kInf, y1 = -kInf;
  auto add = [&](double x, double y) {
    if (!std::isfinite(x) || !std::isfinite(y)) return;
    x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
  };
  for (const Scene::Segment& s : scene.segments) add(s.x0, s.y0), add(s.x1, s.y1);
  for (const Scene::Point& p : scene.points) add(p.x, p.y);
  if (x0 > x1) return 1.0;
  const double w = options.width - 24.0, h = options.height - 24.0 - 36.0;
  const double upp = 1.2 * std::max((x1 - x0) / w, (y1 - y0) / h);
  return upp > 0 ? upp : 1e-3;
}

std::string sceneView(const Scene& scene, const SceneOptions& options) {
  const double upp =
      options.units_per_pixel > 0 ? options.units_per_pixel : fitUnitsPerPixel(scene, options);
  const Frame f{12, options.title.empty() ? 12.0 : 26.0, options.width - 24.0,
                options.height - (options.title.empty() ? 12.0 : 26.0) - 36.0};
  double x0 = kInf, x1 = -kInf, y0 = kInf, y1 = -kInf;
  auto add = [&](double x, double y) {
    if (!std::isfinite(x) || !std::isfinite(y)) return;
    x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
  };
  for (const Scene::Segment& s : scene.segments) add(s.x0, s.y0), add(s.x1, s.y1);
  for (const Scene::Point& p : scene.points) add(p.x, p.y);
  if (x0 > x1) x0 = x1 = y0 = y1 = 0;
  const double cx = (x0 + x1) / 2, cy = (y0 + y1) / 2;
  auto mx = [&](double x) { return f.left + f.width / 2 + (x - cx) / upp; };
  auto my = [&](double y) { return f.top + f.height / 2 - (y - cy) / upp; };

  std::ostringstream o;
  open(o, options.width, options.height, "plot scene");
  if (!options.title.empty())
    o << "<text class=\"title\" x=\"" << px(options.width / 2.0)
      << "\" y=\"16\" text-anchor=\"middle\" font-size=\"13\" font-weight=\"bold\">"
      << escape(options.title) << "</text>";
  o << "<rect x=\"" << px(f.left) << "\" y=\"" << px(f.top) << "\" width=\"" << px(f.width)
    << "\" height=\"" << px(f.height) << "\" fill=\"none\" stroke=\"#cccccc\"/>";
  // Axis directions (bottom left) and a scale bar (bottom right).
  const double ax = f.left + 8, ay = f.top + f.height + 24;
  o << "<g class=\"directions\" stroke=\"#444444\" stroke-width=\"1.2\">"
    << "<line x1=\"" << px(ax) << "\" y1=\"" << px(ay) << "\" x2=\"" << px(ax + 22) << "\" y2=\""
    << px(ay) << "\"/><line x1=\"" << px(ax) << "\" y1=\"" << px(ay) << "\" x2=\"" << px(ax)
    << "\" y2=\"" << px(ay - 22) << "\"/></g>";
  o << "<text x=\"" << px(ax + 25) << "\" y=\"" << px(ay + 4) << "\">" << escape(options.x_label)
    << "</text><text x=\"" << px(ax - 3) << "\" y=\"" << px(ay - 25) << "\">"
    << escape(options.y_label) << "</text>";
  const std::vector<double> bar = niceTicks(0, 0.3 * f.width * upp, 1);
  if (bar.size() > 1) {
    const double len = bar[1] / upp, bx = f.left + f.width - len - 4, by = ay;
    o << "<g class=\"scale-bar\"><line x1=\"" << px(bx) << "\" y1=\"" << px(by) << "\" x2=\""
      << px(bx + len) << "\" y2=\"" << px(by) << "\" stroke=\"#444444\" stroke-width=\"2\"/>"
      << "<text x=\"" << px(bx + len / 2) << "\" y=\"" << px(by - 5)
      << "\" text-anchor=\"middle\">" << escape(linearLabel(bar[1], bar[1], bar[1]) + (options.unit.empty() ? "" : " " + options.unit))
      << "</text></g>";
  }
  for (const Scene::Segment& s : scene.segments)
    o << "<line class=\"segment" << (s.css_class.empty() ? "" : " " + escape(s.css_class))
      << "\" x1=\"" << px(mx(s.x0)) << "\" y1=\"" << px(my(s.y0)) << "\" x2=\"" << px(mx(s.x1))
      << "\" y2=\"" << px(my(s.y1)) << "\" stroke=\"" << escape(s.color) << "\" stroke-width=\""
      << px(s.width) << "\" stroke-linecap=\"round\"/>";
  for (const Scene::Point& p : scene.points) {
    o << "<circle class=\"point" << (p.css_class.empty() ? "" : " " + escape(p.css_class))
      << "\" cx=\"" << px(mx(p.x)) << "\" cy=\"" << px(my(p.y)) << "\" r=\"" << px(p.radius)
      << "\" fill=\"" << (p.filled ? escape(p.color) : "#ffffff") << "\" stroke=\""
      << escape(p.color) << "\" stroke-width=\"1.2\"/>";
  }
  o << "<g class=\"labels\" font-size=\"9\" fill=\"#222222\">";
  for (const Scene::Point& p : scene.points)
    if (!p.label.empty())
      o << "<text x=\"" << px(mx(p.x) + p.radius + 2) << "\" y=\"" << px(my(p.y) - p.radius - 1)
        << "\">" << escape(p.label) << "</text>";
  o << "</g></svg>";
  return o.str();
}

}  // namespace stac::svg
