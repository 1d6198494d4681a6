#include "common/calib_report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "common/svg.hpp"
#include "stac/kinematics.hpp"

namespace stac::cli {
namespace {

using svg::escape;

std::string num(double v, const char* f = "%.4g") {
  if (std::isinf(v)) return v > 0 ? "∞" : "-∞";
  if (std::isnan(v)) return "–";
  char buf[64];
  std::snprintf(buf, sizeof buf, f, v);
  return buf;
}


// Tables and plots are laid out by this stylesheet only (no '<' or '&' in
// it: the document must stay well-formed XML).
const char* kStyle = R"(
body { font-family: sans-serif; font-size: 14px; color: #222; margin: 24px auto; max-width: 1100px; padding: 0 16px; }
h1 { font-size: 22px; margin-bottom: 4px; }
h2 { font-size: 18px; border-bottom: 1px solid #ccc; padding-bottom: 3px; margin-top: 32px; }
table { border-collapse: collapse; margin: 8px 0; }
th, td { padding: 3px 10px; border-bottom: 1px solid #e4e4e4; text-align: right; }
th { background: #f3f3f3; }
td.name, th.name { text-align: left; }
.figures { display: flex; flex-wrap: wrap; gap: 12px; }
.note { color: #555; font-size: 13px; }
code { background: #f3f3f3; padding: 0 3px; }
ul.unidentifiable li { margin-bottom: 6px; }
)";

std::string th(const std::string& s, bool name = false) {
  return std::string("<th") + (name ? " class=\"name\"" : "") + ">" + escape(s) + "</th>";
}
std::string td(const std::string& s, bool name = false) {
  return std::string("<td") + (name ? " class=\"name\"" : "") + ">" + escape(s) + "</td>";
}

void summarySection(std::ostringstream& o, const RobotModel& robot, const SensorSet& sensors,
                    const CalibrationResult& result, const ReportInputs& inputs) {
  const CalibrationSummary& s = result.summary;
  o << "<section id=\"summary\"><h2>Summary</h2><p>";
  o << "URDF <code>" << escape(inputs.urdf) << "</code>, log <code>" << escape(inputs.log)
    << "</code>, sensors "
    << (inputs.sensors.empty() ? std::string("inferred from the log header")
                               : "<code>" + escape(inputs.sensors) + "</code>")
    << ".<br/>";
  o << s.frames << " frames, " << robot.dof() << " joints, " << sensors.markers.size()
    << " markers, " << sensors.joint_sensors.size() << " joint sensors, "
    << sensors.tendon_sensors.size() << " tendon sensors. Method " << escape(s.method)
    << (s.q_phase.empty() ? "" : " / q-phase " + escape(s.q_phase)) << ", " << s.iterations
    << " iterations, " << (s.converged ? "converged" : "<strong>not converged</strong>") << ", "
    << num(s.wall_time, "%.2f") << " s.</p>";
  o << "<table><tr>" << th("group", true) << th("unit") << th("RMS before") << th("RMS after")
    << th("σ (final)") << "</tr>";
  for (int g = 0; g < kNumSensorGroups; ++g) {
    if (!s.group_present[g]) continue;
    o << "<tr>" << td(groupName(static_cast<SensorGroup>(g)), true) << td(groupUnit(static_cast<SensorGroup>(g)))
      << td(num(s.before_rms[g])) << td(num(s.after_rms[g])) << td(num(s.group_sigma[g]))
      << "</tr>";
  }
  o << "</table><p class=\"note\">Before: the seed θ with each frame's joint angles fitted "
       "to it (on up to 1000 frames spread over the log). After: the calibrated θ and "
       "joint angles.</p></section>";
}

void convergenceSection(std::ostringstream& o, const std::vector<IterationReport>& history) {
  o << "<section id=\"convergence\"><h2>Convergence</h2>";
  bool increasing = true;
  for (size_t i = 1; i < history.size(); ++i)
    increasing = increasing && history[i].iteration > history[i - 1].iteration;
  svg::Series cost{"cost", {}, {}};
  svg::Series rms[kNumSensorGroups];
  for (int g = 0; g < kNumSensorGroups; ++g)
    rms[g].name = std::string(groupName(static_cast<SensorGroup>(g))) + " (" + groupUnit(static_cast<SensorGroup>(g)) + ")";
  bool present[kNumSensorGroups] = {false, false, false};
  for (size_t i = 0; i < history.size(); ++i) {
    const IterationReport& r = history[i];
    const double x = increasing ? r.iteration : static_cast<double>(i);
    cost.x.push_back(x);
    cost.y.push_back(r.cost);
    for (int g = 0; g < kNumSensorGroups; ++g) {
      if (!r.present[g]) continue;
      present[g] = true;
      rms[g].x.push_back(x);
      rms[g].y.push_back(r.rms[g]);
    }
  }
  std::vector<svg::Series> groups;
  for (int g = 0; g < kNumSensorGroups; ++g)
    if (present[g]) groups.push_back(rms[g]);
  svg::PlotOptions po;
  // The EKF reports as it filters (about every tenth of the frames), the
  // iterative methods once per outer iteration.
  const bool filter = !history.empty() && history.back().stage == "ekf";
  po.x_label = filter       ? "filter progress report (every ~10% of the frames)"
               : increasing ? "outer iteration (0: initialisation)"
                            : "progress report";
  po.log_y = true;
  po.title = "cost ½Σρ (at each iteration's σ)";
  po.y_label = "cost";
  o << "<div class=\"figures\">" << svg::linePlot({cost}, po);
  po.title = "RMS residual per group";
  po.y_label = "RMS residual";
  o << svg::linePlot(groups, po) << "</div>";
  o << "<p class=\"note\">" << history.size()
    << " progress reports. The cost is evaluated with the noise σ of that iteration, which "
       "variance adaptation re-estimates, so it need not decrease monotonically.</p></section>";
}

void residualSection(std::ostringstream& o, const CalibrationSummary& s,
                     const ResidualSample& before, const ResidualSample& after) {
  o << "<section id=\"residuals\"><h2>Residual distributions</h2><div class=\"figures\">";
  for (int g = 0; g < kNumSensorGroups; ++g) {
    if (!s.group_present[g]) continue;
    const SensorGroup group = static_cast<SensorGroup>(g);
    svg::HistogramOptions ho;
    ho.title = std::string(groupName(group)) + " sensors";
    ho.x_label = std::string("|residual| (") + (g == 0 ? "m, Euclidean" : "raw units") +
                 "), log scale";
    ho.y_label = "readings";
    ho.log_x = true;
    ho.bins = 40;
    o << svg::histogram({{"before: RMS " + num(before.rms(group)), before.magnitude[g]},
                         {"after: RMS " + num(after.rms(group)), after.magnitude[g]}},
                        ho);
  }
  o << "</div><p class=\"note\">" << after.frames.size()
    << " frames spread over the log; one count per reading (a marker reading is its "
       "Euclidean distance).</p></section>";
}

std::string attachment(const SensorSet& sensors, SensorGroup g, int i) {
  if (g == SensorGroup::kMarker) return "link " + sensors.markers[i].link_name;
  if (g == SensorGroup::kJoint) return "joint " + sensors.joint_sensors[i].joint_name;
  const TendonSensorConfig& t = sensors.tendon_sensors[i];
  std::string s = t.kind == TendonSensorConfig::Kind::kPath ? "path " : "coupling ";
  if (t.kind == TendonSensorConfig::Kind::kPath)
    for (size_t k = 0; k < t.path.size(); ++k) s += (k ? "–" : "") + t.path[k].link_name;
  else
    for (size_t k = 0; k < t.coupling.size(); ++k) s += (k ? ", " : "") + t.coupling[k].joint_name;
  return s;
}

void sensorSection(std::ostringstream& o, const CalibrationResult& r, const ResidualSample& before) {
  const SensorSet& sensors = r.sensors;
  o << "<section id=\"sensors\"><h2>Per-sensor residuals</h2><table><tr>" << th("group", true)
    << th("sensor", true) << th("on", true) << th("RMS before") << th("RMS after") << th("MAE after")
    << th("readings") << th("σ (final)") << th("fixed") << "</tr>";
  const std::vector<ResidualStats>* stats[kNumSensorGroups] = {
      &r.marker_residual, &r.joint_residual, &r.tendon_residual};
  const int counts[kNumSensorGroups] = {static_cast<int>(sensors.markers.size()),
                                        static_cast<int>(sensors.joint_sensors.size()),
                                        static_cast<int>(sensors.tendon_sensors.size())};
  for (int g = 0; g < kNumSensorGroups; ++g) {
    // RMS before per sensor, from the sample's sensor indices.
    std::vector<double> sse(counts[g], 0.0);
    std::vector<int> n(counts[g], 0);
    for (size_t k = 0; k < before.magnitude[g].size(); ++k) {
      sse[before.sensor[g][k]] += before.magnitude[g][k] * before.magnitude[g][k];
      ++n[before.sensor[g][k]];
    }
    for (int i = 0; i < counts[g]; ++i) {
      const SensorGroup group = static_cast<SensorGroup>(g);
      const ResidualStats st = i < static_cast<int>(stats[g]->size()) ? (*stats[g])[i] : ResidualStats{};
      const std::string name = g == 0   ? sensors.markers[i].name
                               : g == 1 ? sensors.joint_sensors[i].name
                                        : sensors.tendon_sensors[i].name;
      const double sigma = g == 0   ? sensors.markers[i].sigma
                           : g == 1 ? sensors.joint_sensors[i].sigma
                                    : sensors.tendon_sensors[i].sigma;
      const FixedGainBias fixed = g == 0   ? FixedGainBias::both(sensors.markers[i].fixed)
                                  : g == 1 ? sensors.joint_sensors[i].fixed
                                           : sensors.tendon_sensors[i].fixed;
      o << "<tr>" << td(groupName(group), true) << td(name, true)
        << td(attachment(sensors, group, i), true)
        << td(n[i] ? num(std::sqrt(sse[i] / n[i])) : "–") << td(st.count ? num(st.rms) : "–")
        << td(st.count ? num(st.mae) : "–") << td(std::to_string(st.count)) << td(num(sigma))
        << td(fixed.all() ? "yes" : fixed.gain ? "gain" : fixed.bias ? "bias" : "") << "</tr>";
    }
  }
  o << "</table><p class=\"note\">Markers in metres (Euclidean distance), joint and tendon "
       "sensors in their raw units. RMS before on the sampled frames, after on all frames."
       "</p></section>";
}

void markerSection(std::ostringstream& o, const RobotModel& robot, const SensorSet& sensors,
                   const SensorParameters& seed, const CalibrationResult& r) {
  o << "<section id=\"markers\"><h2>Marker positions</h2>";
  if (sensors.markers.empty()) {
    o << "<p>No markers.</p></section>";
    return;
  }
  KinematicsWorkspace ws(robot);
  forwardKinematics(robot, neutralPose(robot), &ws);
  const int M = static_cast<int>(sensors.markers.size());
  std::vector<Eigen::Vector3d> before(M), after(M);
  for (int m = 0; m < M; ++m) {
    const Eigen::Isometry3d& T = ws.link_pose[sensors.markers[m].link];
    before[m] = T * seed.marker_position[m];
    after[m] = T * r.theta.marker_position[m];
  }
  struct View {
    const char* name;
    int a, b;  // coordinates drawn right and up
  };
  const View views[3] = {{"xy", 0, 1}, {"xz", 0, 2}, {"yz", 1, 2}};
  const char* axis_name[3] = {"x", "y", "z"};
  svg::Scene scenes[3];
  svg::SceneOptions so;
  so.width = 350;
  so.height = 350;
  so.unit = "m";
  double upp = 0;
  for (int v = 0; v < 3; ++v) {
    const int a = views[v].a, b = views[v].b;
    svg::Scene& sc = scenes[v];
    for (int l = 0; l < robot.numLinks(); ++l) {
      const Eigen::Vector3d p = ws.link_pose[l].translation();
      const int parent = robot.links()[l].parent;
      if (parent >= 0) {
        const Eigen::Vector3d q = ws.link_pose[parent].translation();
        sc.segments.push_back({q[a], q[b], p[a], p[b], "#9a9a9a", 3.0, "link"});
      }
      svg::Scene::Point pt;
      pt.x = p[a], pt.y = p[b], pt.color = "#9a9a9a", pt.radius = 2.0, pt.css_class = "link";
      sc.points.push_back(pt);
    }
    for (int m = 0; m < M; ++m)
      sc.segments.push_back({before[m][a], before[m][b], after[m][a], after[m][b], "#444444", 1.0,
                             "marker-shift"});
    for (int m = 0; m < M; ++m) {
      svg::Scene::Point s;
      s.x = before[m][a], s.y = before[m][b], s.color = svg::color(0), s.filled = false;
      s.css_class = "marker-seed";
      sc.points.push_back(s);
    }
    for (int m = 0; m < M; ++m) {
      svg::Scene::Point f;
      f.x = after[m][a], f.y = after[m][b], f.color = svg::color(1);
      f.label = sensors.markers[m].name;
      f.css_class = "marker-final";
      sc.points.push_back(f);
    }
    so.x_label = axis_name[a];
    so.y_label = axis_name[b];
    upp = std::max(upp, svg::fitUnitsPerPixel(sc, so));
  }
  so.units_per_pixel = upp;
  o << "<div class=\"figures\">";
  for (int v = 0; v < 3; ++v) {
    so.title = std::string("view ") + views[v].name;
    so.x_label = axis_name[views[v].a];
    so.y_label = axis_name[views[v].b];
    o << svg::sceneView(scenes[v], so);
  }
  o << "</div><p class=\"note\">The robot at the neutral pose in its base frame (grey: each "
       "link's origin joined to its parent's). Rings: seed marker positions; dots: calibrated "
       "positions, joined by a line.</p>";
  o << "<table><tr>" << th("marker", true) << th("link", true) << th("seed (m)") << th("calibrated (m)")
    << th("moved (mm)") << th("std (mm)") << th("fixed") << "</tr>";
  auto vec = [](const Eigen::Vector3d& v) {
    return num(v.x(), "%.5f") + ", " + num(v.y(), "%.5f") + ", " + num(v.z(), "%.5f");
  };
  for (int m = 0; m < M; ++m) {
    const Eigen::Vector3d& s = seed.marker_position[m];
    const Eigen::Vector3d& f = r.theta.marker_position[m];
    const double sd = m < static_cast<int>(r.std.marker_position.size())
                          ? r.std.marker_position[m].norm()
                          : std::nan("");
    o << "<tr>" << td(sensors.markers[m].name, true) << td(sensors.markers[m].link_name, true)
      << td(vec(s)) << td(vec(f)) << td(num(1e3 * (f - s).norm(), "%.2f"))
      << td(num(1e3 * sd, "%.3g")) << td(sensors.markers[m].fixed ? "yes" : "") << "</tr>";
  }
  o << "</table></section>";
}

void unidentifiableSection(std::ostringstream& o, const CalibrationSummary& s) {
  o << "<section id=\"unidentifiable\"><h2>Unidentifiable parameters</h2>";
  if (s.unidentifiable.empty()) {
    o << "<p>None: the data determine every estimated parameter.</p></section>";
    return;
  }
  o << "<p>" << s.unidentifiable.size()
    << " direction(s) the data cannot determine; their parameters get an infinite std. Fix "
       "one parameter of each with <code>fixed</code> (e.g. <code>fixed: [bias]</code> on a joint "
       "sensor), or add markers.</p>"
       "<ul class=\"unidentifiable\">";
  for (const UnidentifiableDirection& d : s.unidentifiable) {
    o << "<li>" << escape(d.reason) << " <em>(" << undeterminedName(d.kind) << ")</em><br/>";
    for (size_t i = 0; i < d.parameters.size(); ++i)
      o << (i ? " " : "") << "<code>" << escape(d.parameters[i]) << "</code>";
    o << "</li>";
  }
  o << "</ul></section>";
}

// Joint-origin corrections (SPEC §3): each joint's estimate ± std, and which
// components the data determines and which stay on the prior.
void originSection(std::ostringstream& o, const CalibrationResult& r) {
  const SensorSet& sensors = r.sensors;
  if (sensors.joint_origins.empty()) return;
  o << "<section id=\"joint-origins\"><h2>Joint-origin corrections</h2><table><tr><th>joint</th>"
       "<th>xyz (mm)</th><th>std (mm)</th><th>rpy (deg)</th><th>std (deg)</th>"
       "<th>determined by the data</th><th>on the prior</th></tr>";
  const double deg = 180 / M_PI;
  auto vec = [](const Eigen::Vector3d& v) {
    return num(v.x(), "%.3g") + ", " + num(v.y(), "%.3g") + ", " + num(v.z(), "%.3g");
  };
  for (size_t c = 0; c < sensors.joint_origins.size(); ++c) {
    const std::string& joint = sensors.joint_origins[c].joint_name;
    std::string determined, on_prior;
    auto join = [](const std::vector<std::string>& parts) {
      std::string s;
      for (const std::string& p : parts) s += (s.empty() ? "" : " ") + p;
      return s;
    };
    for (const OriginDetermination& d : r.summary.origins)
      if (d.joint == joint) determined = join(d.determined), on_prior = join(d.on_prior);
    const OriginCorrection& v = r.theta.joint_origin[c];
    const OriginCorrection sd =
        c < r.std.joint_origin.size() ? r.std.joint_origin[c] : OriginCorrection{};
    o << "<tr>" << td(joint, true) << td(vec(1e3 * v.xyz)) << td(vec(1e3 * sd.xyz))
      << td(vec(deg * v.rpy)) << td(vec(deg * sd.rpy)) << td(determined, true)
      << td(on_prior, true) << "</tr>";
  }
  o << "</table></section>";
}

}  // namespace

std::string calibrationReportHtml(const RobotModel& robot, const SensorSet& sensors,
                                  const SensorParameters& seed, const CalibrationResult& result,
                                  const std::vector<IterationReport>& history,
                                  const ResidualSample& before, const ResidualSample& after,
                                  const ReportInputs& inputs) {
  const std::string name = robot.name().empty() ? "robot" : robot.name();
  std::ostringstream o;
  o << "<!DOCTYPE html>\n<html xmlns=\"http://www.w3.org/1999/xhtml\" lang=\"en\">\n<head>"
       "<meta charset=\"utf-8\"/><title>STAC calibration of "
    << escape(name) << "</title><style>" << kStyle << "</style></head>\n<body>\n";
  o << "<h1>STAC calibration of " << escape(name) << "</h1>\n";
  summarySection(o, robot, sensors, result, inputs);
  o << "\n";
  convergenceSection(o, history);
  o << "\n";
  residualSection(o, result.summary, before, after);
  o << "\n";
  sensorSection(o, result, before);
  o << "\n";
  markerSection(o, robot, sensors, seed, result);
  o << "\n";
  unidentifiableSection(o, result.summary);
  o << "\n";
  originSection(o, result);
  o << "\n</body>\n</html>\n";
  return o.str();
}

}  // namespace stac::cli
