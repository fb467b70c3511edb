// SPDX-License-Identifier: MIT
#include "render/gpu/gpu_share_tree.hpp"

#include <vplkit/core/error.hpp>
#include <vplkit/distribution/share_tree.hpp>
#include <vplkit/distribution/share_tree_build_params.h>

#include <algorithm>
#include <cmath>
#include <string>

namespace vplrender {

namespace gl = vplkit::gl;

gpu_share_trees build_share_trees_gpu(const gl::buffer& weights, int D, std::size_t n, stage_timer& timer,
                                      nlohmann::json& det) {
  auto running = stage_timer::running("share tree (gpu)");
  if (D < 1 || n == 0) throw vplkit::invalid_input("build_share_trees_gpu: no weights");
  if (n > (std::size_t(1) << 31))
    throw vplkit::invalid_input("build_share_trees_gpu: " + std::to_string(n) + " weights per tree; at most 2^31");
  if (weights.size_bytes() < static_cast<std::size_t>(D) * n * sizeof(float))
    throw vplkit::invalid_input("build_share_trees_gpu: the weight buffer holds fewer than D n floats");
  const std::size_t L = vplkit::share_tree_leaf_count(n);
  const unsigned depth = vplkit::share_tree_depth(L);
  // Tree d reads weights [d n, (d + 1) n) and writes shares [d L, (d + 1) L) through range bindings:
  // their offsets must meet the SSBO offset alignment.
  GLint align = 1;
  glGetIntegerv(GL_SHADER_STORAGE_BUFFER_OFFSET_ALIGNMENT, &align);
  const std::size_t a = static_cast<std::size_t>(std::max(align, 1));
  if (D > 1 && ((n * 4) % a != 0 || (L * 4) % a != 0))
    throw vplkit::invalid_input("build_share_trees_gpu: " + std::to_string(n) +
                                " weights per tree do not meet the driver's buffer offset alignment of " +
                                std::to_string(a) + " bytes");

  gpu_share_trees out;
  out.leaves = static_cast<std::uint32_t>(L);
  gl::timer_query tq;
  tq.begin();
  out.shares = gl::buffer::filled(static_cast<std::size_t>(D) * L * 4, 0);
  gl::buffer sums = gl::buffer::filled(2 * L * 4, 0);  // one tree at a time; only sums[1] is read
  gl::buffer params = gl::buffer::filled(sizeof(vplkit::gpu::share_tree_build_params), 0);
  const gl::program& prog = gl::cached_kernel("vplkit/distribution/share_tree_build.comp");
  sums.bind(VPLKIT_SHARE_TREE_BUILD_BINDING_SUMS);
  glBindBufferBase(GL_UNIFORM_BUFFER, VPLKIT_SHARE_TREE_BUILD_BINDING_PARAMS, params.id());
  for (int d = 0; d < D; ++d) {
    glBindBufferRange(GL_SHADER_STORAGE_BUFFER, VPLKIT_SHARE_TREE_BUILD_BINDING_WEIGHTS, weights.id(),
                      static_cast<GLintptr>(static_cast<std::size_t>(d) * n * 4), static_cast<GLsizeiptr>(n * 4));
    glBindBufferRange(GL_SHADER_STORAGE_BUFFER, VPLKIT_SHARE_TREE_BUILD_BINDING_SHARES, out.shares.id(),
                      static_cast<GLintptr>(static_cast<std::size_t>(d) * L * 4), static_cast<GLsizeiptr>(L * 4));
    gl::check_gl("share_tree_build.comp bindings");
    // Leaves first, then each level from its children (share_tree_build_params.h).
    for (int level = static_cast<int>(depth); level >= 0; --level) {
      vplkit::gpu::share_tree_build_params p{};
      p.n = static_cast<std::uint32_t>(n);
      p.leaves = out.leaves;
      p.level = static_cast<std::uint32_t>(level);
      params.write_bytes(&p, 0, sizeof p);
      gl::dispatch(prog, vplkit::gpu::share_tree_build_groups(p.level));
    }
    float total = 0.0f;
    sums.read_bytes(&total, 4, 4);  // sums[1]
    if (!std::isfinite(total))
      throw vplkit::invalid_input("--sampler share-tree: the weights' float sum of tree " + std::to_string(d) +
                                  " overflows (the tree's sums are floats)");
    out.totals.push_back(total);
  }
  tq.end();
  timer.add("share tree (gpu)", tq.milliseconds(), "gpu");
  det["share_tree"] = {{"backend", "gpu"},
                       {"kernel", "vplkit/distribution/share_tree_build.comp"},
                       {"trees", D},
                       {"leaves", L},
                       {"dispatches_per_tree", depth + 1}};
  return out;
}

}  // namespace vplrender
