// SPDX-License-Identifier: MIT
#include "render/gpu/gpu_tiles.hpp"

#include "render/gpu/gpu_builders.hpp"

#include <vplkit/builders/local_weights.hpp>
#include <vplkit/builders/tile_blocks.hpp>
#include <vplkit/builders/tile_blocks_params.h>
#include <vplkit/builders/tile_weights_params.h>
#include <vplkit/core/error.hpp>
#include <vplkit/core/float_bits.hpp>
#include <vplkit/distribution/discrete_cdf.hpp>
#include <vplkit/distribution/mixture_split.hpp>

#include <algorithm>
#include <string>

namespace vplrender {

namespace gl = vplkit::gl;

gpu_tiles build_tiles_gpu(const frame_buffers& b, const render_settings& s, stage_timer& timer, nlohmann::json& det) {
  auto running = stage_timer::running("tiles (gpu)");
  const gpu_scene_buffers& scene = scene_on_gpu(b, "build_tiles_gpu");
  const vplkit::gbuffer_view<float> g = b.gbuf.view();  // sizes (the pixels are on the GPU)
  const vplkit::dprsm_view<float> view = b.dprsm.view();  // resolution and light
  const int R = view.resolution, B = std::max(1, s.tile_block);
  const vplkit::tile_block_grid grid = vplkit::make_tile_block_grid(R, B);  // the C++ builder's layout
  const std::size_t n = static_cast<std::size_t>(view.texel_count());
  const vplkit::image_regions tiles(g.width, g.height, s.tiles_x, s.tiles_y);
  gpu_tiles out;
  out.count = tiles.count();
  out.blocks = grid.count();
  const std::size_t T = static_cast<std::size_t>(out.count), Nb = static_cast<std::size_t>(out.blocks);
  const std::size_t m = vplkit::discrete_guide_size(Nb);
  // The kernels address the tile buffer with 32-bit uints (estimate_tiles.glsl).
  if (T * (Nb + 1 + m + 1) + n + 1024 > 0xFFFFFFFFull)
    throw vplkit::invalid_input("--candidate-source tiles: " + std::to_string(T) + " tiles of " + std::to_string(Nb) +
                                " blocks exceed the GPU kernels' 2^32 words; use fewer --tiles or a larger --tile-block");

  gl::timer_query tq;
  tq.begin();
  // Blocks: shares (into scratch, copied after the CDFs' parts) and proxies.
  gl::buffer shares = gl::buffer::filled(n * 4, 0);
  gl::buffer proxies = gl::buffer::filled(std::max<std::size_t>(Nb, 1) * 3 * 16, 0);
  vplkit::gpu::tile_blocks_params bp{};
  bp.light = vplkit::gpu::make_light_params(view.light);
  bp.resolution = R;
  bp.block = B;
  const gl::buffer bp_block = gl::buffer::from_bytes(&bp, sizeof bp);
  scene.dprsm.bind(VPLKIT_TILE_BLOCKS_BINDING_DPRSM);
  shares.bind(VPLKIT_TILE_BLOCKS_BINDING_SHARES);
  proxies.bind(VPLKIT_TILE_BLOCKS_BINDING_PROXIES);
  glBindBufferBase(GL_UNIFORM_BUFFER, VPLKIT_TILE_BLOCKS_BINDING_PARAMS, bp_block.id());
  gl::dispatch_linear(gl::cached_kernel("vplkit/builders/tile_blocks.comp"),
                      gl::groups_for(Nb, VPLKIT_TILE_BLOCKS_LOCAL_SIZE));
  // The tiles' gather points and their block weights.
  std::vector<vplkit::pixel_rect> rects;
  for (int i = 0; i < tiles.count(); ++i) rects.push_back(tiles.region_rect(i));
  const gpu_gather_subsets sub = build_gather_subsets_gpu(scene, g, rects, s.tile_points, builder_seed(s.seed, 3));
  gl::buffer weights = gl::buffer::filled(std::max<std::size_t>(T * Nb, 1) * 4, 0);
  vplkit::gpu::tile_weights_params wp{};
  wp.blocks = out.blocks;
  wp.tiles = out.count;
  wp.pixel_count = g.width * g.height;
  wp.dmin = s.dmin;
  const gl::buffer wp_block = gl::buffer::from_bytes(&wp, sizeof wp);
  scene.gbuffer.bind(VPLKIT_TILE_WEIGHTS_BINDING_GBUFFER);
  sub.pixels.bind(VPLKIT_TILE_WEIGHTS_BINDING_SUBSET);
  sub.offsets.bind(VPLKIT_TILE_WEIGHTS_BINDING_OFFSETS);
  proxies.bind(VPLKIT_TILE_WEIGHTS_BINDING_PROXIES);
  weights.bind(VPLKIT_TILE_WEIGHTS_BINDING_WEIGHTS);
  glBindBufferBase(GL_UNIFORM_BUFFER, VPLKIT_TILE_WEIGHTS_BINDING_PARAMS, wp_block.id());
  gl::dispatch_linear(gl::cached_kernel("vplkit/builders/tile_weights.comp"),
                      gl::groups_for(Nb, VPLKIT_TILE_WEIGHTS_LOCAL_SIZE), static_cast<GLuint>(T));
  gpu_cdf_set set = build_cdf_set_gpu(weights, T, Nb, n);
  glBindBuffer(GL_COPY_READ_BUFFER, shares.id());
  glBindBuffer(GL_COPY_WRITE_BUFFER, set.data.id());
  glCopyBufferSubData(GL_COPY_READ_BUFFER, GL_COPY_WRITE_BUFFER, 0, static_cast<GLintptr>(set.extra_base * 4),
                      static_cast<GLsizeiptr>(n * 4));
  glBindBuffer(GL_COPY_READ_BUFFER, 0);
  glBindBuffer(GL_COPY_WRITE_BUFFER, 0);
  gl::check_gl("copy of the tiles' shares");
  const std::vector<int> used = gather_subset_sizes(sub, out.count, s.tile_points);
  tq.end();
  timer.add("tiles (gpu)", tq.milliseconds(), "gpu");
  out.data = std::move(set.data);
  out.guide_base = static_cast<std::uint32_t>(set.guide_base);
  out.share_base = static_cast<std::uint32_t>(set.extra_base);
  out.totals = set.totals;
  det["tiles"] = {{"tiles", out.count},
                  {"grid", {s.tiles_x, s.tiles_y}},
                  {"points", used},
                  {"block", B},
                  {"blocks", out.blocks},
                  {"empty", std::count(out.totals.begin(), out.totals.end(), 0.0f)},
                  {"backend", "gpu"}};
  return out;
}

std::vector<gpu::mixture_record> tile_mixture_records(const gpu_tiles& t, const gpu::mixture_record& flux_record,
                                                      float eps) {
  const std::uint32_t Nb = static_cast<std::uint32_t>(t.blocks);
  const std::uint32_t m = static_cast<std::uint32_t>(vplkit::discrete_guide_size(Nb));
  const bool fallback_empty = vplkit::float_from_bits(flux_record.fallback.w) == 0.0f;
  std::vector<gpu::mixture_record> out(static_cast<std::size_t>(std::max(t.count, 1)));
  for (int d = 0; d < t.count; ++d) {
    const float total = t.totals[static_cast<std::size_t>(d)];
    const vplkit::mixture_split<float> split(eps, total == 0.0f, fallback_empty);
    gpu::mixture_record& r = out[static_cast<std::size_t>(d)];
    r.learned = glm::uvec4(VR_TILE_SLOT + static_cast<std::uint32_t>(d), Nb, m, vplkit::float_bits(total));
    r.fallback = flux_record.fallback;
    r.mix = glm::vec4(split.effective_eps(), split.fallback_scale(), split.learned_scale(), 0.0f);
  }
  return out;
}

}  // namespace vplrender
