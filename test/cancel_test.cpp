// CalibrationOptions::should_stop: every method stops with stac::Cancelled
// when it returns true, and a --method joint solve stops inside its Ceres
// solve (per iteration), not only at the next progress report.
#include <gtest/gtest.h>

#include "stac/calibrate.hpp"
#include "stac/error.hpp"
#include "support/arm_fixture.hpp"

namespace stac {
namespace {

struct Counts {
  int polls = 0, reports = 0;
};

// Runs `method` with should_stop true from its `stop_at`-th poll on.
bool cancelled(Method method, int stop_at, Counts* counts) {
  static const test::ArmProblem p = test::makeArmProblem(60, 3);
  CalibrationOptions o;
  o.method = method;
  o.threads = 1;
  o.tolerance = 0;
  o.progress = [counts](const IterationReport&) { ++counts->reports; };
  o.should_stop = [counts, stop_at] { return ++counts->polls >= stop_at; };
  try {
    calibrate(p.robot, p.sensors, p.seed, p.obs, o, nullptr, &p.q_true);
  } catch (const Cancelled&) {
    return true;
  }
  return false;
}

TEST(Cancel, EveryMethodStopsAtItsFirstPoll) {
  for (Method m : {Method::kStac, Method::kMonolithic, Method::kEkf, Method::kClassical}) {
    Counts c;
    EXPECT_TRUE(cancelled(m, 1, &c)) << static_cast<int>(m);
    EXPECT_EQ(c.polls, 1) << static_cast<int>(m);
    EXPECT_EQ(c.reports, 0) << "stopped before its first report";
  }
}

TEST(Cancel, StacStopsBetweenIterations) {
  Counts c;
  EXPECT_TRUE(cancelled(Method::kStac, 4, &c));
  EXPECT_EQ(c.polls, 4);
  EXPECT_GE(c.reports, 1);
}

// The joint method reports once before its first Ceres solve ("seed"); the
// third poll is the solve's second iteration: without the per-iteration
// callback it would be the report after the first solve, which would have
// reached the caller's progress first.
TEST(Cancel, JointStopsInsideTheCeresSolve) {
  Counts c;
  EXPECT_TRUE(cancelled(Method::kMonolithic, 3, &c));
  EXPECT_EQ(c.polls, 3);
  EXPECT_EQ(c.reports, 1);
}

}  // namespace
}  // namespace stac
