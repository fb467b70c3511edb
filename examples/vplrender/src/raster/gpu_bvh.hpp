// SPDX-License-Identifier: MIT
#pragma once
// The scene's BVH for the GPU backend's exact visibility (--visibility exact): built on the host by
// the pack's binned-SAH builder (vplkit::build_bvh_soup, include/vplkit/visibility/bvh_build.hpp)
// and uploaded once per frame beside the other scene buffers, in the layout
// glsl/vplkit/visibility/bvh_layout.glsl reads (nodes, triangles; two std430 arrays).
#include "scene/scene.hpp"

#include <headless_gl/compute.hpp>

#include <cstdint>

namespace vplrender {

struct gpu_bvh {
  vplkit::gl::buffer nodes;      // vplkit_bvh_node[], at least one entry (Mesa binds no empty buffer)
  vplkit::gl::buffer triangles;  // vplkit_bvh_triangle[], at least one entry
  std::uint32_t node_count = 0;  // 0: empty hierarchy, every query misses
  std::uint32_t triangle_count = 0;
  int depth = 0;
  // Loop iterations one query may spend (nodes visited + triangles tested), what the GPU backend
  // budgets per query under llvmpipe's loop limit (docs/glsl.md): node_count + triangle_count, a
  // strict bound, capped at 1024 for large scenes (docs/glsl/bvh.md measures at most 146 per query
  // over the parity rays and about 25 in a 97k-triangle scene).
  long long query_cost = 1;
};

// Builds and uploads (needs the current GL context). Throws vplkit::invalid_input for geometry the
// builder refuses (non-finite vertices).
gpu_bvh upload_scene_bvh(const scene& s);

}  // namespace vplrender
