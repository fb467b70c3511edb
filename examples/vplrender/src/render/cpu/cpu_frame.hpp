// SPDX-License-Identifier: MIT
#pragma once
// What every CPU stage starts from: the frame's G-buffer and DPRSM as the library's views, checked
// once here (validate() names the bad buffer), the image size and the worker count.
#include "render/cpu/parallel.hpp"
#include "render/frame_buffers.hpp"
#include "render/settings.hpp"

#include <vplkit/core/error.hpp>

namespace vplrender {

struct cpu_frame {
  vplkit::gbuffer_view<float> g;
  vplkit::dprsm_view<float> view;
  int threads;
  int W, H;
};

inline cpu_frame open_cpu_frame(const frame_buffers& b, const render_settings& s) {
  if (!b.has_host_copies() && b.gpu)
    throw vplkit::invalid_input("the CPU backend: the frame's G-buffer and DPRSM are on the GPU only (prepared for "
                                "--backend gpu; read_back_host_copies brings them to the host)");
  cpu_frame f{b.gbuf.view(), b.dprsm.view(), thread_count(s.threads), 0, 0};
  f.g.validate();
  f.view.validate();
  f.W = f.g.width;
  f.H = f.g.height;
  return f;
}

}  // namespace vplrender
