// The saved fuzz corpus (test/fuzz/corpus/<target>/, minimised by
// test/fuzz/run.sh) and the fuzzers' findings (test/fuzz/regressions/
// <target>/, each the minimised input of a fixed bug) replayed through the
// same entry points as the libFuzzer harnesses, without libFuzzer: every
// input must be accepted or refused with an InputError, never crash, throw
// anything else or trip a sanitizer (in the ASan build).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>
#include <vector>

#include "fuzz/fuzz_targets.hpp"

namespace stac {
namespace {

namespace fs = std::filesystem;
using Target = std::function<void(const std::uint8_t*, std::size_t)>;

std::vector<fs::path> filesIn(const fs::path& dir) {
  std::vector<fs::path> files;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (e.is_regular_file()) files.push_back(e.path());
  std::sort(files.begin(), files.end());
  return files;
}

// Feeds every file of the target's corpus and regressions; returns how many.
size_t replay(const std::string& target, const Target& run) {
  const fs::path root = fs::path(STAC_SOURCE_DIR) / "test" / "fuzz";
  size_t count = 0;
  for (const char* kind : {"corpus", "regressions"}) {
    for (const fs::path& file : filesIn(root / kind / target)) {
      std::ifstream in(file, std::ios::binary);
      const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
      SCOPED_TRACE(file.string());
      const auto start = std::chrono::steady_clock::now();
      EXPECT_NO_THROW(run(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()));
      // The fuzzers' hang limit is 5 s; a corpus input is far below it.
      EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(),
                5.0);
      ++count;
    }
  }
  return count;
}

TEST(FuzzReplay, LogReader) { EXPECT_GT(replay("log_reader", fuzz::logReader), 0u); }
TEST(FuzzReplay, SensorsReader) { EXPECT_GT(replay("sensors_reader", fuzz::sensorsReader), 0u); }
TEST(FuzzReplay, UrdfLoader) { EXPECT_GT(replay("urdf_loader", fuzz::urdfLoader), 0u); }
TEST(FuzzReplay, UrdfPatcher) { EXPECT_GT(replay("urdf_patcher", fuzz::urdfPatcher), 0u); }

}  // namespace
}  // namespace stac
