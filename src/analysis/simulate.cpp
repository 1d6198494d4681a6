#include "stac/simulate.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "stac/kinematics.hpp"

namespace stac {

namespace {

constexpr double kPi = 3.14159265358979323846;

// Portable draws from a std::mt19937_64 (the engine itself is fully specified
// by the standard; the distributions are not).
class Draw {
 public:
  explicit Draw(std::mt19937_64& rng) : rng_(rng) {}
  // [0, 1), 53 random bits.
  double uniform() { return static_cast<double>(rng_() >> 11) * 0x1.0p-53; }
  // (0, 1].
  double uniformPositive() {
    return static_cast<double>((rng_() >> 11) + 1) * 0x1.0p-53;
  }
  // Standard normal by Box–Muller (cosine branch only: exactly two engine
  // draws per call).
  double normal() {
    const double r = std::sqrt(-2.0 * std::log(uniformPositive()));
    return r * std::cos(2.0 * kPi * uniform());
  }

 private:
  std::mt19937_64& rng_;
};

// Motion: s(t) = Σ a_k sin(2π f_k t + φ_k), squashed by tanh(g s)/tanh(g).
// The bands are disjoint so that no two components can cancel for long: the
// dominant one completes >= 1.2 cycles in 3 s, so every joint sweeps >= 60%
// of its range in 300 frames at 100 Hz (worst of 200000 random draws: 61%;
// with overlapping bands it could fall below 10%).
constexpr int kComponents = 3;
constexpr double kAmplitude[kComponents] = {0.5, 0.3, 0.2};
constexpr double kFreqLow[kComponents] = {0.4, 0.9, 0.15};  // Hz
constexpr double kFreqHigh[kComponents] = {0.7, 1.5, 0.3};  // Hz
constexpr double kSquash = 1.5;
constexpr double kRangeUse = 0.9;  // central 90%: 5% margin on each side

// Gross error magnitude for a scalar sensor, in units of its σ.
constexpr double kGrossLow = 10.0, kGrossSpan = 40.0;
// Gross marker displacement, metres.
constexpr double kMarkerGrossLow = 0.05, kMarkerGrossSpan = 0.15;

bool inUnit(double p) { return std::isfinite(p) && p >= 0.0 && p <= 1.0; }

bool checkOptions(const SimulationOptions& o, bool need_frames, std::string* error) {
  std::string e;
  if (need_frames && o.frames < 1)
    e = "frames must be at least 1, got " + std::to_string(o.frames);
  else if (!(std::isfinite(o.rate_hz) && o.rate_hz > 0.0))
    e = "rate must be positive, got " + std::to_string(o.rate_hz);
  else if (!(std::isfinite(o.noise_scale) && o.noise_scale >= 0.0))
    e = "noise scale must be non-negative, got " + std::to_string(o.noise_scale);
  else if (!inUnit(o.dropout))
    e = "dropout must be in [0, 1], got " + std::to_string(o.dropout);
  else if (!inUnit(o.outliers))
    e = "outliers must be in [0, 1], got " + std::to_string(o.outliers);
  if (error) *error = e;
  return e.empty();
}

}  // namespace

bool SimulationOptions::isValid(std::string* error) const {
  return checkOptions(*this, true, error);
}

std::vector<JointRange> motionRanges(const RobotModel& robot) {
  const int n = robot.dof();
  std::vector<JointRange> range(n);
  const auto& movable = robot.movableJoints();
  for (int i = 0; i < n; ++i) {
    const MovableJoint& mj = movable[robot.qJoints()[i]];
    double lo = robot.lowerLimits()[i], hi = robot.upperLimits()[i];
    const double span = mj.type == JointType::kPrismatic ? 0.2 : 2.0 * kPi;
    const bool flo = std::isfinite(lo) && std::abs(lo) < 1e100;
    const bool fhi = std::isfinite(hi) && std::abs(hi) < 1e100;
    if (!flo && !fhi) {
      lo = -0.5 * span;
      hi = 0.5 * span;
    } else if (!flo) {
      lo = hi - span;
    } else if (!fhi) {
      hi = lo + span;
    }
    range[i] = {lo, std::max(lo, hi)};
  }
  // A mimic follower (angle = m q + o) with limits narrows its master's range.
  for (const MovableJoint& f : movable) {
    if (!f.is_mimic || !f.has_limits || f.multiplier == 0.0) continue;
    if (!(std::isfinite(f.lower) && std::isfinite(f.upper))) continue;
    if (std::abs(f.lower) > 1e100 || std::abs(f.upper) > 1e100) continue;
    double a = (f.lower - f.offset) / f.multiplier;
    double b = (f.upper - f.offset) / f.multiplier;
    if (a > b) std::swap(a, b);
    JointRange& r = range[f.q_index];
    const double lo = std::max(r.lower, a), hi = std::min(r.upper, b);
    if (lo <= hi) r = {lo, hi};  // inconsistent limits: keep the master's
  }
  return range;
}

RowMatrix simulateMotion(const RobotModel& robot, int frames, double rate_hz,
                         std::mt19937_64& rng) {
  if (frames < 0) throw std::invalid_argument("simulateMotion: frames < 0");
  if (!(std::isfinite(rate_hz) && rate_hz > 0.0))
    throw std::invalid_argument("simulateMotion: rate must be positive");
  const int n = robot.dof();
  const std::vector<JointRange> range = motionRanges(robot);
  Draw draw(rng);
  // All random parameters first (a fixed count per joint).
  std::vector<double> freq(n * kComponents), phase(n * kComponents);
  for (int i = 0; i < n; ++i)
    for (int k = 0; k < kComponents; ++k) {
      freq[i * kComponents + k] =
          kFreqLow[k] + (kFreqHigh[k] - kFreqLow[k]) * draw.uniform();
      phase[i * kComponents + k] = 2.0 * kPi * draw.uniform();
    }
  const double norm = std::tanh(kSquash);
  RowMatrix q(frames, n);
  for (int t = 0; t < frames; ++t) {
    const double time = t / rate_hz;
    for (int i = 0; i < n; ++i) {
      double s = 0.0;
      for (int k = 0; k < kComponents; ++k)
        s += kAmplitude[k] * std::sin(2.0 * kPi * freq[i * kComponents + k] * time +
                                      phase[i * kComponents + k]);
      const double mid = 0.5 * (range[i].lower + range[i].upper);
      const double half = 0.5 * (range[i].upper - range[i].lower);
      q(t, i) = mid + kRangeUse * half * std::tanh(kSquash * s) / norm;
    }
  }
  return q;
}

namespace {

// The log's columns (joint sensors, tendon sensors, markers' x/y/z) for
// `frames` rows.
Log emptyLog(const SensorSet& sensors, int frames) {
  Log log;
  for (const JointSensorConfig& s : sensors.joint_sensors) log.columns.push_back(s.logColumn());
  for (const TendonSensorConfig& s : sensors.tendon_sensors) log.columns.push_back(s.logColumn());
  for (const MarkerConfig& m : sensors.markers)
    for (const std::string& c : m.logColumns()) log.columns.push_back(c);
  log.time_name = "time";
  log.time.resize(frames);
  log.values.resize(frames, sensors.joint_sensors.size() + sensors.tendon_sensors.size() +
                                3 * sensors.markers.size());
  log.line_of_frame.resize(frames);
  return log;
}

// A marker's reading into cell[0..2] from its prediction: noise, then maybe
// dropped or a gross error (returns true for the latter). Fifteen draws
// whatever happens, so one reading's fate never shifts another's noise.
bool noisyMarker(const MarkerConfig& c, const double* predicted, double k, double gross_scale,
                 const SimulationOptions& options, Draw& draw, double* cell) {
  Eigen::Vector3d x;
  for (int i = 0; i < 3; ++i) x[i] = predicted[i] + k * c.sigma * draw.normal();
  const double u_drop = draw.uniform(), u_out = draw.uniform(), u_mag = draw.uniform();
  Eigen::Vector3d dir;
  for (int i = 0; i < 3; ++i) dir[i] = draw.normal();
  if (u_drop < options.dropout) {
    cell[0] = cell[1] = cell[2] = std::numeric_limits<double>::quiet_NaN();
    return false;
  }
  const bool outlier = u_out < options.outliers;
  if (outlier) {
    const double len = dir.norm();
    dir = len > 1e-12 ? Eigen::Vector3d(dir / len) : Eigen::Vector3d::UnitX();
    const double mag = std::max(kMarkerGrossLow + kMarkerGrossSpan * u_mag,
                                (kGrossLow + kGrossSpan * u_mag) * c.sigma * gross_scale);
    x += mag * dir;
  }
  for (int i = 0; i < 3; ++i) cell[i] = x[i];
  return outlier;
}

}  // namespace

SimulatedLog simulateLog(const MeasurementModel& model,
                         const SensorParameters& truth, const RowMatrix& q,
                         const SimulationOptions& options,
                         std::mt19937_64& rng) {
  std::string error;
  if (!checkOptions(options, false, &error))
    throw std::invalid_argument("simulateLog: " + error);
  if (q.cols() != model.dof())
    throw std::invalid_argument("simulateLog: q has " + std::to_string(q.cols()) +
                                " columns, the robot has " +
                                std::to_string(model.dof()) + " joints");
  const SensorSet& sensors = model.sensors();
  const int frames = static_cast<int>(q.rows());
  const int M = static_cast<int>(sensors.markers.size());
  const int J = static_cast<int>(sensors.joint_sensors.size());
  const int N = static_cast<int>(sensors.tendon_sensors.size());
  if (static_cast<int>(truth.marker_position.size()) != M ||
      static_cast<int>(truth.joint_sensor.size()) != J ||
      static_cast<int>(truth.tendon_sensor.size()) != N)
    throw std::invalid_argument("simulateLog: parameters do not match the sensors");

  SimulatedLog out;
  Log& log = out.log;
  log = emptyLog(sensors, frames);

  const double k = options.noise_scale;
  const double gross_scale = std::max(1.0, k);
  KinematicsWorkspace ws(model.robot());
  Eigen::VectorXd pm(3 * M), pj(J), pt(N), qt(model.dof());
  Draw draw(rng);

  // A scalar reading: noise, then maybe a gross error. Four draws each.
  auto scalar = [&](double predicted, double sigma, int t, SensorGroup group,
                    int index, const std::string& name) {
    const double noise = draw.normal();
    const double u_out = draw.uniform(), u_mag = draw.uniform(), u_sign = draw.uniform();
    double v = predicted + k * sigma * noise;
    if (u_out < options.outliers) {
      const double sign = u_sign < 0.5 ? -1.0 : 1.0;
      v += sign * (kGrossLow + kGrossSpan * u_mag) * sigma * gross_scale;
      out.outliers.push_back({t, group, index, name});
    }
    return v;
  };

  for (int t = 0; t < frames; ++t) {
    log.time[t] = t / options.rate_hz;
    log.line_of_frame[t] = t + 2;  // line 1 is the header
    qt = q.row(t).transpose();
    predictFrame(model, truth, qt, &ws, pm.data(), pj.data(), pt.data());
    double* row = log.values.row(t).data();
    for (int j = 0; j < J; ++j) {
      const JointSensorConfig& s = sensors.joint_sensors[j];
      row[j] = scalar(pj[j], s.sigma, t, SensorGroup::kJoint, j, s.name);
    }
    for (int n = 0; n < N; ++n) {
      const TendonSensorConfig& s = sensors.tendon_sensors[n];
      row[J + n] = scalar(pt[n], s.sigma, t, SensorGroup::kTendon, n, s.name);
    }
    for (int m = 0; m < M; ++m) {
      double* cell = row + J + N + 3 * m;
      if (noisyMarker(sensors.markers[m], pm.data() + 3 * m, k, gross_scale, options, draw, cell))
        out.outliers.push_back({t, SensorGroup::kMarker, m, sensors.markers[m].name});
    }
  }
  return out;
}

Simulation simulate(const MeasurementModel& model, const SensorParameters& truth,
                    const SimulationOptions& options) {
  std::string error;
  if (!options.isValid(&error)) throw std::invalid_argument("simulate: " + error);
  std::mt19937_64 rng(options.seed);
  Simulation sim;
  sim.q = simulateMotion(model.robot(), options.frames, options.rate_hz, rng);
  sim.data = simulateLog(model, truth, sim.q, options, rng);
  return sim;
}

Log jointAnglesLog(const RobotModel& robot, const RowMatrix& q,
                   const std::vector<double>& time) {
  if (q.cols() != robot.dof())
    throw std::invalid_argument("jointAnglesLog: q has the wrong number of columns");
  if (!time.empty() && static_cast<Eigen::Index>(time.size()) != q.rows())
    throw std::invalid_argument("jointAnglesLog: one time per frame expected");
  Log log;
  for (int i = 0; i < robot.dof(); ++i) log.columns.push_back(robot.qName(i));
  if (!time.empty()) {
    log.time_name = "time";
    log.time = time;
  }
  log.values = q;
  log.line_of_frame.resize(q.rows());
  for (Eigen::Index t = 0; t < q.rows(); ++t) log.line_of_frame[t] = static_cast<int>(t) + 2;
  return log;
}

}  // namespace stac
