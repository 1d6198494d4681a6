#include "common/outputs.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "common/cli.hpp"
#include "stac/error.hpp"
#include "stac/file_io.hpp"

namespace stac::cli {

namespace {
namespace fs = std::filesystem;

// Absolute, normalised form of a path that may not exist yet.
fs::path normalised(const std::string& p) {
  std::error_code ec;
  fs::path n = fs::weakly_canonical(fs::absolute(p, ec), ec);
  return ec ? fs::path(p).lexically_normal() : n;
}

bool samePath(const std::string& a, const std::string& b) {
  return sameFile(a, b) || normalised(a) == normalised(b);
}
}  // namespace

void checkOutputs(const std::vector<std::string>& inputs,
                  const std::vector<std::pair<std::string, std::string>>& outputs) {
  for (size_t i = 0; i < outputs.size(); ++i) {
    const auto& [flag, path] = outputs[i];
    if (path.empty()) throw UsageError(flag + " needs a file name");
    for (const std::string& in : inputs)
      if (!in.empty() && samePath(path, in))
        throw UsageError(flag + " '" + path + "' is one of the inputs: refusing to overwrite it");
    for (size_t j = 0; j < i; ++j)
      if (samePath(path, outputs[j].second))
        throw UsageError(flag + " and " + outputs[j].first + " name the same file '" + path + "'");
    std::error_code ec;
    if (fs::is_directory(path, ec)) throw UsageError(flag + " '" + path + "' is a directory");
    const fs::path dir = normalised(path).parent_path();
    if (!dir.empty() && !fs::is_directory(dir, ec))
      throw UsageError(flag + " '" + path + "': folder '" + dir.string() + "' does not exist");
  }
}

void writeOutput(const std::string& path, const std::string& content) {
  try {
    writeFileAtomically(path, content);
  } catch (const std::runtime_error& e) {
    // The user's folder failed, not us: bad input (exit 2), nothing partial left.
    throw InputError(path, std::string("cannot write: ") + e.what());
  }
}

std::vector<ParameterChange> largestChanges(const MeasurementModel& model,
                                            const SensorParameters& before,
                                            const SensorParameters& after, int n) {
  const SensorSet& s = model.sensors();
  const Eigen::VectorXd scale = model.thetaScale(after);
  std::vector<ParameterChange> all;
  auto add = [&](const std::string& name, double b, double a, double sc) {
    all.push_back({name, b, a, std::abs(a - b) / sc});
  };
  if (!s.markers.empty() && !s.mocap_frame_fixed) {
    const double angle = Eigen::AngleAxisd(after.mocap.rotation * before.mocap.rotation.inverse()).angle();
    add("mocap.frame.rotation (angle)", 0.0, angle, 1.0);
    const char* axes[3] = {"x", "y", "z"};
    for (int i = 0; i < 3; ++i)
      add(std::string("mocap.frame.translation.") + axes[i], before.mocap.translation[i],
          after.mocap.translation[i], scale[MeasurementModel::kTranslationOffset + i]);
  }
  const char* axes[3] = {"x", "y", "z"};
  for (size_t m = 0; m < s.markers.size(); ++m) {
    if (s.markers[m].fixed) continue;
    for (int i = 0; i < 3; ++i)
      add("markers." + s.markers[m].name + ".position." + axes[i], before.marker_position[m][i],
          after.marker_position[m][i], scale[model.markerOffset(static_cast<int>(m)) + i]);
  }
  for (size_t j = 0; j < s.joint_sensors.size(); ++j) {
    if (s.joint_sensors[j].fixed) continue;
    const int o = model.jointOffset(static_cast<int>(j));
    add("joint_sensors." + s.joint_sensors[j].name + ".gain", before.joint_sensor[j].gain,
        after.joint_sensor[j].gain, scale[o]);
    add("joint_sensors." + s.joint_sensors[j].name + ".bias", before.joint_sensor[j].bias,
        after.joint_sensor[j].bias, scale[o + 1]);
  }
  for (size_t j = 0; j < s.tendon_sensors.size(); ++j) {
    if (s.tendon_sensors[j].fixed) continue;
    const int o = model.tendonOffset(static_cast<int>(j));
    add("tendon_sensors." + s.tendon_sensors[j].name + ".gain", before.tendon_sensor[j].gain,
        after.tendon_sensor[j].gain, scale[o]);
    add("tendon_sensors." + s.tendon_sensors[j].name + ".bias", before.tendon_sensor[j].bias,
        after.tendon_sensor[j].bias, scale[o + 1]);
  }
  std::stable_sort(all.begin(), all.end(),
                   [](const ParameterChange& a, const ParameterChange& b) { return a.score > b.score; });
  if (static_cast<int>(all.size()) > n) all.resize(n);
  return all;
}

void writeLogOutput(const std::string& path, const Log& log) {
  try {
    writeLog(path, log);
  } catch (const InputError&) {
    throw;
  } catch (const std::runtime_error& e) {
    throw InputError(path, std::string("cannot write: ") + e.what());
  }
}

}  // namespace stac::cli
