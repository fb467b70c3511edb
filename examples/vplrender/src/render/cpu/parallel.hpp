// SPDX-License-Identifier: MIT
#pragma once
// The CPU backend's threads: items (image rows, texel blocks) handed out one at a time to a pool
// of std::threads, with progress reported from the calling thread.
#include "render/settings.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace vplrender {

// The threads for `requested` (0: std::thread::hardware_concurrency(), at least 1).
inline int thread_count(int requested) {
  if (requested > 0) return requested;
  const unsigned h = std::thread::hardware_concurrency();
  return h > 0 ? static_cast<int>(h) : 1;
}

// Runs work(item, worker) for item in [0, n) on `threads` workers, handing out items one at a
// time (items are rows or blocks: coarse enough). The calling thread reports progress every
// 50 ms and wakes as soon as the last worker stops (a plain sleep would round every stage up to
// 50 ms steps, which the stage times report). The first exception of any worker is rethrown after
// all have stopped.
template <class Work>
void parallel_items(int n, int threads, const std::string& label, const progress_fn& progress, Work&& work) {
  std::atomic<int> next{0}, done{0};
  std::atomic<bool> failed{false};
  std::exception_ptr error;
  std::mutex error_mutex;
  std::mutex wake_mutex;
  std::condition_variable wake;
  int running = 0;  // workers that have not stopped (under wake_mutex)
  std::vector<std::thread> pool;
  const int t = std::max(1, std::min(threads, n));
  running = t;
  for (int k = 0; k < t; ++k)
    pool.emplace_back([&, k] {
      for (;;) {
        const int i = next.fetch_add(1);
        if (i >= n || failed.load()) break;
        try {
          work(i, k);
        } catch (...) {
          std::lock_guard<std::mutex> lock(error_mutex);
          if (!error) error = std::current_exception();
          failed = true;
        }
        done.fetch_add(1);
      }
      std::lock_guard<std::mutex> lock(wake_mutex);
      if (--running == 0) wake.notify_one();
    });
  if (progress) {
    std::unique_lock<std::mutex> lock(wake_mutex);
    while (running > 0) {
      lock.unlock();
      progress(label, static_cast<std::uint64_t>(done.load()), static_cast<std::uint64_t>(n));
      lock.lock();
      wake.wait_for(lock, std::chrono::milliseconds(50), [&] { return running == 0; });
    }
  }
  for (std::thread& th : pool) th.join();
  if (error) std::rethrow_exception(error);
  if (progress) progress(label, static_cast<std::uint64_t>(n), static_cast<std::uint64_t>(n));
}

}  // namespace vplrender
