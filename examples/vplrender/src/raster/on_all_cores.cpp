// SPDX-License-Identifier: MIT
#include "raster/on_all_cores.hpp"

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <thread>
#include <vector>

namespace vplrender {

chunk_plan plan_chunks(std::size_t n) {
  chunk_plan p;
  const std::size_t hw = std::max(1u, std::thread::hardware_concurrency());
  p.chunk = n / (4 * hw) + 1;
  p.chunks = (n + p.chunk - 1) / p.chunk;
  p.threads = std::max<std::size_t>(1, std::min(hw, p.chunks));
  return p;
}

void run_chunks(const chunk_plan& plan, const std::function<void(std::size_t)>& work) {
  std::atomic<std::size_t> next{0};
  std::exception_ptr failure;
  std::mutex failure_mutex;
  auto worker = [&] {
    for (std::size_t c = next++; c < plan.chunks; c = next++) {
      try {
        work(c);
      } catch (...) {
        const std::lock_guard<std::mutex> lock(failure_mutex);
        if (!failure) failure = std::current_exception();
      }
    }
  };
  std::vector<std::thread> pool;
  for (std::size_t k = 1; k < plan.threads; ++k) pool.emplace_back(worker);
  worker();
  for (std::thread& t : pool) t.join();
  if (failure) std::rethrow_exception(failure);
}

}  // namespace vplrender
