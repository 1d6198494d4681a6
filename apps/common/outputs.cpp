#include "common/outputs.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "common/cli.hpp"
#include "common/interrupt.hpp"
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
  const DeferInterrupts whole_file;  // never a temporary file left behind
  markOutputsStarted();
  try {
    writeFileAtomically(path, content);
  } catch (const std::runtime_error& e) {
    // The user's folder failed, not us: bad input (exit 2), nothing partial left.
    throw InputError(path, std::string("cannot write: ") + e.what());
  }
}

void writeLogOutput(const std::string& path, const Log& log) {
  const DeferInterrupts whole_file;
  markOutputsStarted();
  try {
    writeLog(path, log);
  } catch (const InputError&) {
    throw;
  } catch (const std::runtime_error& e) {
    throw InputError(path, std::string("cannot write: ") + e.what());
  }
}

}  // namespace stac::cli
