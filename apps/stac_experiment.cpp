// stac_experiment: the paper's experiments re-run on the bundled robots
// (EXPERIMENTS.md). Each writes CSV and SVG into --out and prints a
// Markdown summary on stdout.
#include <chrono>
#include <iostream>
#include <algorithm>
#include <cstdlib>
#include <sys/stat.h>

#include "common/cli.hpp"
#include "experiments/run.hpp"

#ifndef STAC_DATA_DIR
#define STAC_DATA_DIR "data"
#endif

namespace stac::experiments {

void progressLine(const Context&, const std::string& text) { std::cerr << text << std::endl; }

namespace {

// The numeric value of attribute `name` in the first tag of `svg`, or
// `fallback`.
double rootAttribute(const std::string& svg, const std::string& name, double fallback) {
  const size_t end = svg.find('>');
  const size_t at = svg.find(" " + name + "=\"");
  if (at == std::string::npos || at > end) return fallback;
  return std::atof(svg.c_str() + at + name.size() + 3);
}

}  // namespace

std::string stackSvg(const std::vector<std::string>& parts) {
  // Each part's own width/height attributes place it below the previous one.
  double y = 0, width = 0;
  std::string body;
  for (const std::string& p : parts) {
    const double w = rootAttribute(p, "width", 600), h = rootAttribute(p, "height", 320);
    body += "<g transform=\"translate(0," + std::to_string(static_cast<int>(y)) + ")\">" + p + "</g>\n";
    y += h + 10;
    width = std::max(width, w);
  }
  return "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" +
         std::to_string(static_cast<int>(width)) + "\" height=\"" +
         std::to_string(static_cast<int>(y)) + "\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n" +
         body + "</svg>\n";
}

}  // namespace stac::experiments

namespace {

using namespace stac;

const std::vector<cli::Option> kOptions = {
    {"run", "fig6|fig7|tables|all", "which experiment", true},
    {"out", "DIR", "folder for the CSV and SVG files (must exist)", true},
    {"data", "DIR", "the bundled robots (default: the source tree's data/)"},
    {"size", "smoke|full", "smoke: a few seconds, to check the pipeline (default full)"},
    {"threads", "N", "worker threads; 0 = all cores (default)"},
    {"seed", "S", "random seed (default 1)"},
};

const char* kSynopsis =
    "stac_experiment --run fig6|fig7|tables|all --out DIR [--size smoke|full]\n\n"
    "Re-runs the paper's experiments on the bundled robots: Fig. 6 (q-phase\n"
    "strategies), Fig. 7 (STAC vs EKF over seeding error x noise), Tables I/II\n"
    "(cross-sensor prediction on held-out data against manual and classical\n"
    "calibration). Writes <experiment>.csv and .svg into DIR and prints Markdown.";

int run(const cli::Args& args) {
  experiments::Context context;
  context.out_dir = args.get("out");
  context.data_dir = args.get("data", STAC_DATA_DIR);
  context.smoke = args.getChoice("size", {"smoke", "full"}, "full") == "smoke";
  context.threads = args.getIntAtLeast("threads", 0, 0, "0 = all cores");
  context.seed = args.getUnsigned("seed", 1);
  struct stat st;
  if (stat(context.out_dir.c_str(), &st) != 0 || !S_ISDIR(st.st_mode))
    throw cli::UsageError(args.typed("out") + ": not an existing folder");
  const std::string which = args.getChoice("run", {"fig6", "fig7", "tables", "all"}, "all");
  const auto start = std::chrono::steady_clock::now();
  if (which == "fig6" || which == "all") std::cout << experiments::runFig6(context) << std::endl;
  if (which == "fig7" || which == "all") std::cout << experiments::runFig7(context) << std::endl;
  if (which == "tables" || which == "all") std::cout << experiments::runTables(context) << std::endl;
  std::cerr << "done in "
            << std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count()
            << " s" << std::endl;
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  return stac::cli::runApp(argc, argv, "stac_experiment", kSynopsis, kOptions, run);
}
