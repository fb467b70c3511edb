// SPDX-License-Identifier: MIT
#pragma once
// Which pipeline stage is running, under the names the stage timer reports (render/stage_timer.hpp),
// so that a failure deep inside a stage can say where it happened. The innermost stage that an
// exception left is kept as failed_stage(): by the time main() catches a std::bad_alloc the marks
// have unwound, and that is the name it prints.
#include <cstddef>
#include <new>
#include <stdexcept>
#include <string>
#include <utility>

namespace vplrender {

// The innermost stage now running ("" outside every stage).
const std::string& running_stage();
// The innermost stage an exception propagated out of since the last stage began ("" when none did).
const std::string& failed_stage();

// Marks `name` as running for its lifetime (stages nest; the previous one comes back).
class stage_mark {
public:
  explicit stage_mark(std::string name);
  ~stage_mark();
  stage_mark(const stage_mark&) = delete;
  stage_mark& operator=(const stage_mark&) = delete;

private:
  std::string previous_;
  std::string name_;
  int uncaught_at_entry_;
};

// A host or GPU allocation that failed, with where and how much: "<stage>: out of memory
// allocating N MiB for <what>". Exit code 1.
class out_of_memory_error : public std::runtime_error {
public:
  out_of_memory_error(const std::string& stage, std::size_t bytes, const std::string& what);
};

// "12.5 MiB" (one decimal; "< 0.1 MiB" below that).
std::string mebibytes(std::size_t bytes);

namespace detail {
[[noreturn]] void throw_out_of_memory(std::size_t bytes, const char* what);
// The test fault hook: true when VPLKIT_TEST_FAIL_ALLOC names the running stage. Read here only.
bool test_fails_allocation();
}  // namespace detail

// Runs make(), an allocation of about `bytes` for `what` (host memory or a GL buffer); a
// std::bad_alloc or a GL_OUT_OF_MEMORY becomes out_of_memory_error naming the running stage.
template <class Make>
auto allocating(std::size_t bytes, const char* what, Make&& make) -> decltype(make()) {
  if (detail::test_fails_allocation()) detail::throw_out_of_memory(bytes, what);
  try {
    return std::forward<Make>(make)();
  } catch (const std::bad_alloc&) {
    detail::throw_out_of_memory(bytes, what);
  }
}

}  // namespace vplrender
