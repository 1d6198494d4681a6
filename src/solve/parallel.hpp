// Deterministic parallel loops: work is cut into chunks whose boundaries do
// not depend on the thread count, and reductions are summed chunk by chunk in
// order, so results are bit-identical with 1 or N threads.
#pragma once

#include <algorithm>
#include <atomic>
#include <functional>
#include <thread>
#include <vector>

namespace stac {

// Number of threads to use for a request (0 = all cores).
inline int resolveThreads(int requested) {
  if (requested > 0) return requested;
  const unsigned hw = std::thread::hardware_concurrency();
  return hw == 0 ? 1 : static_cast<int>(hw);
}

// Calls body(chunk, thread) for chunk in [0, num_chunks) on `threads`
// threads; thread in [0, threads) identifies the caller's workspace.
// Exceptions from bodies are rethrown (the first one) after all join.
inline void parallelFor(int num_chunks, int threads,
                        const std::function<void(int chunk, int thread)>& body) {
  threads = std::max(1, std::min(threads, num_chunks));
  if (threads <= 1) {
    for (int c = 0; c < num_chunks; ++c) body(c, 0);
    return;
  }
  std::atomic<int> next{0};
  std::exception_ptr error;
  std::atomic<bool> failed{false};
  auto worker = [&](int tid) {
    for (int c; !failed && (c = next++) < num_chunks;) {
      try {
        body(c, tid);
      } catch (...) {
        if (!failed.exchange(true)) error = std::current_exception();
      }
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(worker, t);
  worker(0);
  for (std::thread& th : pool) th.join();
  if (error) std::rethrow_exception(error);
}

// Frames per chunk: fixed, so chunking is independent of the thread count.
constexpr int kFramesPerChunk = 16;
inline int numChunks(int frames) { return (frames + kFramesPerChunk - 1) / kFramesPerChunk; }

}  // namespace stac
