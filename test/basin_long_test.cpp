// The wide basin (issues 4, 13): over many random truths per robot — a
// random mocap rotation, gains of both signs, biases up to ±1
// rad-equivalent, markers a few centimetres from their link origins — STAC
// started from the paper's seeding (gains 1, biases 0, markers at the link
// origin, mocap frame identity) must reach the truth (every parameter within
// 4 reported std; one reported undetermined has none) in >= 95% of the
// cases, every miss must carry verdict suspect (exit 4: no silent wrong
// answer), and no result that reached it may (no false alarm). Robots:
// the bundled ones and the real public ones of STAC_ROBOTS_DIR with at most
// 12 joints; variants: plain, 5% gross outliers + 30% marker dropout with a
// Huber loss, partial off-centre swings, 80 static postures (no motion in
// time, as a real recording of held postures), ur5 with continuous joints, TALOS
// from 2000 frames. Label "long": outside the default run; prints a table
// row per robot and variant. STAC_BASIN_TRUTHS=N takes N truths instead of
// 20 (a quicker look), STAC_BASIN_ONLY=robot/variant one row (or a comma
// list of rows and whole robots: "go1,panda/partial"),
// STAC_BASIN_THREADS=n calibrates on n threads (2);
// STAC_BASIN_PICK=k truth k alone; STAC_BASIN_DIAG=1 calibrates each miss
// again from its truth and prints both fits, per sensor (a wrong minimum
// fits worse; a miss that fits as well is a std too small);
// STAC_BASIN_LOSS=cauchy runs the outlier rows under Cauchy's loss instead
// of Huber's; STAC_BASIN_TRACE=1 prints every iteration's cost and RMS
// and the seconds since the run's start;
// STAC_BASIN_MAX_ITERATIONS=n raises (or lowers) the iteration limit, as
// a user told "not converged" would;
// STAC_BASIN_NO_SCREEN=1 fits the outlier rows without setting spikes in
// time aside first (spike_screen.hpp). Other robots without a rebuild:
// STAC_ROBOTS_DIR=dir (its *.urdf instead of the configured set),
// STAC_BASIN_MAX_DOF=n (robots up to n joints instead of 12),
// STAC_BASIN_LAYOUT=n (their sensors laid out at random from seed n: some
// links without a marker, some with two, path tendons; see layoutSeed).
// STAC_BASIN_NOISE_SEED=n draws the motion and noise anew for the same
// truths; STAC_BASIN_Z=text prints the z of every parameter whose name
// holds it, reached or not (is a std honest?); STAC_BASIN_TICKS=K logs
// every joint sensor in encoder ticks (K a radian, about 2048).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <random>

#include "stac/calibrate.hpp"
#include "stac/theta_space.hpp"
#include "stac/sensors_file.hpp"
#include "stac/simulate.hpp"
#include "support/arm_files.hpp"
#include "support/basin_draws.hpp"
#include "support/external_sensors.hpp"
#include "support/test_util.hpp"

