// SPDX-License-Identifier: MIT
// The stderr progress bar: silent when disabled or before its delay, complete when finished.
// (No timing is measured: the delays used are 0 and "never".)
#include <catch2/catch.hpp>

#include "app/progress.hpp"

#include <chrono>
#include <sstream>

using namespace vplrender;

TEST_CASE("progress_enabled follows the mode") {
  CHECK(progress_enabled(progress_mode::always, 2));
  CHECK_FALSE(progress_enabled(progress_mode::never, 2));
  CHECK_FALSE(progress_enabled(progress_mode::automatic, -1));  // not a terminal
}

TEST_CASE("a disabled bar prints nothing") {
  std::ostringstream out;
  {
    progress_bar bar("render", 10, false, out, std::chrono::seconds(0));
    for (int i = 0; i <= 10; ++i) bar.update(static_cast<std::uint64_t>(i));
  }
  CHECK(out.str().empty());
}

TEST_CASE("a run shorter than the delay prints nothing") {
  std::ostringstream out;
  {
    progress_bar bar("render", 10, true, out, std::chrono::hours(1000));
    for (int i = 0; i <= 10; ++i) bar.update(static_cast<std::uint64_t>(i));
    bar.finish();
    CHECK_FALSE(bar.shown());
  }
  CHECK(out.str().empty());
}

TEST_CASE("past its delay the bar draws, and finish ends the line at 100%") {
  std::ostringstream out;
  progress_bar bar("render", 200, true, out, std::chrono::seconds(0));
  bar.update(50);
  CHECK(bar.shown());
  CHECK(out.str().find("render [") != std::string::npos);
  CHECK(out.str().find(" 25%") != std::string::npos);
  bar.update(200);
  bar.finish();
  const std::string s = out.str();
  CHECK(s.find("100%") != std::string::npos);
  CHECK(s.back() == '\n');
  CHECK(s.find("##############################]") != std::string::npos);
  bar.finish();  // idempotent
  CHECK(out.str() == s);
}

TEST_CASE("a zero-length job and an overshoot stay within 0..100%") {
  std::ostringstream out;
  {
    progress_bar bar("x", 0, true, out, std::chrono::seconds(0));
    bar.update(5);
  }
  CHECK(out.str().find("100%") != std::string::npos);
  CHECK(out.str().find("200%") == std::string::npos);
}
