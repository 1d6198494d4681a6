// Method::kMonolithic: the alternation's start, then the monolithic problem with
// variance adaptation around it: solve, re-estimate σ, solve again until σ
// settles.
#include <algorithm>

#include "methods/alternation.hpp"
#include "methods/monolithic.hpp"

namespace stac {

Outcome runMonolithic(const MethodInput& in) {
  const Problem& problem = in.problem;
  const CalibrationOptions& options = in.options;
  Workspaces ws = makeWorkspaces(problem.model, problem.threads);
  Start start = startRun(in, false, &ws);
  State& s = start.state;
  int iterations = 0;
  bool converged = false;
  PassStats st = start.st;
  for (int round = 0; round < (options.adapt_variance ? 5 : 1); ++round) {
    int its = 0;
    solveMonolithic(problem.model, s.noise, problem.loss, problem.obs, options, &s.theta, &s.q,
                      &its, &converged);
    iterations += its;
    st = costPass(problem, s.theta, s.noise, s.q.q, options.adapt_variance, &ws);
    if (options.progress) options.progress(makeReport(round + 1, st, in.start, "joint", &s.theta));
    if (!options.adapt_variance) break;
    if (adaptAndRescore(problem, &s, &ws, &st) < 1e-4) break;
  }
  Outcome out = finishRun(problem, &start, st, &ws);
  out.iterations = iterations;
  out.converged = converged;
  return out;
}

}  // namespace stac
