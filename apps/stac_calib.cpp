// stac_calib: calibrate a robot's sensors from a synchronized log (SPEC §4).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <iostream>

#include "common/calib_report.hpp"
#include "common/cli.hpp"
#include "common/inputs.hpp"
#include "common/interrupt.hpp"
#include "common/outputs.hpp"
#include "stac/calibrate.hpp"
#include "stac/error.hpp"
#include "stac/evaluate.hpp"
#include "stac/file_io.hpp"
#include "stac/log.hpp"
#include "stac/theta_space.hpp"
#include "stac/residuals.hpp"
#include "stac/robot_model.hpp"
#include "stac/sensors_file.hpp"
#include "stac/simulate.hpp"
#include "stac/urdf_patch.hpp"

namespace {

using namespace stac;
using cli::checkOutputs;
using cli::writeOutput;

const std::vector<cli::Option> kOptions = {
    {"urdf", "FILE", "robot description (URDF)", true},
    {"log", "FILE", "synchronized readings (CSV, SPEC §2)", true},
    {"sensors", "FILE", "sensors file with the seed (YAML); inferred from the log header if absent"},
    {"output", "FILE", "calibration to write (default: calibration.yaml)"},
    {"joint-angles", "FILE", "also write the estimated joint angles per frame (CSV)"},
    {"urdf-out", "FILE", "also write the URDF with its marker links moved to the calibrated positions"},
    {"report", "FILE", "also write an HTML report (convergence, residuals, marker positions)"},
    {"method", "stac|joint|ekf|classical",
     "alternating STAC (default), one monolithic problem, or a baseline: extended Kalman "
     "filter over [theta; q] (paper IV-A), classical regression with q read off the joint "
     "sensors (paper IV-B; needs a joint sensor on every joint)"},
    {"q-phase", "lm-iter|lm-batch|bfgs",
     "per-frame solver of the q-phase (default lm-iter; --method stac only)"},
    {"ekf-initial-q", "FILE",
     "EKF: q of the first frame from the first row of a joint-angles CSV (as written by "
     "--joint-angles); default: frame 0 solved with the seed"},
    {"ekf-q-speed", "V",
     "EKF: random-walk std of q per frame = V * joint range * frame interval (default 10)"},
    {"ekf-iterations", "N",
     "EKF: measurement updates per frame; 1 = the paper's EKF (default), more = iterated EKF"},
    {"ekf-theta-std", "K",
     "EKF: multiplies the seed std of theta (0.2 rad, 0.1 m frame, 0.05 m markers, gain 30%, "
     "bias 0.3 rad / 0.02 m times the gain; default 1)"},
    {"max-iterations", "N", "outer iterations at most (default 200)"},
    {"tolerance", "TOL", "stop when the relative cost decrease is below TOL (default 1e-7)"},
    {"threads", "N", "worker threads; 0 = all cores (default)"},
    {"loss", "none|huber|cauchy", "robust loss per reading (default none)"},
    {"loss-scale", "S", "robust loss scale in standard deviations (default 3)"},
    {"no-adapt-variance", "", "keep every sigma at its seed value"},
    {"mocap-units", "m|mm", "unit of the marker columns (default m)"},
    {"joint-origins", "all|J1,J2,...",
     "also estimate corrections to the <origin> of these joints (all: every movable joint "
     "that is not a mimic follower), unless the sensors file lists them already"},
    {"origin-prior", "XYZ,RPY",
     "prior std of the joint-origin corrections, metres and radians (default 0.005,0.01)"},
    {"holdout", "F", "keep the last fraction F of the frames (0 < F < 1) out of the fit and print "
                     "the cross-sensor prediction table on them"},
    cli::ignoreColumnsOption(),
    {"quiet", "", "no progress lines on stderr"},
};

const char* kSynopsis =
    "stac_calib --urdf robot.urdf --log data.csv [--sensors seed.yaml] [options]\n\n"
    "Simultaneous Tracking And Calibration: estimates sensor gains and biases,\n"
    "marker positions and the mocap frame together with the joint angles of\n"
    "every frame, and writes the calibration (same schema as the sensors file).";


// What a user must not miss even with --quiet: the reasons the result
// failed its own checks (summary.verdict). Returns the exit code: 4 if any.
int reportVerdict(const CalibrationSummary& s, const std::string& output) {
  if (!s.suspect()) return 0;
  for (const std::string& reason : s.verdict)
    std::cerr << "stac_calib: warning: " << reason << "\n";
  std::cerr << "stac_calib: the calibration failed its own checks; written to " << output
            << " with the reasons in summary.verdict (exit 4)\n";
  return 4;
}

// The calibration options from the command line (every method's own
// options refused with another method).
CalibrationOptions parseOptions(const cli::Args& args) {
  CalibrationOptions options;
  const std::string method =
      args.getChoice("method", {"stac", "joint", "ekf", "classical"}, "stac");
  options.method = method == "joint"       ? Method::kMonolithic
                   : method == "ekf"       ? Method::kEkf
                   : method == "classical" ? Method::kClassical
                                           : Method::kStac;
  for (const char* ekf_option :
       {"ekf-initial-q", "ekf-q-speed", "ekf-theta-std", "ekf-iterations"})
    if (args.has(ekf_option) && options.method != Method::kEkf)
      throw cli::UsageError(std::string("--") + ekf_option + " needs --method ekf");
  options.ekf.q_speed = args.getPositive("ekf-q-speed", options.ekf.q_speed);
  options.ekf.theta_std_scale = args.getPositive("ekf-theta-std", options.ekf.theta_std_scale);
  options.ekf.iterations = args.getIntAtLeast("ekf-iterations", options.ekf.iterations, 1);
  const std::string qp = args.getChoice("q-phase", {"lm-iter", "lm-batch", "bfgs"}, "lm-iter");
  options.stac.q_phase = qp == "lm-batch" ? QPhaseMethod::kLmBatch
                    : qp == "bfgs"   ? QPhaseMethod::kBfgs
                                     : QPhaseMethod::kLmIter;
  options.max_iterations = args.getIntAtLeast("max-iterations", options.max_iterations, 1);
  options.tolerance = args.getNonNegative("tolerance", options.tolerance);
  options.threads = args.getIntAtLeast("threads", 0, 0, "0 = all cores");
  const std::string loss = args.getChoice("loss", {"none", "huber", "cauchy"}, "none");
  options.loss = loss == "huber" ? LossKind::kHuber
                 : loss == "cauchy" ? LossKind::kCauchy
                                    : LossKind::kNone;
  options.loss_scale = args.getPositive("loss-scale", options.loss_scale);
  options.adapt_variance = !args.has("no-adapt-variance");
  // Every value was checked above with its flag; this catches a check
  // the library adds later.
  std::string error;
  if (!options.isValid(&error)) throw cli::UsageError(error);
  return options;
}

// Progress lines on stderr (not with --quiet); every report kept for the
// HTML report's convergence plot.
std::function<void(const IterationReport&)> progressPrinter(bool quiet,
                                                            std::vector<IterationReport>* history) {
  return [quiet, history](const IterationReport& r) {
    // The verdict's check run (stage "check") is not the calibration's
    // convergence: printed, not plotted.
    if (r.stage != "check") history->push_back(r);
    if (quiet) return;
    char buf[256];
    int n = std::snprintf(buf, sizeof buf, "%-5s %4d  cost %-12.6g", r.stage.c_str(),
                          r.iteration, r.cost);
    for (int g = 0; g < kNumSensorGroups; ++g)
      if (r.present[g])
        n += std::snprintf(buf + n, sizeof buf - n, "  rms %s %-10.4g",
                           groupName(static_cast<SensorGroup>(g)), r.rms[g]);
    std::snprintf(buf + n, sizeof buf - n, "  %.2f s", r.elapsed);
    std::cerr << buf << std::endl;
  };
}

// What --urdf-out did: the marker links moved, and the markers it could not
// place.
void printUrdfPatch(const UrdfPatch& urdf_patch, const SensorSet& sensors,
                    const std::string& urdf_out) {
  std::cout << "calibrated URDF written to " << urdf_out << ": " << urdf_patch.placed.size()
            << " marker link(s) on the calibrated markers\n";
  // The calibration's positions stay right for markers on another link;
  // on their own moved link they are now at its origin.
  std::string at_origin;
  for (const PlacedMarker& p : urdf_patch.placed)
    for (const MarkerConfig& m : sensors.markers)
      if (m.name == p.marker && m.link_name == p.link) at_origin += " " + p.marker;
  if (!at_origin.empty())
    std::cout << "with that URDF these markers are at [0, 0, 0] of their link:" << at_origin << "\n";
  if (!urdf_patch.unplaced.empty()) {
    std::cout << "markers not written to the URDF (no marker link of their own):\n";
    for (const UnplacedMarker& u : urdf_patch.unplaced)
      std::cout << "  " << u.marker << ": " << u.reason << "\n";
  }
}

// --holdout: the cross-sensor prediction table on the held-out tail.
void printHoldout(const RobotModel& robot, const CalibrationResult& result,
                  const Observations& all, int test_frames, int threads) {
  const Observations test = sliceFrames(all, all.num_frames - test_frames, all.num_frames);
  EvaluationOptions eval;
  eval.threads = threads;
  const std::vector<CrossSensorRow> rows =
      crossSensorTable(robot, result.sensors, result.theta, test, eval);
  std::cout << "\nheld out: the last " << test_frames << " of " << all.num_frames
            << " frames (not used in the fit); cross-sensor prediction, mean absolute error\n"
            << "(markers: Euclidean distance; parentheses: the group also estimated q)\n"
            << crossSensorTableText(rows);
}

// The HTML report: residuals on the frames calibrate() used for "before"
// (the seed θ with q fitted to it), and at the final θ and q (refitted if
// the method gave none).
std::string reportHtml(const RobotModel& robot, const SensorsFile& sf,
                       const CalibrationResult& result, const RowMatrix& q,
                       const Observations& obs, const CalibrationOptions& options,
                       const std::vector<IterationReport>& history,
                       const cli::ReportInputs& inputs) {
  ResidualSampleOptions ro;
  ro.threads = options.threads;
  ro.loss = options.loss;
  ro.loss_scale = options.loss_scale;
  const bool have_q = q.rows() == obs.num_frames && q.cols() == robot.dof();
  return cli::calibrationReportHtml(
      robot, sf.sensors, sf.theta, result, history,
      sampleResiduals(robot, sf.sensors, sf.theta, obs, nullptr, ro),
      sampleResiduals(robot, result.sensors, result.theta, obs, have_q ? &q : nullptr, ro),
      inputs);
}

// How many of the log's frames the fraction `holdout` (--holdout; 0
// without it) keeps out of the fit. A time-block split: neighbouring frames
// are correlated, so the held-out frames are the end of the log, never a
// random sample.
int holdoutFrames(double holdout, const cli::Args& args, int frames,
                  const std::string& log_path) {
  const int test_frames = static_cast<int>(std::lround(holdout * frames));
  if (holdout > 0.0 && (test_frames < 1 || test_frames > frames - 2))
    throw InputError(log_path, args.typed("holdout") + " of " + std::to_string(frames) +
                                   " frames leaves no frame to fit or none to test");
  return test_frames;
}

// --origin-prior XYZ,RPY: two positive finite numbers.
OriginPrior parseOriginPrior(const cli::Args& args) {
  const std::vector<std::string> parts = args.getList("origin-prior", "number");
  OriginPrior prior;
  double* out[2] = {&prior.xyz, &prior.rpy};
  bool ok = parts.size() == 2;
  for (size_t i = 0; ok && i < 2; ++i) {
    const std::optional<double> v = cli::parseFiniteNumber(parts[i]);
    ok = v && *v > 0;
    if (ok) *out[i] = *v;
  }
  if (!ok)
    throw cli::UsageError(args.typed("origin-prior") +
                          ": expected two positive numbers XYZ,RPY (metres, radians)");
  return prior;
}

// --joint-origins and --origin-prior (SPEC §3, §4) on the seed.
void applyOriginOptions(const cli::Args& args, const RobotModel& robot, SensorsFile* sf) {
  const size_t listed = sf->sensors.joint_origins.size();
  if (args.has("joint-origins")) {
    const std::vector<std::string> names = args.getList("joint-origins", "joint name");
    try {
      addJointOrigins(robot, names, sf);
    } catch (const std::invalid_argument& e) {
      throw cli::UsageError(args.typed("joint-origins") + ": " + e.what());
    }
  }
  OriginPrior& prior = sf->sensors.origin_prior;
  if (args.has("origin-prior")) {
    if (sf->sensors.joint_origins.empty())
      throw cli::UsageError(args.typed("origin-prior") +
                            ": no joint origins to estimate (give --joint-origins or "
                            "joint_origins in the sensors file)");
    prior = parseOriginPrior(args);
  } else if (sf->sensors.joint_origins.size() > listed && !prior.any()) {
    prior = {kDefaultOriginPriorXyz, kDefaultOriginPriorRpy};
  }
}

int run(const cli::Args& args) {
  const std::string urdf = args.get("urdf"), log_path = args.get("log");
  const std::string sensors_path = args.get("sensors");
  const std::string output = args.get("output", "calibration.yaml");
  const std::string q_path = args.get("joint-angles");
  const std::string urdf_out = args.get("urdf-out"), report_path = args.get("report");

  CalibrationOptions options = parseOptions(args);
  const std::string ekf_q_path = args.get("ekf-initial-q");
  const double mocap_scale = args.getChoice("mocap-units", {"m", "mm"}, "m") == "mm" ? 1e-3 : 1.0;
  const double holdout = args.getFraction("holdout", 0.0, /*open=*/true);

  std::vector<std::string> inputs = {urdf, log_path};
  if (!sensors_path.empty()) inputs.push_back(sensors_path);
  if (!ekf_q_path.empty()) inputs.push_back(ekf_q_path);
  std::vector<std::pair<std::string, std::string>> outputs = {{"--output", output}};
  if (!q_path.empty()) outputs.emplace_back("--joint-angles", q_path);
  if (args.has("urdf-out")) outputs.emplace_back("--urdf-out", urdf_out);
  if (args.has("report")) outputs.emplace_back("--report", report_path);
  checkOutputs(inputs, outputs);

  const RobotModel robot = RobotModel::fromFile(urdf);
  const Log log = readLog(log_path);
  requireDataRows(log);  // before inference, which would only complain about the header
  SensorsFile sf = cli::sensorsForLog(args, sensors_path, robot, log);
  applyOriginOptions(args, robot, &sf);
  const Observations all = cli::bindSensors(log, sf, sensors_path, mocap_scale);
  if (!ekf_q_path.empty()) options.ekf.initial_q = firstJointAngles(readLog(ekf_q_path), robot);
  requireReadings(all, sf.sensors, log_path, ReadingCheck::kEverySensor);
  const int test_frames = holdoutFrames(holdout, args, all.num_frames, log_path);
  const Observations obs =
      test_frames > 0 ? sliceFrames(all, 0, all.num_frames - test_frames) : all;
  // The frames left to fit must see every sensor too.
  if (test_frames > 0) requireReadings(obs, sf.sensors, log_path, ReadingCheck::kEverySensor);

  const bool quiet = args.has("quiet");
  std::vector<IterationReport> history;  // for the report's convergence plot
  if (!quiet || !report_path.empty()) options.progress = progressPrinter(quiet, &history);
  // From here a Ctrl-C is polled (between iterations, stac::Cancelled) and
  // the outputs are written all or none.
  const cli::DeferInterrupts polled;
  options.should_stop = cli::interruptRequested;
  RowMatrix q;
  const CalibrationResult result =
      calibrateFromSource(sensors_path.empty() ? log_path : sensors_path, robot, sf.sensors,
                          sf.theta, obs, options, &q);

  // All outputs are complete in memory before the first is written.
  const std::string yaml = sensorsToYaml(result.sensors, result.theta, &result);
  Log q_log;
  if (!q_path.empty()) {
    q_log = jointAnglesLog(robot, q, obs.time);
    if (!obs.time_name.empty()) q_log.time_name = obs.time_name;
  }
  UrdfPatch urdf_patch;
  if (!urdf_out.empty())
    urdf_patch = patchUrdfMarkers(robot, result.sensors, result.theta);
  const std::string report =
      report_path.empty() ? std::string()
                          : reportHtml(robot, sf, result, q, obs, options, history,
                                       {urdf, log_path, sensors_path});
  cli::throwIfInterrupted();  // the last point where nothing is written
  writeOutput(output, yaml);
  if (!q_path.empty()) cli::writeLogOutput(q_path, q_log);
  if (!urdf_out.empty()) writeOutput(urdf_out, urdf_patch.urdf);
  if (!report_path.empty()) writeOutput(report_path, report);
  std::cout << briefReport(robot, sf.theta, result) << "\ncalibration written to " << output
            << "\n";
  const int verdict_exit = reportVerdict(result.summary, output);
  if (!urdf_out.empty()) printUrdfPatch(urdf_patch, sf.sensors, urdf_out);
  if (!report_path.empty()) std::cout << "report written to " << report_path << "\n";
  if (test_frames > 0)
    printHoldout(robot, result, all, test_frames, options.threads);
  return verdict_exit;
}

}  // namespace

int main(int argc, char** argv) {
  return stac::cli::runApp(argc, argv, "stac_calib", kSynopsis, kOptions, run);
}
