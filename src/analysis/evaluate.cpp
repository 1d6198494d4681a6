#include "stac/evaluate.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>

#include "io/quoted.hpp"
#include "model/prediction_errors.hpp"
#include "stac/calibrate.hpp"
#include "stac/error.hpp"
#include "stac/file_io.hpp"
#include "stac/kinematics.hpp"
#include "stac/measurement.hpp"
#include "stac/theta_space.hpp"
#include "solve/parallel.hpp"
#include "solve/q_phase.hpp"

namespace stac {

namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();


// Estimates q from the used groups: a tracking pass from the neutral pose
// (each frame warm-started from its predecessor), then lm-batch refinements.
RowMatrix estimateQ(const MeasurementModel& model, const SensorParameters& theta,
                    const Observations& obs, const EvaluationOptions& options) {
  const RobotModel& robot = model.robot();
  const NoiseModel noise = NoiseModel::fromSeeds(model.sensors());
  const RobustLoss loss;
  QPhaseOptions qo;
  qo.method = QPhaseMethod::kLmBatch;
  qo.max_steps = options.max_steps;
  qo.threads = options.threads;
  for (int g = 0; g < kNumSensorGroups; ++g) qo.eval.group_weight[g] = options.use[g] ? 1.0 : 0.0;
  const int threads = resolveThreads(options.threads);
  std::vector<FrameWorkspace> ws;
  ws.reserve(threads);
  for (int i = 0; i < threads; ++i) ws.emplace_back(model);
  QState state;
  state.q.resize(obs.num_frames, robot.dof());
  trackingPass(model, theta, noise, loss, obs, qo, neutralPose(robot),
               options.tracking_segments, &ws, &state);
  for (int i = 0; i < options.refinements; ++i)
    qPhase(model, theta, noise, loss, obs, qo, &ws, &state);
  return state.q;
}

}  // namespace

bool EvaluationOptions::isValid(std::string* error) const {
  auto fail = [&](const std::string& e) {
    if (error) *error = e;
    return false;
  };
  if (!use[0] && !use[1] && !use[2]) return fail("no sensor group is used to estimate q");
  if (threads < 0) return fail("threads must be >= 0 (0 = all cores)");
  if (tracking_segments < 1) return fail("tracking_segments must be at least 1");
  if (refinements < 0) return fail("refinements must be >= 0");
  if (max_steps < 1) return fail("max_steps must be at least 1");
  return true;
}

namespace {

// The frames whose q the q-phase held at a bound of its box.
void countFramesAtLimit(const RobotModel& robot, EvaluationResult* r) {
  const auto at = atWidenedLimit(robot, r->q);
  r->q_names.clear();
  for (int j = 0; j < robot.dof(); ++j)
    r->q_names.push_back(robot.qName(j));
  r->frames_at_limit.assign(robot.dof(), 0);
  for (int j = 0; j < robot.dof(); ++j)
    r->frames_at_limit[j] = static_cast<int>(at.col(j).count());
  r->frames_clamped = static_cast<int>(at.rowwise().any().count());
}

}  // namespace

