// SPDX-License-Identifier: MIT
#pragma once
// allocating() (render/running_stage.hpp) for GL buffers: a GL_OUT_OF_MEMORY from the driver reads
// like a failed host allocation, "<stage>: out of memory allocating N MiB for <what>".
#include "render/running_stage.hpp"

#include <headless_gl/compute.hpp>

#include <new>
#include <utility>

namespace vplrender {

template <class Make>
auto gpu_allocating(std::size_t bytes, const char* what, Make&& make) -> decltype(make()) {
  return allocating(bytes, what, [&]() -> decltype(make()) {
    try {
      return std::forward<Make>(make)();
    } catch (const vplkit::gl::gl_out_of_memory&) {
      throw std::bad_alloc();
    }
  });
}

}  // namespace vplrender
