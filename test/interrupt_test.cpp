// The apps' signal handling (apps/common/interrupt.hpp) in-process: inside
// a DeferInterrupts scope a signal is only recorded; the outermost scope
// ends the process on leaving (exit 128 + signal, one line); outside any
// scope the handler ends it at once. Death tests: each runs in a child.
#include <gtest/gtest.h>

#include <csignal>

#include "common/interrupt.hpp"

namespace stac::cli {
namespace {

TEST(InterruptDeathTest, OutsideAScopeEndsAtOnce) {
  EXPECT_EXIT(
      {
        installInterruptHandlers("app");
        std::raise(SIGINT);
        std::_Exit(0);  // not reached
      },
      ::testing::ExitedWithCode(130), "^app: interrupted by SIGINT: no output written\n$");
}

// A signal while the outputs are written: they finish (here the scope's
// body goes on after the signal), then the process ends saying so.
TEST(InterruptDeathTest, DuringWritesEveryOutputFinishesFirst) {
  EXPECT_EXIT(
      {
        installInterruptHandlers("app");
        {
          const DeferInterrupts writing;
          markOutputsStarted();
          std::raise(SIGTERM);
          if (pendingInterrupt() != SIGTERM) std::_Exit(1);
          {
            const DeferInterrupts nested;  // leaving an inner scope does not end it
          }
          std::fputs("second output written\n", stderr);
        }
        std::_Exit(0);  // not reached
      },
      ::testing::ExitedWithCode(143),
      "^second output written\napp: interrupted by SIGTERM: the outputs were written in full\n$");
}

// A poll inside the scope turns the signal into Interrupted (the app's
// runApp reports it); unwinding out of the scope does not end the process.
TEST(InterruptDeathTest, APollThrowsAndUnwindingLeavesTheReportToTheApp) {
  EXPECT_EXIT(
      {
        installInterruptHandlers("app");
        int code = 0;
        try {
          const DeferInterrupts polled;
          std::raise(SIGINT);
          throwIfInterrupted();
        } catch (const Interrupted& e) {
          code = reportInterrupt("app", e.signal);
        }
        std::_Exit(code);
      },
      ::testing::ExitedWithCode(130), "^app: interrupted by SIGINT: no output written\n$");
}

}  // namespace
}  // namespace stac::cli
