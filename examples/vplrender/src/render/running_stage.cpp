// SPDX-License-Identifier: MIT
#include "render/running_stage.hpp"

#include <cstdio>
#include <cstdlib>
#include <exception>

namespace vplrender {

namespace {
// The pipeline runs its stages on one thread (the CPU backend's worker threads run inside one).
std::string& running() {
  static std::string s;
  return s;
}
std::string& failed() {
  static std::string s;
  return s;
}
}  // namespace

const std::string& running_stage() { return running(); }
const std::string& failed_stage() { return failed(); }

stage_mark::stage_mark(std::string name)
    : previous_(std::exchange(running(), name)), name_(std::move(name)), uncaught_at_entry_(std::uncaught_exceptions()) {
  failed().clear();  // a stage starts: an earlier failure was handled
}

stage_mark::~stage_mark() {
  if (std::uncaught_exceptions() > uncaught_at_entry_ && failed().empty()) failed() = name_;
  running() = std::move(previous_);
}

std::string mebibytes(std::size_t bytes) {
  const double mib = static_cast<double>(bytes) / (1024.0 * 1024.0);
  if (mib < 0.1) return "< 0.1 MiB";
  char text[64];
  std::snprintf(text, sizeof text, "%.1f MiB", mib);
  return text;
}

out_of_memory_error::out_of_memory_error(const std::string& stage, std::size_t bytes, const std::string& what)
    : std::runtime_error((stage.empty() ? std::string("setup") : stage) + ": out of memory allocating " +
                         mebibytes(bytes) + " for " + what) {}

namespace detail {

void throw_out_of_memory(std::size_t bytes, const char* what) {
  throw out_of_memory_error(running_stage(), bytes, what);
}

bool test_fails_allocation() {
  const char* stage = std::getenv("VPLKIT_TEST_FAIL_ALLOC");
  return stage != nullptr && *stage != '\0' && running_stage() == stage;
}

}  // namespace detail

}  // namespace vplrender
