// The experiments of stac_experiment, one function each. Each writes its
// CSV and SVG into context.out_dir and returns its Markdown summary.
#pragma once

#include <string>
#include <vector>

#include "experiments/experiment.hpp"

namespace stac::experiments {

std::string runFig6(const Context& context);    // q-phase strategies
std::string runFig7(const Context& context);    // STAC vs EKF robustness grid
std::string runTables(const Context& context);  // Tables I/II: cross-sensor prediction

// A line on stderr so long runs show progress.
void progressLine(const Context& context, const std::string& text);

// Several <svg> elements stacked vertically in one standalone SVG document.
std::string stackSvg(const std::vector<std::string>& parts);

}  // namespace stac::experiments