EvaluationResult evaluatePrediction(const RobotModel& robot, const SensorSet& sensors,
                                    const SensorParameters& theta, const Observations& obs,
                                    const EvaluationOptions& options) {
  std::string error;
  if (!options.isValid(&error)) throw std::invalid_argument(error);
  const int M = sensors.groupSize(static_cast<SensorGroup>(0)), J = sensors.groupSize(static_cast<SensorGroup>(1)), N = sensors.groupSize(static_cast<SensorGroup>(2));
  const int T = obs.num_frames;
  if (obs.marker.rows() != T || obs.joint.rows() != T || obs.tendon.rows() != T ||
      obs.marker.cols() != 3 * M || obs.joint.cols() != J || obs.tendon.cols() != N)
    throw std::invalid_argument("evaluatePrediction: the observations do not match the sensors");
  if (static_cast<int>(theta.marker_position.size()) != M ||
      static_cast<int>(theta.joint_sensor.size()) != J ||
      static_cast<int>(theta.tendon_sensor.size()) != N)
    throw std::invalid_argument("evaluatePrediction: the parameters do not match the sensors");
  for (int g = 0; g < kNumSensorGroups; ++g)
    if (options.use[g] && sensors.groupSize(static_cast<SensorGroup>(g)) == 0)
      throw std::invalid_argument(std::string("evaluatePrediction: no ") +
                                  groupName(static_cast<SensorGroup>(g)) +
                                  " sensors to estimate q from");

  const MeasurementModel model(robot, sensors);
  EvaluationResult result;
  result.frames = T;
  result.q = T > 0 ? estimateQ(model, theta, obs, options) : RowMatrix(0, robot.dof());
  countFramesAtLimit(robot, &result);

  // Absolute errors of every reading (NaN where missing), frames x sensors.
  RowMatrix err_marker = RowMatrix::Constant(T, M, kNaN);
  RowMatrix err_joint = RowMatrix::Constant(T, J, kNaN);
  RowMatrix err_tendon = RowMatrix::Constant(T, N, kNaN);
  RowMatrix* errors_of[kNumSensorGroups] = {&err_marker, &err_joint, &err_tendon};
  visitPredictionErrors(model, theta, obs, result.q, options.threads,
                        [&](int, int t, SensorGroup g, int sensor, double e) {
                          (*errors_of[static_cast<int>(g)])(t, sensor) = e;
                        });

  const RowMatrix* errors[kNumSensorGroups] = {&err_marker, &err_joint, &err_tendon};
  for (int g = 0; g < kNumSensorGroups; ++g) {
    GroupPredictionError& ge = result.group[g];
    ge.present = sensors.groupSize(static_cast<SensorGroup>(g)) > 0;
    ge.predicted = ge.present && options.predict[g];
    ge.used = options.use[g];
    ge.mae = kNaN;
    if (!ge.predicted) continue;
    double group_sum = 0.0;
    for (int i = 0; i < sensors.groupSize(static_cast<SensorGroup>(g)); ++i) {
      SensorPredictionError se;
      se.name = sensors.sensorName(static_cast<SensorGroup>(g), i);
      se.group = static_cast<SensorGroup>(g);
      se.index = i;
      double sum = 0.0;
      for (int t = 0; t < T; ++t) {
        const double e = (*errors[g])(t, i);
        if (std::isnan(e)) continue;
        sum += e;
        ++se.count;
      }
      se.mae = se.count > 0 ? sum / se.count : kNaN;
      group_sum += sum;
      ge.count += se.count;
      result.sensors.push_back(se);
    }
    if (ge.count > 0) ge.mae = group_sum / ge.count;
  }
  return result;
}

