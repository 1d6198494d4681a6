// stac_eval: cross-sensor prediction on held-out data (SPEC §4; paper
// Tables I, II).
#include <iostream>
#include <string>
#include <vector>

#include "common/cli.hpp"
#include "common/inputs.hpp"
#include "common/outputs.hpp"
#include "stac/error.hpp"
#include "stac/evaluate.hpp"
#include "stac/log.hpp"
#include "stac/robot_model.hpp"
#include "stac/sensors_file.hpp"

namespace {

using namespace stac;

const std::vector<cli::Option> kOptions = {
    {"urdf", "FILE", "robot description (URDF)", true},
    {"sensors", "FILE", "calibration to evaluate (sensors file, YAML)", true},
    {"log", "FILE", "held-out readings (CSV, SPEC §2)", true},
    {"use", "GROUPS", "groups that estimate q: comma-separated marker,joint,tendon", true},
    {"predict", "GROUPS", "groups to predict (default: every group in the sensors file)"},
    {"truth", "FILE", "true sensors file: also print each parameter's error"},
    {"json", "FILE", "also write the numbers as JSON"},
    {"mocap-units", "m|mm", "unit of the marker columns (default m)"},
    cli::ignoreColumnsOption(),
    {"threads", "N", "worker threads; 0 = all cores (default)"},
};

const char* kSynopsis =
    "stac_eval --urdf robot.urdf --sensors calibration.yaml --log test.csv\n"
    "          --use joint,tendon [--predict marker,joint,tendon]\n"
    "          [--truth truth.yaml] [--json result.json]\n\n"
    "Estimates the joint angles of every frame from the --use groups only,\n"
    "predicts every group from them and prints the mean absolute error per group\n"
    "(markers: mean Euclidean distance in metres; joint and tendon sensors: raw\n"
    "units). Groups that also estimated q are shown in parentheses.";

// "joint,tendon" -> flags per group; UsageError on an unknown or repeated name.
void parseGroups(const cli::Args& args, const std::string& flag, bool out[kNumSensorGroups]) {
  for (int g = 0; g < kNumSensorGroups; ++g) out[g] = false;
  for (const std::string& item : args.getList(flag, "sensor group")) {
    const std::optional<SensorGroup> group = groupFromName(item);
    if (!group)
      throw cli::UsageError(args.typed(flag) + ": unknown sensor group '" + item +
                            "' (expected a comma-separated list of marker, joint, tendon)");
    const int found = static_cast<int>(*group);
    if (out[found]) throw cli::UsageError(args.typed(flag) + ": names '" + item + "' twice");
    out[found] = true;
  }
}


int run(const cli::Args& args) {
  const std::string urdf = args.get("urdf"), sensors_path = args.get("sensors");
  const std::string log_path = args.get("log"), truth_path = args.get("truth");
  const std::string json_path = args.get("json");

  EvaluationOptions options;
  parseGroups(args, "use", options.use);
  const bool explicit_predict = args.has("predict");
  if (explicit_predict) parseGroups(args, "predict", options.predict);
  options.threads = args.getIntAtLeast("threads", 0, 0, "0 = all cores");
  const double mocap_scale = args.getChoice("mocap-units", {"m", "mm"}, "m") == "mm" ? 1e-3 : 1.0;

  std::vector<std::string> inputs = {urdf, sensors_path, log_path};
  if (!truth_path.empty()) inputs.push_back(truth_path);
  if (args.has("json")) cli::checkOutputs(inputs, {{"--json", json_path}});

  const RobotModel robot = RobotModel::fromFile(urdf);
  SensorsFile sf = loadSensorsFile(sensors_path, robot);
  ignoreColumns(&sf, cli::ignoredColumns(args), "--ignore-columns", sensors_path);
  for (int g = 0; g < kNumSensorGroups; ++g) {
    const std::string name = groupName(static_cast<SensorGroup>(g));
    if (options.use[g] && sf.sensors.groupSize(static_cast<SensorGroup>(g)) == 0)
      throw cli::UsageError("--use " + name + ": the sensors file '" + sensors_path + "' has no " +
                            name + " sensors");
    if (explicit_predict && options.predict[g] && sf.sensors.groupSize(static_cast<SensorGroup>(g)) == 0)
      throw cli::UsageError("--predict " + name + ": the sensors file '" + sensors_path +
                            "' has no " + name + " sensors");
  }
  std::vector<ParameterError> truth;
  if (!truth_path.empty()) {
    const SensorsFile tf = loadSensorsFile(truth_path, robot);
    truth = compareToTruth(sf.sensors, sf.theta, tf.sensors, tf.theta, truth_path);
  }
  const Log log = readLog(log_path);
  const Observations obs = cli::bindSensors(log, sf, sensors_path, mocap_scale);
  requireReadings(obs, sf.sensors, log_path, ReadingCheck::kAnyFrame);

  const EvaluationResult result = evaluatePrediction(robot, sf.sensors, sf.theta, obs, options);
  const std::vector<ParameterError>* truth_ptr = truth_path.empty() ? nullptr : &truth;
  if (args.has("json")) cli::writeOutput(json_path, evaluationJson(result, truth_ptr));
  std::cout << evaluationReport(result, truth_ptr);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return stac::cli::runApp(argc, argv, "stac_eval", kSynopsis, kOptions, run);
}
