// readLog on a 25,000-row x 140-column CSV (a time column and 139 sensor
// columns: 45 markers' x/y/z and 4 potentiometers, ~5% empty cells), the
// size SPEC §2's reader must handle well under a second. Also parseLog
// alone (no file read) and writeLog.
//   build/test/io_bench --benchmark_repetitions=9 --benchmark_report_aggregates_only=true
#include <benchmark/benchmark.h>

#include <random>
#include <string>

#include "stac/file_io.hpp"
#include "stac/log.hpp"
#include "support/test_util.hpp"

namespace {

using namespace stac;

constexpr int kRows = 25000;
constexpr int kMarkers = 45;
constexpr int kPots = 4;  // 1 + 3*45 + 4 = 140 columns

struct Fixture {
  test::TempDir dir;
  std::string path = dir.file("log.csv");
  std::string text;
  Fixture() {
    std::mt19937_64 rng(1);
    std::uniform_real_distribution<double> u(-1.5, 1.5);
    std::uniform_int_distribution<int> drop(0, 19);
    Log log;
    log.time_name = "time";
    for (int m = 0; m < kMarkers; ++m)
      for (const char* axis : {".x", ".y", ".z"})
        log.columns.push_back("m_" + std::to_string(m) + axis);
    for (int p = 0; p < kPots; ++p) log.columns.push_back("pot_" + std::to_string(p));
    log.values.resize(kRows, static_cast<Eigen::Index>(log.columns.size()));
    for (int t = 0; t < kRows; ++t) {
      log.time.push_back(0.01 * t);
      for (Eigen::Index c = 0; c < log.values.cols(); ++c)
        log.values(t, c) = drop(rng) == 0 ? std::numeric_limits<double>::quiet_NaN() : u(rng);
    }
    writeLog(path, log);
    text = readTextFile(path);
  }
};

Fixture& fixture() {
  static Fixture f;
  return f;
}

void BM_ReadLog(benchmark::State& state) {
  Fixture& f = fixture();
  for (auto _ : state) {
    Log log = readLog(f.path);
    benchmark::DoNotOptimize(log.values.data());
  }
  state.counters["MB"] = static_cast<double>(f.text.size()) / 1e6;
  state.counters["cells/s"] = benchmark::Counter(static_cast<double>(kRows) * 140,
                                                 benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_ReadLog)->Unit(benchmark::kMillisecond);

void BM_ParseLog(benchmark::State& state) {
  Fixture& f = fixture();
  for (auto _ : state) {
    Log log = parseLog(f.text, f.path);
    benchmark::DoNotOptimize(log.values.data());
  }
}
BENCHMARK(BM_ParseLog)->Unit(benchmark::kMillisecond);

void BM_WriteLog(benchmark::State& state) {
  Fixture& f = fixture();
  const Log log = parseLog(f.text, f.path);
  const std::string out = f.dir.file("out.csv");
  for (auto _ : state) writeLog(out, log);
}
BENCHMARK(BM_WriteLog)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
