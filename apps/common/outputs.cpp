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

std::vector<ParameterChange> largestChanges(const ThetaSpace& space,
                                            const SensorParameters& before,
                                            const SensorParameters& after, int n) {
  const Eigen::VectorXd scale = space.scale(after);
  const Eigen::VectorXd change = space.minus(after, before);
  std::vector<ParameterChange> all;
  bool rotation_listed = false;
  for (int i : space.freeIndex()) {
    const ThetaEntry e = space.entry(i);
    if (e.block == ThetaBlock::kMocapRotation) {
      // One entry for the turn: its components depend on the axes chosen.
      if (rotation_listed) continue;
      rotation_listed = true;
      const double angle = change.segment<3>(ThetaSpace::kRotationOffset).norm();
      all.push_back({"mocap.frame.rotation (angle)", 0.0, angle, angle});
      continue;
    }
    all.push_back({space.names()[i], space.value(before, i), space.value(after, i),
                   std::abs(change[i]) / scale[i]});
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