namespace {

// The truth's sensors, matched by name, in the estimate's layout; throws
// InputError(truth_source, ...) naming what does not match.
SensorParameters alignTruth(const SensorSet& sensors, const SensorSet& truth_sensors,
                            const SensorParameters& truth, const std::string& truth_source) {
  std::map<std::string, int> truth_index[kNumSensorGroups];
  for (int g = 0; g < kNumSensorGroups; ++g)
    for (int i = 0; i < truth_sensors.groupSize(static_cast<SensorGroup>(g)); ++i)
      truth_index[g][truth_sensors.sensorName(static_cast<SensorGroup>(g), i)] = i;
  std::vector<std::string> missing, extra, mismatched;
  if (!sensors.markers.empty() && truth_sensors.markers.empty())
    missing.push_back("the mocap frame (no markers)");
  SensorParameters aligned;
  aligned.mocap = truth.mocap;
  aligned.marker_position.resize(sensors.markers.size());
  aligned.joint_sensor.resize(sensors.joint_sensors.size());
  aligned.tendon_sensor.resize(sensors.tendon_sensors.size());
  for (int g = 0; g < kNumSensorGroups; ++g) {
    for (int i = 0; i < sensors.groupSize(static_cast<SensorGroup>(g)); ++i) {
      const std::string& name = sensors.sensorName(static_cast<SensorGroup>(g), i);
      auto it = truth_index[g].find(name);
      if (it == truth_index[g].end()) {
        missing.push_back(name);
        continue;
      }
      const int k = it->second;
      truth_index[g].erase(it);
      switch (static_cast<SensorGroup>(g)) {
        case SensorGroup::kMarker:
          if (sensors.markers[i].link != truth_sensors.markers[k].link)
            mismatched.push_back(name + " (link " + sensors.markers[i].link_name + " vs " +
                                 truth_sensors.markers[k].link_name + ")");
          aligned.marker_position[i] = truth.marker_position[k];
          break;
        case SensorGroup::kJoint:
          if (sensors.joint_sensors[i].joint != truth_sensors.joint_sensors[k].joint)
            mismatched.push_back(name + " (joint " + sensors.joint_sensors[i].joint_name +
                                 " vs " + truth_sensors.joint_sensors[k].joint_name + ")");
          aligned.joint_sensor[i] = truth.joint_sensor[k];
          break;
        case SensorGroup::kTendon: aligned.tendon_sensor[i] = truth.tendon_sensor[k]; break;
      }
    }
    for (const auto& [name, k] : truth_index[g]) extra.push_back(name);
  }
  auto join = [](const std::vector<std::string>& v) {
    std::string s;
    for (const std::string& x : v) s += (s.empty() ? "" : ", ") + x;
    return s;
  };
  std::string problem;
  if (!missing.empty()) problem += "lacks " + join(missing);
  if (!extra.empty())
    problem += (problem.empty() ? "" : "; ") + std::string("has sensors the calibration lacks: ") +
               join(extra);
  if (!mismatched.empty())
    problem += (problem.empty() ? "" : "; ") + std::string("attaches differently: ") +
               join(mismatched);
  if (!problem.empty())
    throw InputError(truth_source, "the truth does not match the calibrated sensors: " + problem);
  // A joint the truth does not correct has its URDF origin: a zero correction.
  aligned.joint_origin.assign(sensors.joint_origins.size(), OriginCorrection{});
  for (size_t c = 0; c < sensors.joint_origins.size(); ++c)
    for (size_t k = 0; k < truth_sensors.joint_origins.size(); ++k)
      if (truth_sensors.joint_origins[k].link == sensors.joint_origins[c].link)
        aligned.joint_origin[c] = truth.joint_origin[k];
  return aligned;
}

}  // namespace

std::vector<ParameterError> compareToTruth(const SensorSet& sensors,
                                           const SensorParameters& theta,
                                           const SensorSet& truth_sensors,
                                           const SensorParameters& truth,
                                           const std::string& truth_source) {
  const ThetaSpace space(sensors);
  const Eigen::VectorXd d =
      space.minus(theta, alignTruth(sensors, truth_sensors, truth, truth_source));
  std::vector<ParameterError> out;
  if (!sensors.markers.empty()) {
    out.push_back({"mocap.translation", d.segment<3>(ThetaSpace::kTranslationOffset).norm(), "m"});
    out.push_back({"mocap.rotation", d.segment<3>(ThetaSpace::kRotationOffset).norm(), "rad"});
  }
  for (size_t m = 0; m < sensors.markers.size(); ++m)
    out.push_back({sensors.markers[m].name + ".position",
                   d.segment<3>(space.markerOffset(static_cast<int>(m))).norm(), "m"});
  for (size_t j = 0; j < sensors.joint_sensors.size(); ++j) {
    const int o = space.jointOffset(static_cast<int>(j));
    out.push_back({sensors.joint_sensors[j].name + ".gain", d[o], ""});
    out.push_back({sensors.joint_sensors[j].name + ".bias", d[o + 1], ""});
  }
  for (size_t j = 0; j < sensors.tendon_sensors.size(); ++j) {
    const int o = space.tendonOffset(static_cast<int>(j));
    out.push_back({sensors.tendon_sensors[j].name + ".gain", d[o], ""});
    out.push_back({sensors.tendon_sensors[j].name + ".bias", d[o + 1], ""});
  }
  for (size_t c = 0; c < sensors.joint_origins.size(); ++c) {
    const int o = space.originOffset(static_cast<int>(c));
    out.push_back({sensors.joint_origins[c].joint_name + ".origin.xyz", d.segment<3>(o).norm(), "m"});
    out.push_back(
        {sensors.joint_origins[c].joint_name + ".origin.rpy", d.segment<3>(o + 3).norm(), "rad"});
  }
  return out;
}

