// Ctrl-C (SIGINT) and SIGTERM in the stac_* apps (SPEC §4): never a partial
// output nor a temporary file left behind; exit 128 + the signal's number
// (130, 143) with one line on stderr.
//
// runApp installs the handlers. Outside a DeferInterrupts scope nothing is
// being written, so the handler prints the line and ends the process at
// once (_exit). Inside one (a calibration that polls interruptRequested()
// through CalibrationOptions::should_stop, and every phase that writes
// files) it only records the signal: the work stops at its next poll
// (throwIfInterrupted(), or the library's stac::Cancelled) or at the end of
// the outermost scope. An app wraps all its writes in one scope and polls
// once before the first: every output is written, or none.
#pragma once

#include <stdexcept>
#include <string>

namespace stac::cli {

struct Interrupted : std::runtime_error {
  explicit Interrupted(int signal_number)
      : std::runtime_error("interrupted"), signal(signal_number) {}
  int signal;
};

// SIGINT and SIGTERM handlers for the app named `app`.
void installInterruptHandlers(const std::string& app);

// The signal received inside a DeferInterrupts scope, 0 if none.
int pendingInterrupt();
inline bool interruptRequested() { return pendingInterrupt() != 0; }
// Throws Interrupted if a signal is pending.
void throwIfInterrupted();

// While one exists, a signal is recorded instead of ending the process; the
// outermost one ends the process (reportInterrupt's line, exit 128 + signal)
// on leaving if a signal is pending.
class DeferInterrupts {
 public:
  DeferInterrupts();
  ~DeferInterrupts();
  DeferInterrupts(const DeferInterrupts&) = delete;
  DeferInterrupts& operator=(const DeferInterrupts&) = delete;
};

// Called by writeOutput before each write: from then on an interrupt says
// the outputs were written (the app's scope completes them all).
void markOutputsStarted();

// Prints "stac_calib: interrupted by SIGINT: no output written" (or "...:
// the outputs were written in full") and returns the exit code, 128 + signal.
int reportInterrupt(const std::string& app, int signal_number);

}  // namespace stac::cli