namespace stac {
namespace {

using test::closeToTruth;
using test::withinReportedStd;
using test::externalRobot;
using test::paperSeed;
using test::randomTruth;
using test::Robot;
using test::simulateVariant;
using test::Variant;
using test::variantName;

// STAC_BASIN_LAYOUT=n: the real robots' sensors laid out at random from
// seed n, as an independent generator lays them (external_sensors.hpp),
// instead of as sensor inference names them.
unsigned layoutSeed() {
  const char* env = std::getenv("STAC_BASIN_LAYOUT");
  return env ? static_cast<unsigned>(std::strtoul(env, nullptr, 10)) : 0;
}

std::vector<Robot> robots(int max_dof) {
  std::vector<Robot> out;
  {
    RobotModel m = RobotModel::fromString(test::kArmUrdf, "arm4");
    SensorsFile t = parseSensorsYaml(test::kArmTruth, "arm4_truth", m);
    out.push_back({"arm4", std::move(m), std::move(t), 300});
  }
  for (const char* name : {"gimbal2", "hand24", "humanoid38"}) {
    const std::string urdf = test::dataPath(std::string(name) + ".urdf");
    const std::string truth = test::dataPath(std::string(name) + "_seed.yaml");
    if (test::readFile(urdf).empty() || test::readFile(truth).empty()) continue;
    out.push_back(test::bundledRobot(name, 500));
  }
  // Real public robots (STAC_ROBOTS_DIR) with the sensors a user would log
  // without a sensors file, the gauges removed by CAD-known markers.
  for (const std::string& urdf : test::externalUrdfs()) {
    RobotModel m = RobotModel::fromFile(urdf);
    if (m.dof() > max_dof) continue;
    out.push_back(externalRobot(std::move(m), 600, layoutSeed()));
  }
  return out;
}

// The outlier rows' loss: Huber, as the issue asks, or STAC_BASIN_LOSS=cauchy
// to measure the redescending loss on the same truths and logs.
LossKind outlierLoss() {
  const char* env = std::getenv("STAC_BASIN_LOSS");
  return env && std::string(env) == "cauchy" ? LossKind::kCauchy : LossKind::kHuber;
}

struct Tally {
  int truths = 0, reached = 0, reported = 0, flagged_misses = 0, silent_misses = 0,
      false_alarms = 0, noise_draws = 0;
};

// STAC_BASIN_ONLY: a comma list of rows ("arm4/outliers") and robots ("go1").
bool selected(const std::string& robot, const std::string& variant) {
  const char* only = std::getenv("STAC_BASIN_ONLY");
  if (!only) return true;
  const std::string list = std::string(",") + only + ",";
  return list.find("," + robot + ",") != std::string::npos ||
         list.find("," + robot + "/" + variant + ",") != std::string::npos;
}

// STAC_BASIN_TICKS=K: every joint sensor logs encoder ticks, K of them a
// radian (a prismatic joint's per its stroke) about an offset of 2048, its
// σ K times: the same problems in another unit, which must give the same
// answers (0: radians, the default).
double ticksPerRadian() {
  const char* env = std::getenv("STAC_BASIN_TICKS");
  return env ? std::atof(env) : 0.0;
}

Robot inTicks(Robot robot, double ticks) {
  if (ticks > 0)
    for (JointSensorConfig& js : robot.truth.sensors.joint_sensors) js.sigma *= ticks;
  return robot;
}

void truthInTicks(double ticks, SensorParameters* truth) {
  if (ticks > 0)
    for (GainBias& gb : truth->joint_sensor) gb = {ticks * gb.gain, ticks * gb.bias + 2048};
}

// Whether `r` is where the calibration started from the truth itself (rt)
// ends: every parameter within half of r's reported std of that fit's.
bool fitOfTheTruth(const Robot& robot, const CalibrationResult& rt, const CalibrationResult& r) {
  std::string why;
  return withinReportedStd(robot.truth.sensors, rt.theta, r, &why, nullptr, 0.5);
}

// Whether a result that reports some parameters undetermined found another
// minimum than the truth's: the calibration started from the truth itself
// (rt) determines every parameter and fits some sensor group's readings better
// by more than 5% in RMS. Its undetermined parameters pass the 4-std test
// vacuously, yet it did not reach the truth (hand24 on partial swings,
// fresh truth 15: the thumb's trade-off reported, the markers at 1.20x the
// RMS of the truth's own fit, flagged, and counted as a false alarm).
bool anotherMinimum(const CalibrationResult& rt, const CalibrationResult& r) {
  if (!rt.summary.unidentifiable.empty()) return false;
  for (int g = 0; g < kNumSensorGroups; ++g)
    if (r.summary.group_present[g] && r.summary.after_rms[g] > 1.05 * rt.summary.after_rms[g])
      return true;
  return false;
}

// One robot, one variant: kTruths random truths from the paper's seeding.
// Counts the truths reached, and the misses the verdict flags (exit 4) or
// not (a silent wrong answer).
Tally runVariant(const Robot& robot_in, Variant v, int truths, int frames) {
  const double ticks = ticksPerRadian();
  const Robot robot = inTicks(robot_in, ticks);
  Tally tally;
  if (!selected(robot.name, variantName(v))) return tally;
  const MeasurementModel model(robot.model, robot.truth.sensors);
  // STAC_BASIN_TRUTH_SEED: other truths than the default draw's.
  const char* truth_seed = std::getenv("STAC_BASIN_TRUTH_SEED");
  std::mt19937_64 rng(truth_seed ? std::strtoull(truth_seed, nullptr, 10) : 2024);
  double z2 = 0, zn = 0;  // the reached truths' squared errors in std, and their count
  const char* pick = std::getenv("STAC_BASIN_PICK");  // one truth, by its index
  // Another draw of the motion and noise for the same truths (is a std honest?)
  const char* noise_env = std::getenv("STAC_BASIN_NOISE_SEED");
  const int noise_draw = noise_env ? std::atoi(noise_env) : 0;
  for (int k = 0; k < truths; ++k) {
    SensorParameters truth = randomTruth(robot.model, robot.truth.sensors, robot.truth.theta, rng);
    truthInTicks(ticks, &truth);
    if (pick && std::atoi(pick) != k) continue;
    const Simulation sim =
        simulateVariant(robot, model, truth, v, frames, test::basinLogSeed(k, noise_draw));
    const Observations obs = bindLog(sim.data.log, robot.truth.sensors, "truth", 1.0);
    CalibrationOptions o;
    o.threads = 2;
    if (const char* th = std::getenv("STAC_BASIN_THREADS")) o.threads = std::atoi(th);
    if (v == Variant::kOutliers) o.loss = outlierLoss();
    if (std::getenv("STAC_BASIN_NO_SCREEN")) o.screen_spikes = false;  // to measure the screen
    if (const char* it = std::getenv("STAC_BASIN_MAX_ITERATIONS")) o.max_iterations = std::atoi(it);
    if (std::getenv("STAC_BASIN_TRACE"))  // each iteration's cost and RMS, to stderr
      o.progress = [start = std::chrono::steady_clock::now()](const IterationReport& r) {
        const std::chrono::duration<double> t = std::chrono::steady_clock::now() - start;
        std::fprintf(stderr, "    %-5s %3d cost %.9g rms %.4g %.4g %.4g  %.1f s\n",
                     r.stage.c_str(), r.iteration, r.cost, r.rms[0], r.rms[1], r.rms[2],
                     t.count());
      };
    RowMatrix q_est;
    const CalibrationResult r = calibrate(robot.model, robot.truth.sensors,
                                          paperSeed(robot.truth.sensors, truth), obs, o, &q_est);
    std::string why;
    std::vector<double> z;  // every parameter's error in its reported std
    // Reached as the issue counts it: every parameter within 4 reported
    // std of the truth. A parameter the result reports undetermined (a
    // mirror configuration, a bias known only modulo a turn, a null
    // direction) has no std: it tells the user it does not know, and
    // passes; such results are counted apart ("reported").
    bool reached = withinReportedStd(robot.truth.sensors, truth, r, &why, &z);
    std::string exact_why;
    const bool exact = reached && closeToTruth(robot.truth.sensors, truth, r, &exact_why);
    // The calibration started from the truth itself, made once where asked.
    std::optional<CalibrationResult> from_truth;
    const auto fromTruth = [&]() -> const CalibrationResult& {
      if (!from_truth) from_truth = calibrate(robot.model, robot.truth.sensors, truth, obs, o);
      return *from_truth;
    };
    const bool another = reached && !exact && anotherMinimum(fromTruth(), r);
    if (another) {
      reached = false;
      why = "reported undetermined (" + exact_why +
            "), where the truth's own fit determines every parameter and fits better";
    }
    if (reached) {
      for (double e : z) z2 += e * e;
      zn += static_cast<double>(z.size());
    }
    const bool suspect = r.summary.suspect();  // verdict suspect, exit 4
    // A miss with verdict ok is a wrong answer unless it is the answer the
    // data give: the calibration started from the truth itself ends at the
    // same parameters (within half a std), and the truth lies in the
    // tail of the std (a 4.1-std gain on humanoid38's plain truth 9, as
    // likely as one parameter in some 15,000 draws; the truth's own fit
    // lands there). Counted apart, as a noise draw. Not another minimum
    // (above): its undetermined parameters are within any std of the
    // truth's fit vacuously (hand24 partial, fresh seed 13 truth 10: the
    // middle finger's trade-off reported, the markers at 1.20x the truth's
    // fit, verdict ok, had counted as a noise draw).
    const bool draw = !reached && !suspect && !another && fitOfTheTruth(robot, fromTruth(), r);
    ++tally.truths;
    tally.reached += reached;
    tally.reported += reached && !exact;
    tally.false_alarms += reached && suspect;
    tally.flagged_misses += !reached && suspect;
    tally.noise_draws += draw;
    tally.silent_misses += !reached && !suspect && !draw;
    if (!reached)
      std::printf("  %s/%s truth %d: missed (%s)%s\n", robot.name.c_str(), variantName(v), k,
                  why.c_str(),
                  suspect ? (", verdict suspect: " + r.summary.verdict[0]).c_str()
                  : draw  ? ", verdict ok: a noise draw (the truth's own fit ends there too)"
                          : ", SILENT: verdict ok");
    if (reached && !exact)
      std::printf("  %s/%s truth %d: reached, %s reported undetermined (%s)\n",
                  robot.name.c_str(), variantName(v), k, r.summary.unidentifiable.empty() ? "?" :
                  r.summary.unidentifiable[0].parameters[0].c_str(), exact_why.c_str());
    if (std::getenv("STAC_BASIN_DIAG") && (suspect || !reached)) {
      std::printf("    sigma/seed");
      for (int g = 0; g < kNumSensorGroups; ++g)  // "-": the robot has no such sensor
        if (r.summary.group_present[g])
          std::printf(" %.3g", r.summary.group_sigma[g] / r.summary.seed_group_sigma[g]);
        else
          std::printf(" -");
      std::printf(", iterations %d\n", r.summary.iterations);
    }
    if ((!reached || suspect) && std::getenv("STAC_BASIN_DIAG")) {
      // Is the miss a worse minimum, or as good a fit as the truth's own?
      const CalibrationResult& rt = fromTruth();
      std::printf("    diag: cost %.6g (from truth %.6g), rms", r.summary.final_cost,
                  rt.summary.final_cost);
      for (int g = 0; g < kNumSensorGroups; ++g)
        std::printf(" %.4g/%.4g", r.summary.after_rms[g], rt.summary.after_rms[g]);
      std::printf(", iterations %d/%d, from truth: %s\n", r.summary.iterations, rt.summary.iterations,
                  rt.summary.unidentifiable.empty() ? "identifiable" : rt.summary.unidentifiable[0].reason.c_str());
      for (const auto& d : r.summary.unidentifiable) {
        std::printf("    undetermined: %s:", d.reason.c_str());
        for (const auto& p : d.parameters) std::printf(" %s", p.c_str());
        std::printf("\n");
      }
      // Per joint: the estimate's angles against the truth's (mean offset,
      // and the slope of a fit estimate = a + slope truth: -1 a mirror).
      for (int j = 0; j < robot.model.dof(); ++j) {
        const Eigen::ArrayXd e = q_est.col(j).array(), t = sim.q.col(j).array();
        const double te = t.mean(), ee = e.mean();
        const double var = (t - te).square().sum();
        const double slope = var > 0 ? ((t - te) * (e - ee)).sum() / var : 0.0;
        std::printf("    q%-3d mean %+.3f offset %+.4f slope %+.3f range %.3f  est %.3f..%.3f\n", j, te,
                    ee - te, slope, t.maxCoeff() - t.minCoeff(), e.minCoeff(), e.maxCoeff());
      }
      const SensorSet& ss = robot.truth.sensors;
      for (size_t m = 0; m < ss.markers.size(); ++m)
        std::printf("    %s on %s %.3g/%.3g\n", ss.markers[m].name.c_str(), ss.markers[m].link_name.c_str(), r.marker_residual[m].rms / ss.markers[m].sigma, rt.marker_residual[m].rms / ss.markers[m].sigma);
      for (size_t m = 0; m < ss.joint_sensors.size(); ++m)
        std::printf("    %s %.3g/%.3g  gain %.4g/%.4g bias %.4g/%.4g\n", ss.joint_sensors[m].name.c_str(), r.joint_residual[m].rms / ss.joint_sensors[m].sigma, rt.joint_residual[m].rms / ss.joint_sensors[m].sigma, r.theta.joint_sensor[m].gain, truth.joint_sensor[m].gain, r.theta.joint_sensor[m].bias, truth.joint_sensor[m].bias);
      for (size_t m = 0; m < ss.tendon_sensors.size(); ++m)
        std::printf("    %s %.3g/%.3g\n", ss.tendon_sensors[m].name.c_str(), r.tendon_residual[m].rms / ss.tendon_sensors[m].sigma, rt.tendon_residual[m].rms / ss.tendon_sensors[m].sigma);
    }
    if (reached && suspect) {
      std::printf("  %s/%s truth %d: reached but flagged (%s)\n", robot.name.c_str(),
                  variantName(v), k, r.summary.verdict[0].c_str());
      if (std::getenv("STAC_BASIN_DIAG")) {  // how near the 4 std it came
        std::vector<double> a;
        for (double e : z) a.push_back(std::abs(e));
        std::sort(a.rbegin(), a.rend());
        std::printf("    largest errors (std):");
        for (size_t i = 0; i < a.size() && i < 5; ++i) std::printf(" %.2f", a[i]);
        std::printf(" of %zu\n", a.size());
      }
    }
  }
  // An honest std gives errors of RMS 1 std over the reached truths.
  std::printf("basin %-12s %-9s reached %2d/%d (%d reported undetermined)  misses flagged %d, "
              "noise draws %d, silent %d  false alarms %d  (error RMS %.2f std)\n",
              robot.name.c_str(), variantName(v), tally.reached, tally.truths, tally.reported,
              tally.flagged_misses, tally.noise_draws, tally.silent_misses, tally.false_alarms,
              zn > 0 ? std::sqrt(z2 / zn) : 0.0);
  std::fflush(stdout);
  return tally;
}

int truthsPerVariant() {
  const char* env = std::getenv("STAC_BASIN_TRUTHS");  // a quicker look
  return env ? std::max(1, std::atoi(env)) : 20;
}

void expectBasin(const Robot& robot, const Tally& t) {
  EXPECT_GE(t.reached, t.truths - t.truths / 20) << robot.name;  // >= 95%
  EXPECT_EQ(t.silent_misses, 0) << robot.name;  // no silent wrong answer
  EXPECT_EQ(t.false_alarms, 0) << robot.name;   // no right answer called suspect
}

TEST(Basin, PaperSeedingConvergesFromRandomTruths) {
  const char* max_dof = std::getenv("STAC_BASIN_MAX_DOF");  // larger robots of another set
  for (Robot& robot : robots(max_dof ? std::atoi(max_dof) : 12)) {
    for (Variant v : {Variant::kPlain, Variant::kOutliers, Variant::kPartialSwings,
                      Variant::kPostures}) {
      const Tally t = runVariant(robot, v, truthsPerVariant(), robot.frames);
      expectBasin(robot, t);
    }
  }
}

// A copy of ur5 with every joint continuous (no limits): the initialisation
// cannot assume where in its range, or over how much of it, a joint moves.
TEST(Basin, ContinuousJoints) {
  for (const std::string& urdf : test::externalUrdfs()) {
    if (urdf.find("ur5") == std::string::npos) continue;
    std::string text = test::readFile(urdf);
    for (size_t at = text.find("type=\"revolute\""); at != std::string::npos;
         at = text.find("type=\"revolute\"", at))
      text.replace(at, 15, "type=\"continuous\"");
    Robot robot = externalRobot(RobotModel::fromString(text, "ur5_continuous"), 600, layoutSeed());
    robot.name = "ur5_continuous";
    expectBasin(robot, runVariant(robot, Variant::kPlain, truthsPerVariant(), robot.frames));
  }
}

// TALOS at 2000 frames: a whole humanoid from a short log.
TEST(Basin, TalosShortLog) {
  for (const std::string& urdf : test::externalUrdfs()) {
    if (urdf.find("talos") == std::string::npos) continue;
    Robot robot = externalRobot(RobotModel::fromFile(urdf), 2000, layoutSeed());
    expectBasin(robot, runVariant(robot, Variant::kPlain, truthsPerVariant(), robot.frames));
  }
}

}  // namespace
}  // namespace stac