namespace {

std::string number(double v, const char* fmt = "%.6g") {
  if (!std::isfinite(v)) return "-";
  char buf[64];
  std::snprintf(buf, sizeof buf, fmt, v);
  return buf;
}

std::string jsonNumber(double v) { return std::isfinite(v) ? formatNumber(v) : "null"; }

std::string jsonString(const std::string& s) { return doubleQuoted(s, QuoteStyle::kJson); }


}  // namespace

std::string evaluationReport(const EvaluationResult& r, const std::vector<ParameterError>* truth) {
  std::ostringstream o;
  std::string use;
  for (int g = 0; g < kNumSensorGroups; ++g)
    if (r.group[g].used) use += (use.empty() ? "" : ",") + std::string(groupName(static_cast<SensorGroup>(g)));
  o << "cross-sensor prediction: q of " << r.frames << " frames estimated from " << use << "\n";
  o << "mean absolute error per group (in parentheses: groups that also estimated q)\n";
  char buf[256];
  std::string head = " ", row = " ";
  for (int g = 0; g < kNumSensorGroups; ++g) {
    const GroupPredictionError& ge = r.group[g];
    if (!ge.predicted) continue;
    std::snprintf(buf, sizeof buf, " %16s", (std::string(groupName(static_cast<SensorGroup>(g))) +
                                              " (" + groupUnit(static_cast<SensorGroup>(g)) + ")").c_str());
    head += buf;
    const std::string v = ge.used ? "(" + number(ge.mae) + ")" : number(ge.mae);
    std::snprintf(buf, sizeof buf, " %16s", v.c_str());
    row += buf;
  }
  o << head << "\n" << row << "\n";
  if (r.frames_clamped > 0) {
    o << "\nwarning: " << r.frames_clamped << " of " << r.frames
      << " frames have a joint held at its limit (the URDF's widened by 5%): their readings ask "
         "for angles the URDF rules out, and their predictions carry the difference:";
    for (size_t j = 0; j < r.frames_at_limit.size(); ++j)
      if (r.frames_at_limit[j] > 0) o << " " << r.q_names[j] << " (" << r.frames_at_limit[j] << ")";
    o << "\n";
  }
  if (!r.sensors.empty()) {
    o << "\nper sensor                          MAE     readings\n";
    for (const SensorPredictionError& s : r.sensors) {
      const int g = static_cast<int>(s.group);
      std::snprintf(buf, sizeof buf, "  %-6s %-22s %12s %8d%s\n", groupName(s.group),
                    s.name.c_str(), number(s.mae).c_str(), s.count,
                    r.group[g].used ? "  (used)" : "");
      o << buf;
    }
  }
  if (truth) {
    o << "\nparameter errors against the truth (gain, bias: estimate - truth; position,\n"
         "translation: distance; rotation: angle)\n";
    for (const ParameterError& p : *truth) {
      std::snprintf(buf, sizeof buf, "  %-32s %14s%s%s\n", p.name.c_str(), number(p.error).c_str(),
                    p.unit.empty() ? "" : " ", p.unit.c_str());
      o << buf;
    }
  }
  return o.str();
}

