// SPDX-License-Identifier: MIT
#include "io/cleanup_on_signal.hpp"

#include <atomic>
#include <csignal>
#include <cstring>
#include <mutex>

#include <limits.h>
#include <unistd.h>

namespace vplrender {

namespace {

// One run publishes three outputs; a few spare slots for tests that hold several sets.
constexpr int slot_count = 16;
struct slot_entry {
  char path[PATH_MAX];
  std::atomic<int> used{0};  // 1 once `path` is complete; lock-free, so safe to read in a handler
};
slot_entry table[slot_count];
std::mutex table_mutex;  // between threads registering; never taken by the handler
static_assert(std::atomic<int>::is_always_lock_free, "the signal handler reads the table lock-free");

extern "C" void cleanup_and_reraise(int sig) {
  for (slot_entry& e : table)
    if (e.used.load(std::memory_order_acquire) == 1) ::unlink(e.path);
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

}  // namespace

void install_cleanup_on_signal() {
  static std::once_flag once;
  std::call_once(once, [] {
    for (int sig : {SIGINT, SIGTERM}) {
      struct sigaction sa {};
      sa.sa_handler = cleanup_and_reraise;
      sigemptyset(&sa.sa_mask);
      sa.sa_flags = SA_RESETHAND;
      ::sigaction(sig, &sa, nullptr);
    }
  });
}

cleanup_slot register_for_cleanup(const std::string& path) {
  if (path.size() >= PATH_MAX) return 0;
  std::lock_guard<std::mutex> lock(table_mutex);
  for (int i = 0; i < slot_count; ++i) {
    slot_entry& e = table[i];
    if (e.used.load(std::memory_order_relaxed) != 0) continue;
    std::memcpy(e.path, path.c_str(), path.size() + 1);
    e.used.store(1, std::memory_order_release);
    return i + 1;
  }
  return 0;
}

void unregister_cleanup(cleanup_slot slot) {
  if (slot < 1 || slot > slot_count) return;
  std::lock_guard<std::mutex> lock(table_mutex);
  table[slot - 1].used.store(0, std::memory_order_release);
}

}  // namespace vplrender
