// stac_simulate: synthetic data from a known truth (SPEC §4).
//
//   stac_simulate --urdf robot.urdf --sensors truth.yaml --frames N
//                 --log data.csv [--joint-angles q_true.csv] [--seed S]
//                 [--rate HZ] [--noise-scale K] [--dropout P] [--outliers P]
#include <cstdint>
#include <filesystem>
#include <iostream>
#include <string>
#include <vector>

#include "common/cli.hpp"
#include "common/interrupt.hpp"
#include "common/outputs.hpp"
#include "stac/error.hpp"
#include "stac/file_io.hpp"
#include "stac/log.hpp"
#include "stac/measurement.hpp"
#include "stac/robot_model.hpp"
#include "stac/sensors_file.hpp"
#include "stac/simulate.hpp"

namespace {

using stac::cli::Args;
using stac::cli::Option;
using stac::cli::UsageError;
namespace fs = std::filesystem;

const char* kSynopsis =
    "usage: stac_simulate --urdf robot.urdf --sensors truth.yaml --frames N\n"
    "                     --log data.csv [--joint-angles q_true.csv] [--seed S]\n"
    "                     [--rate HZ] [--noise-scale K] [--dropout P] [--outliers P]\n"
    "\n"
    "Simulates smooth random motion inside the joint limits and the readings of\n"
    "every sensor in truth.yaml, with Gaussian noise of each sensor's sigma times\n"
    "K, dropped marker readings and gross outliers. The same seed gives the same\n"
    "files, byte for byte.";

const std::vector<Option> kOptions = {
    {"urdf", "FILE", "robot model (URDF)", true},
    {"sensors", "FILE", "the true sensor parameters (YAML, SPEC §3)", true},
    {"frames", "N", "number of frames (>= 1)", true},
    {"log", "FILE", "output log (CSV, SPEC §2)", true},
    {"joint-angles", "FILE", "also write the true joint angles (CSV)", false},
    {"seed", "S", "random seed, a non-negative integer (default 1)", false},
    {"rate", "HZ", "sample rate in Hz (default 100)", false},
    {"noise-scale", "K", "noise = sensor sigma * K (default 1; 0: noise-free)", false},
    {"dropout", "P", "probability that a marker is missing in a frame (default 0)", false},
    {"outliers", "P", "fraction of readings replaced by gross errors (default 0)", false},
};

int run(const Args& args) {
  stac::SimulationOptions options;
  options.frames = args.getIntAtLeast("frames", 0, 1);
  options.rate_hz = args.getPositive("rate", options.rate_hz);
  options.noise_scale = args.getNonNegative("noise-scale", options.noise_scale);
  options.dropout = args.getFraction("dropout", options.dropout);
  options.outliers = args.getFraction("outliers", options.outliers);
  options.seed = args.getUnsigned("seed", 1);
  std::string error;
  if (!options.isValid(&error)) throw UsageError(error);

  const std::string log_path = args.get("log");
  const std::string q_path = args.get("joint-angles");
  std::vector<std::pair<std::string, std::string>> outputs = {{"--log", log_path}};
  if (args.has("joint-angles")) outputs.emplace_back("--joint-angles", q_path);
  stac::cli::checkOutputs({args.get("urdf"), args.get("sensors")}, outputs);

  const stac::RobotModel robot = stac::RobotModel::fromFile(args.get("urdf"));
  const stac::SensorsFile truth = stac::loadSensorsFile(args.get("sensors"), robot);
  const stac::MeasurementModel model(robot, truth.sensors);
  stac::Simulation sim = stac::simulate(model, truth.theta, options);
  sim.data.log.path = log_path;

  // Everything is computed before anything is written.
  stac::Log q_log;
  if (args.has("joint-angles")) {
    q_log = stac::jointAnglesLog(robot, sim.q, sim.data.log.time);
    q_log.path = q_path;
  }
  const stac::cli::DeferInterrupts all_or_none;
  stac::cli::throwIfInterrupted();
  stac::cli::writeLogOutput(log_path, sim.data.log);
  if (args.has("joint-angles")) stac::cli::writeLogOutput(q_path, q_log);

  const stac::SensorSet& s = truth.sensors;
  std::cerr << "stac_simulate: " << options.frames << " frames at " << options.rate_hz
            << " Hz of " << s.joint_sensors.size() << " joint sensors, "
            << s.tendon_sensors.size() << " tendon sensors, " << s.markers.size()
            << " markers (seed " << options.seed << ", " << sim.data.outliers.size()
            << " outliers) -> " << log_path
            << (q_path.empty() ? "" : ", joint angles -> " + q_path) << "\n";
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return stac::cli::runApp(argc, argv, "stac_simulate", kSynopsis, kOptions, run);
}
