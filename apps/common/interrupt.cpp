#include "common/interrupt.hpp"

#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstring>
#include <exception>
#include <iostream>
#include <string>

namespace stac::cli {

namespace {
// Read and written by the handler: lock-free atomics (async-signal-safe),
// owned by the app, never by the library.
std::atomic<int> g_signal{0};
std::atomic<int> g_deferring{0};
std::atomic<int> g_written{0};
const char* g_app = "stac";
static_assert(std::atomic<int>::is_always_lock_free, "the signal handler needs lock-free ints");

const char* signalName(int s) {
  return s == SIGINT ? "SIGINT" : s == SIGTERM ? "SIGTERM" : "a signal";
}

const char* outcome() {
  return g_written.load() ? ": the outputs were written in full\n" : ": no output written\n";
}

void writeAll(const char* text) {
  size_t left = std::strlen(text);
  while (left > 0) {
    const ssize_t n = ::write(STDERR_FILENO, text, left);
    if (n <= 0) return;
    text += n;
    left -= static_cast<size_t>(n);
  }
}

// The one line and the exit, with async-signal-safe calls only.
[[noreturn]] void endNow(int s) {
  writeAll(g_app);
  writeAll(": interrupted by ");
  writeAll(signalName(s));
  writeAll(outcome());
  ::_exit(128 + s);
}

extern "C" void onSignal(int s) {
  int none = 0;
  g_signal.compare_exchange_strong(none, s);  // the first signal names the exit
  if (g_deferring.load() == 0) endNow(g_signal.load());
}
}  // namespace

void installInterruptHandlers(const std::string& app) {
  static std::string name;  // outlives every signal the process can receive
  name = app;
  g_app = name.c_str();
  struct sigaction sa;
  std::memset(&sa, 0, sizeof sa);
  sa.sa_handler = onSignal;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESTART;  // a deferred signal must not fail a write with EINTR
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

int pendingInterrupt() { return g_signal.load(); }

void throwIfInterrupted() {
  if (const int s = pendingInterrupt()) throw Interrupted(s);
}

void markOutputsStarted() { g_written.store(1); }

DeferInterrupts::DeferInterrupts() { g_deferring.fetch_add(1); }

DeferInterrupts::~DeferInterrupts() {
  // Leaving the outermost scope with a signal pending (it came after the
  // last poll): end as the handler would have. During unwinding the
  // exception's own path reports it instead.
  if (g_deferring.fetch_sub(1) == 1 && pendingInterrupt() && std::uncaught_exceptions() == 0) {
    std::cout.flush();
    endNow(pendingInterrupt());
  }
}

int reportInterrupt(const std::string& app, int signal_number) {
  std::cerr << app << ": interrupted by " << signalName(signal_number) << outcome();
  return 128 + signal_number;
}

}  // namespace stac::cli
