// SPDX-License-Identifier: MIT
#pragma once
// A one-line progress bar on stderr. It appears only once a run has lasted `delay` (1 s by
// default), so short runs print nothing, and redraws at most ten times a second. With
// progress_mode::automatic it is shown only when stderr is a terminal: a log file gets no
// carriage-return noise.
#include "cli/options.hpp"

#include <chrono>
#include <cstdint>
#include <iosfwd>
#include <string>

namespace vplrender {

// always -> true, never -> false, automatic -> isatty(fd).
bool progress_enabled(progress_mode mode, int fd = 2);

class progress_bar {
public:
  progress_bar(std::string label, std::uint64_t total, bool enabled, std::ostream& out,
               std::chrono::duration<double> delay = std::chrono::seconds(1));
  ~progress_bar();  // calls finish()
  progress_bar(const progress_bar&) = delete;
  progress_bar& operator=(const progress_bar&) = delete;

  void update(std::uint64_t done);  // from one thread
  // Draws the final state (if the bar is showing, or the run has outlasted the delay) and ends
  // the line. Idempotent.
  void finish();
  bool shown() const { return shown_; }

private:
  void draw(std::uint64_t done, double elapsed);

  std::string label_;
  std::uint64_t total_;
  std::uint64_t done_ = 0;
  bool enabled_;
  bool shown_ = false;
  bool finished_ = false;
  std::ostream& out_;
  std::chrono::duration<double> delay_;
  std::chrono::steady_clock::time_point start_;
  double last_draw_ = -1.0;
};

}  // namespace vplrender
