// SPDX-License-Identifier: MIT
#include "app/progress.hpp"

#include <algorithm>
#include <cstdio>
#include <ostream>

#include <unistd.h>

namespace vplrender {

bool progress_enabled(progress_mode mode, int fd) {
  switch (mode) {
    case progress_mode::always: return true;
    case progress_mode::never: return false;
    case progress_mode::automatic: return ::isatty(fd) == 1;
  }
  return false;
}

progress_bar::progress_bar(std::string label, std::uint64_t total, bool enabled, std::ostream& out,
                           std::chrono::duration<double> delay)
    : label_(std::move(label)), total_(total), enabled_(enabled), out_(out), delay_(delay),
      start_(std::chrono::steady_clock::now()) {}

progress_bar::~progress_bar() {
  try {
    finish();
  } catch (...) {  // a destructor must not throw; a failed progress line is not worth a crash
  }
}

void progress_bar::draw(std::uint64_t done, double elapsed) {
  const double frac = total_ == 0 ? 1.0 : std::min(1.0, static_cast<double>(done) / static_cast<double>(total_));
  constexpr int width = 30;
  const int filled = static_cast<int>(frac * width);
  char pct[64];
  std::snprintf(pct, sizeof pct, "] %3d%% %.1fs", static_cast<int>(frac * 100.0), elapsed);
  out_ << '\r' << label_ << " [" << std::string(static_cast<std::size_t>(filled), '#')
       << std::string(static_cast<std::size_t>(width - filled), '.') << pct << std::flush;
  shown_ = true;
  last_draw_ = elapsed;
}

void progress_bar::update(std::uint64_t done) {
  done_ = done;
  if (!enabled_ || finished_) return;
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  if (elapsed < delay_.count()) return;
  if (shown_ && elapsed - last_draw_ < 0.1) return;
  draw(done, elapsed);
}

void progress_bar::finish() {
  if (finished_) return;
  finished_ = true;
  if (!enabled_) return;
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  if (!shown_ && elapsed < delay_.count()) return;
  draw(done_, elapsed);
  out_ << '\n' << std::flush;
}

}  // namespace vplrender
