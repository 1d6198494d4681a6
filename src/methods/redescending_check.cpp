#include "methods/redescending_check.hpp"

#include <cmath>
#include <cstdio>
#include <utility>

namespace stac {

double largestShiftInStd(const ThetaSpace& space, const SensorParameters& a,
                         const SensorParameters& b, const Eigen::VectorXd& std, int* which,
                         const Eigen::VectorXd* period) {
  const Eigen::VectorXd d = space.minus(a, b);
  double largest = 0;
  *which = -1;
  for (int i : space.freeIndex()) {
    if (!(std[i] > 0) || !std::isfinite(std[i])) continue;
    double di = d[i];
    if (period && (*period)[i] > 0) di -= (*period)[i] * std::round(di / (*period)[i]);
    const double z = std::abs(di) / std[i];
    if (z > largest) largest = z, *which = i;
  }
  return largest;
}

std::string lossDisagreement(const MeasurementModel& model, const Outcome& huber,
                             const CauchyFit& cauchy) {
  const ThetaSpace& space = model.thetaSpace();
  // A bias Cauchy's result knows only modulo a turn (turn_ambiguity.hpp):
  // a whole turn apart is the same fit.
  Eigen::VectorXd period = Eigen::VectorXd::Zero(space.size());
  for (const UnidentifiableDirection& u : cauchy.unidentifiable) {
    if (u.reason.find("modulo a turn") == std::string::npos || u.parameters.empty()) continue;
    for (int i = 0; i < space.size(); ++i)
      if (space.names()[i] == u.parameters[0] && space.entry(i).block == ThetaBlock::kJointSensor)
        period[i] = 2 * M_PI * std::abs(cauchy.theta.joint_sensor[space.entry(i).item].gain);
  }
  const Eigen::VectorXd std = huber.uncertainty.std.cwiseMax(cauchy.std);
  int which = -1;
  const double z = largestShiftInStd(space, huber.theta, cauchy.theta, std, &which, &period);
  if (z <= kLossShiftStd) return {};
  char buf[96];
  std::snprintf(buf, sizeof buf, "%.3g", z);
  const std::string what = space.ownerPhrase(which);  // "the mocap rotation", "bias of p"
  return "Huber's loss and the redescending Cauchy loss (same seed, same scale) disagree by " +
         std::string(buf) + " std on " + (what.rfind("the ", 0) == 0 ? "" : "the ") + what +
         ": gross readings bias Huber's fit here (a gross reading from the sensor that "
         "dominates its joint drags the frame's angle along); rerun with --loss cauchy";
}

std::string crossCheckWithCauchy(const MethodInput& in, const Outcome& huber) {
  const Problem& problem = in.problem;
  const RobustLoss cauchy(LossKind::kCauchy, problem.loss.scale());
  const Problem redescending{problem.model, problem.obs, problem.seed_noise, cauchy,
                             problem.threads};
  CalibrationOptions options = in.options;
  options.loss = LossKind::kCauchy;
  if (in.options.progress)
    options.progress = [&](const IterationReport& r) {
      IterationReport c = r;
      c.stage = "check";
      in.options.progress(c);
    };
  const MethodInput check{redescending, in.seed, options, in.start, in.q0};
  // Cauchy's loss is not convex: its run may end in a wrong minimum, which
  // says nothing about Huber's. So Huber's fit is judged only against a
  // Cauchy fit that passes every check of its own. (Their costs do not
  // tell: with σ adapted neither run ends at its loss's exact minimum, and
  // where both reach the truth Huber's end often fits Cauchy's problem
  // better than Cauchy's end does.)
  Outcome outcome = runStac(check);
  const Eigen::VectorXd std = outcome.uncertainty.std;
  const CalibrationResult other = makeResult(check, std::move(outcome), nullptr);
  if (!other.summary.verdict.empty()) return {};
  return lossDisagreement(problem.model, huber, {other.theta, std, other.summary.unidentifiable});
}

}  // namespace stac