std::string evaluationJson(const EvaluationResult& r, const std::vector<ParameterError>* truth) {
  std::ostringstream o;
  o << "{\n  \"frames\": " << r.frames << ",\n  \"use\": [";
  bool first = true;
  for (int g = 0; g < kNumSensorGroups; ++g) {
    if (!r.group[g].used) continue;
    o << (first ? "" : ", ") << jsonString(groupName(static_cast<SensorGroup>(g)));
    first = false;
  }
  o << "],\n  \"mae\": {";
  first = true;
  for (int g = 0; g < kNumSensorGroups; ++g) {
    if (!r.group[g].predicted) continue;
    o << (first ? "" : ", ") << jsonString(groupName(static_cast<SensorGroup>(g))) << ": "
      << jsonNumber(r.group[g].mae);
    first = false;
  }
  o << "},\n  \"per_sensor\": {";
  first = true;
  for (const SensorPredictionError& s : r.sensors) {
    o << (first ? "\n" : ",\n") << "    " << jsonString(s.name) << ": {\"mae\": "
      << jsonNumber(s.mae) << ", \"count\": " << s.count << "}";
    first = false;
  }
  o << (first ? "}" : "\n  }");
  o << ",\n  \"frames_at_limit\": {\"frames\": " << r.frames_clamped << ", \"joints\": {";
  first = true;
  for (size_t j = 0; j < r.frames_at_limit.size(); ++j) {
    if (r.frames_at_limit[j] == 0) continue;
    o << (first ? "" : ", ") << jsonString(r.q_names[j]) << ": " << r.frames_at_limit[j];
    first = false;
  }
  o << "}}";
  if (truth) {
    o << ",\n  \"truth\": {";
    first = true;
    for (const ParameterError& p : *truth) {
      o << (first ? "\n" : ",\n") << "    " << jsonString(p.name) << ": " << jsonNumber(p.error);
      first = false;
    }
    o << (first ? "}" : "\n  }");
  }
  o << "\n}\n";
  return o.str();
}

std::vector<CrossSensorRow> crossSensorTable(const RobotModel& robot, const SensorSet& sensors,
                                             const SensorParameters& theta,
                                             const Observations& obs,
                                             const EvaluationOptions& options) {
  const bool present[kNumSensorGroups] = {!sensors.markers.empty(), !sensors.joint_sensors.empty(),
                                          !sensors.tendon_sensors.empty()};
  // Group subsets as bit masks, ordered by size, then by group order: the
  // single-sensor rows of the paper's tables come first.
  std::vector<int> masks;
  for (int size = 1; size <= kNumSensorGroups; ++size)
    for (int mask = 1; mask < (1 << kNumSensorGroups); ++mask) {
      int bits = 0;
      bool ok = true;
      for (int g = 0; g < kNumSensorGroups; ++g)
        if (mask & (1 << g)) {
          ++bits;
          ok = ok && present[g];
        }
      if (ok && bits == size) masks.push_back(mask);
    }
  std::vector<CrossSensorRow> rows;
  for (int mask : masks) {
    EvaluationOptions o = options;
    CrossSensorRow row;
    for (int g = 0; g < kNumSensorGroups; ++g) {
      o.use[g] = (mask & (1 << g)) != 0;
      o.predict[g] = present[g];
      if (o.use[g])
        row.label += (row.label.empty() ? "" : "+") + std::string(groupName(static_cast<SensorGroup>(g)));
    }
    row.result = evaluatePrediction(robot, sensors, theta, obs, o);
    rows.push_back(std::move(row));
  }
  return rows;
}

std::string crossSensorTableText(const std::vector<CrossSensorRow>& rows) {
  if (rows.empty()) return "";
  std::ostringstream o;
  char buf[256];
  std::snprintf(buf, sizeof buf, "  %-24s", "q estimated from");
  o << buf;
  const EvaluationResult& first = rows.front().result;
  for (int g = 0; g < kNumSensorGroups; ++g) {
    if (!first.group[g].predicted) continue;
    std::snprintf(buf, sizeof buf, " %16s",
                  (std::string(groupName(static_cast<SensorGroup>(g))) + " (" + groupUnit(static_cast<SensorGroup>(g)) + ")").c_str());
    o << buf;
  }
  o << "\n";
  for (const CrossSensorRow& row : rows) {
    std::snprintf(buf, sizeof buf, "  %-24s", row.label.c_str());
    o << buf;
    for (int g = 0; g < kNumSensorGroups; ++g) {
      const GroupPredictionError& ge = row.result.group[g];
      if (!first.group[g].predicted) continue;
      const std::string v = ge.used ? "(" + number(ge.mae) + ")" : number(ge.mae);
      std::snprintf(buf, sizeof buf, " %16s", v.c_str());
      o << buf;
    }
    o << "\n";
  }
  return o.str();
}

}  // namespace stac
