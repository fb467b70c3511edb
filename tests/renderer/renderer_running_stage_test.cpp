// SPDX-License-Identifier: MIT
// "Out of memory" names the stage and the size: the running stage under the stage timer's names,
// the stage an exception left, allocating()'s message and its test fault hook.
#include "render/running_stage.hpp"
#include "render/stage_timer.hpp"

#include <catch2/catch.hpp>

#include <cstdlib>
#include <functional>
#include <new>
#include <stdexcept>
#include <string>

using namespace vplrender;

namespace {
struct fail_alloc_env {
  explicit fail_alloc_env(const char* stage) { ::setenv("VPLKIT_TEST_FAIL_ALLOC", stage, 1); }
  ~fail_alloc_env() { ::unsetenv("VPLKIT_TEST_FAIL_ALLOC"); }
};
std::string message_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const out_of_memory_error& e) {
    return e.what();
  }
  return "(no out_of_memory_error)";
}
}  // namespace

TEST_CASE("stage marks nest under the stage timer's names", "[renderer][memory]") {
  stage_timer timer;
  CHECK(running_stage().empty());
  {
    auto t = timer.scoped("estimate (cpu)");
    CHECK(running_stage() == "estimate (cpu)");
    {
      auto m = stage_timer::running("cdf (gpu)");
      CHECK(running_stage() == "cdf (gpu)");
    }
    CHECK(running_stage() == "estimate (cpu)");
  }
  CHECK(running_stage().empty());
  REQUIRE(timer.stages().size() == 1);
  CHECK(timer.stages()[0].name == "estimate (cpu)");
}

TEST_CASE("the innermost stage an exception leaves is kept for main()", "[renderer][memory]") {
  stage_timer timer;
  try {
    auto outer = timer.scoped("scene upload (cpu)");
    { auto done = stage_timer::running("voxelize (gpu)"); }  // finished normally: not blamed
    auto inner = stage_timer::running("dprsm (gpu)");
    throw std::bad_alloc();
  } catch (const std::bad_alloc&) {
    CHECK(running_stage().empty());
    CHECK(failed_stage() == "dprsm (gpu)");
  }
  {
    auto next = stage_timer::running("gbuffer (gpu)");  // a new stage: the handled failure is gone
    CHECK(failed_stage().empty());
  }
  try {
    auto outer = stage_timer::running("estimate (gpu)");
    { auto done = stage_timer::running("cdf (gpu)"); }
    throw std::runtime_error("after the inner stage");
  } catch (const std::runtime_error&) {
    CHECK(failed_stage() == "estimate (gpu)");
  }
}

TEST_CASE("allocating: a std::bad_alloc names the stage, the size and what", "[renderer][memory]") {
  auto m = stage_timer::running("scene upload (cpu)");
  const std::string msg = message_of([] {
    allocating(std::size_t(3) << 20, "the G-buffer surfels", []() -> int { throw std::bad_alloc(); });
  });
  CHECK(msg == "scene upload (cpu): out of memory allocating 3.0 MiB for the G-buffer surfels");
  // A successful allocation passes its value through.
  CHECK(allocating(16, "x", [] { return 42; }) == 42);
}

TEST_CASE("allocating outside every stage says 'setup'", "[renderer][memory]") {
  const std::string msg =
      message_of([] { allocating(1536, "a table", []() -> int { throw std::bad_alloc(); }); });
  CHECK(msg == "setup: out of memory allocating < 0.1 MiB for a table");
}

TEST_CASE("VPLKIT_TEST_FAIL_ALLOC fails the allocations of the stage it names, only those", "[renderer][memory]") {
  fail_alloc_env env("estimate (gpu)");
  int made = 0;
  {
    auto m = stage_timer::running("cdf (gpu)");
    CHECK(allocating(8, "x", [&] { return ++made; }) == 1);
  }
  auto m = stage_timer::running("estimate (gpu)");
  const std::string msg = message_of([&] {
    allocating(std::size_t(5) << 19, "the per-pixel estimates", [&] { return ++made; });
  });
  CHECK(msg == "estimate (gpu): out of memory allocating 2.5 MiB for the per-pixel estimates");
  CHECK(made == 1);  // the hook fails before the allocation is attempted
}

TEST_CASE("mebibytes: one decimal", "[renderer][memory]") {
  CHECK(mebibytes(0) == "< 0.1 MiB");
  CHECK(mebibytes(std::size_t(1) << 20) == "1.0 MiB");
  CHECK(mebibytes(std::size_t(3) << 30) == "3072.0 MiB");
}
