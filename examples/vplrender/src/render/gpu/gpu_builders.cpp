// SPDX-License-Identifier: MIT
#include "render/gpu/gpu_builders.hpp"

#include "render/gpu/gpu_visibility.hpp"
#include "render/gpu/loop_budget.hpp"
#include "render/mixture_components.hpp"
#include "render/method_traits.hpp"

#include <vplkit/builders/flux_weights_params.h>
#include <vplkit/builders/gather_subset.hpp>
#include <vplkit/builders/gather_subset_params.h>
#include <vplkit/builders/gbg_accumulate_params.h>
#include <vplkit/builders/gbg_finish_params.h>
#include <vplkit/builders/global_weights_params.h>
#include <vplkit/builders/local_weights.hpp>
#include <vplkit/core/error.hpp>
#include <vplkit/visibility/triangle_voxel_query.hpp>
#include <vplkit/visibility/voxel_visible.hpp>
#include <vplkit/vpl/luminance.hpp>

#include <glm/geometric.hpp>
#include <glm/vec4.hpp>

#include <algorithm>
#include <cmath>
#include <string>

namespace vplrender {

namespace gl = vplkit::gl;

const gpu_scene_buffers& scene_on_gpu(const frame_buffers& b, const char* who) {
  if (!b.gpu)
    throw vplkit::invalid_input(std::string(who) + ": the frame's buffers are not on the GPU (prepared for --backend " +
                                to_string(b.back) + ")");
  // The arrays may be absent (a GPU frame keeps them on the GPU): only the sizes are checked.
  if (b.gbuf.width <= 0 || b.gbuf.height <= 0 || b.dprsm.resolution <= 0)
    throw vplkit::invalid_input(std::string(who) + ": the frame has an empty G-buffer (" + std::to_string(b.gbuf.width) +
                                "x" + std::to_string(b.gbuf.height) + ") or DPRSM (resolution " +
                                std::to_string(b.dprsm.resolution) + ")");
  return *b.gpu;
}

dprsm_data host_dprsm(const frame_buffers& b) {
  if (b.has_host_copies()) return b.dprsm;
  return read_back_dprsm(scene_on_gpu(b, "host_dprsm"), b.dprsm.resolution, b.dprsm.light);
}

gpu_gather_subsets build_gather_subsets_gpu(const gpu_scene_buffers& scene, const vplkit::gbuffer_view<float>& g,
                                            const std::vector<vplkit::pixel_rect>& rects, int count,
                                            std::uint32_t seed) {
  const int N = static_cast<int>(rects.size());
  gpu_gather_subsets out;
  // Rectangle i's strata at [i count, i count + shape.count); the rest stays -1 (skipped).
  const std::size_t cap = static_cast<std::size_t>(N) * static_cast<std::size_t>(count);
  out.pixels = gl::buffer::filled(std::max<std::size_t>(cap, 1) * 4, 0xFF);
  std::vector<std::uint32_t> offsets;
  for (int i = 0; i <= N; ++i) offsets.push_back(static_cast<std::uint32_t>(i) * static_cast<std::uint32_t>(count));
  out.offsets = gl::buffer::from_vector(offsets);
  const gl::program& sp = gl::cached_kernel("vplkit/builders/gather_subset.comp");
  for (int i = 0; i < N; ++i) {
    const vplkit::pixel_rect& r = rects[static_cast<std::size_t>(i)];
    const vplkit::gather_subset_grid_shape shape = vplkit::gather_subset_grid(r, count);
    if (shape.count <= 0) continue;
    const std::uint32_t first = static_cast<std::uint32_t>(i) * static_cast<std::uint32_t>(count);
    const vplkit::gpu::gather_subset_params p =
        vplkit::gpu::make_gather_subset_params(g, r, count, seed, first, vplkit::gather_subset_default_attempts, first);
    out.params.push_back(gl::buffer::from_bytes(&p, sizeof p));
    scene.gbuffer.bind(VPLKIT_GATHER_SUBSET_BINDING_GBUFFER);
    out.pixels.bind(VPLKIT_GATHER_SUBSET_BINDING_PIXELS);
    glBindBufferBase(GL_UNIFORM_BUFFER, VPLKIT_GATHER_SUBSET_BINDING_PARAMS, out.params.back().id());
    gl::dispatch(sp, gl::groups_for(static_cast<std::size_t>(shape.count), VPLKIT_GATHER_SUBSET_LOCAL_SIZE));
  }
  return out;
}

std::vector<int> gather_subset_sizes(const gpu_gather_subsets& s, int rects, int count) {
  // |S_i| for the report: the subsets are a few hundred ints.
  const std::size_t cap = static_cast<std::size_t>(rects) * static_cast<std::size_t>(count);
  const std::vector<std::int32_t> picks = s.pixels.read<std::int32_t>(cap);
  std::vector<int> used(static_cast<std::size_t>(rects), 0);
  for (std::size_t k = 0; k < cap; ++k)
    if (picks[k] >= 0) ++used[k / static_cast<std::size_t>(count)];
  return used;
}

gpu_weights build_brsm_weights_gpu(const frame_buffers& b, const render_settings& s, bool local, stage_timer& timer) {
  auto running = stage_timer::running(local ? "local weights (gpu)" : "global weights (gpu)");
  const gpu_scene_buffers& scene = scene_on_gpu(b, "build_brsm_weights_gpu");
  const vplkit::gbuffer_view<float> g = b.gbuf.view();  // sizes (the pixels are on the GPU)
  const vplkit::dprsm_view<float> view = b.dprsm.view();  // resolution and light
  const int count = local ? s.local_subset : s.global_subset;
  if (count < 0) throw vplkit::invalid_input("build_brsm_weights_gpu: negative subset size");
  // The same rectangles, seeds and streams as build_distributions_cpu (stratified_gather_subset
  // over the image; local_gather_subsets over the regions).
  std::vector<vplkit::pixel_rect> rects;
  if (local) {
    const vplkit::image_regions regions(g.width, g.height, s.regions_x, s.regions_y);
    for (int i = 0; i < regions.count(); ++i) rects.push_back(regions.region_rect(i));
  } else {
    rects.push_back(vplkit::full_image_rect(g));
  }
  const int N = static_cast<int>(rects.size());
  const std::uint32_t seed = builder_seed(s.seed, local ? 1u : 0u);
  const std::size_t n = static_cast<std::size_t>(view.texel_count());

  gpu_weights out;
  out.regions = N;
  gl::timer_query tq;
  tq.begin();
  gpu_gather_subsets sub = build_gather_subsets_gpu(scene, g, rects, count, seed);
  out.weights = gl::buffer::filled((static_cast<std::size_t>(N) + 1) * n * 4, 0);
  vplkit::gpu::global_weights_params wp{};
  wp.light = vplkit::gpu::make_light_params(view.light);
  wp.resolution = view.resolution;
  wp.regions = N;
  wp.pixel_count = g.width * g.height;
  wp.dmin = s.dmin;
  const gl::buffer wp_block = gl::buffer::from_bytes(&wp, sizeof wp);
  scene.gbuffer.bind(VPLKIT_GLOBAL_WEIGHTS_BINDING_GBUFFER);
  scene.dprsm.bind(VPLKIT_GLOBAL_WEIGHTS_BINDING_DPRSM);
  sub.pixels.bind(VPLKIT_GLOBAL_WEIGHTS_BINDING_SUBSET);
  sub.offsets.bind(VPLKIT_GLOBAL_WEIGHTS_BINDING_OFFSETS);
  out.weights.bind(VPLKIT_GLOBAL_WEIGHTS_BINDING_WEIGHTS);
  glBindBufferBase(GL_UNIFORM_BUFFER, VPLKIT_GLOBAL_WEIGHTS_BINDING_PARAMS, wp_block.id());
  gl::dispatch_linear(gl::cached_kernel("vplkit/builders/global_weights.comp"),
                      gl::groups_for(n, VPLKIT_GLOBAL_WEIGHTS_LOCAL_SIZE), static_cast<GLuint>(N));
  out.used = gather_subset_sizes(sub, N, count);
  tq.end();
  timer.add(local ? "local weights (gpu)" : "global weights (gpu)", tq.milliseconds(), "gpu");
  return out;
}

gbg_gpu_weights build_gbg_weights_gpu(const frame_buffers& b, const render_settings& s, stage_timer& timer,
                                      nlohmann::json& det, bool read_back) {
  auto running = stage_timer::running("gbg weights + hole fill (gpu)");
  const gpu_scene_buffers& scene = scene_on_gpu(b, "build_gbg_weights_gpu");
  const vplkit::gbuffer_view<float> g = b.gbuf.view();  // sizes (the pixels are on the GPU)
  const vplkit::dprsm_view<float> view = b.dprsm.view();  // resolution and light
  if (s.dirs < 1) throw vplkit::invalid_input("build_gbg_weights_gpu: --dirs must be >= 1");
  const vplkit::voxel_grid_view<float> grid = b.grid.occupancy().view();
  const int W = g.width, H = g.height, R = view.resolution;
  const std::size_t n_pixels = static_cast<std::size_t>(W) * static_cast<std::size_t>(H);
  const std::size_t n = static_cast<std::size_t>(view.texel_count());
  const float depth_tol = gathering_depth_tolerance(s, grid);
  // The frame's facts (counted on the GPU for a GPU frame): gather points and the nearest lit texel.
  const frame_facts facts = facts_of(b);
  const int gather_points = static_cast<int>(facts.gather_points);

  // Fixed point as gbg_weights.glsl recommends: max_units = 2^(63 - ceil(log2(|G| n_dirs))) keeps any
  // texel's sum below 2^63; scale = 2^floor(log2(max_units / v_bound)) with v_bound the gathering
  // accumulator's largest per-hit value, I / (pi d1min^2) in luminance, d1min the nearest lit
  // texel's distance to the light less the depth tolerance. A power of two, so 1 / scale is exact.
  const double hits_max = std::max(1.0, double(std::max(gather_points, 1)) * s.dirs);
  const double max_units = std::ldexp(1.0, 63 - static_cast<int>(std::ceil(std::log2(hits_max))));
  double d1min = std::isinf(facts.nearest_lit_distance) ? 1e30 : double(facts.nearest_lit_distance);
  d1min = std::max(d1min - double(depth_tol), 1e-3);
  // The paper accumulator (luminance of eq. 5 clamped at dmin) is bounded instead by
  // luminance(I) Omega_max / (pi^2 dmin^2), Omega_max = 4 (2/R)^2 (gbg_weights.glsl). With --dmin 0
  // the values are unbounded: the grid is then sized for a clamp at 1e-3 of the scene diagonal and
  // larger values saturate (the weights only shape the pdf; eps keeps it positive where it must be).
  const bool paper_acc = s.gbg_accumulator == gbg_accumulator_choice::paper;
  const double lum_i = std::max(double(vplkit::luminance(view.light.intensity)), 1e-30);
  const double dmin_b = std::max({double(s.dmin), 1e-3 * double(s.scene_diagonal), 1e-6});
  const double v_bound = paper_acc ? lum_i * (16.0 / (double(R) * R)) / (9.869604401089358 * dmin_b * dmin_b)
                                   : lum_i / (3.141592653589793 * d1min * d1min);
  const double scale = std::ldexp(1.0, static_cast<int>(std::floor(std::log2(max_units / v_bound))));

  const gl::program& acc_prog = gl::cached_kernel("vplkit/builders/gbg_accumulate.comp", gbg_tracer_define(s.visibility));
  const gl::program& fin_prog = gl::cached_kernel("vplkit/builders/gbg_finish.comp");
  gl::buffer b_acc = gl::buffer::filled(2 * n * 4, 0);
  gl::buffer b_stats = gl::buffer::filled(VPLKIT_GBG_STATS_SIZE * 4, 0);
  gl::buffer b_weights = gl::buffer::filled(n * 4, 0);

  // llvmpipe leaves every loop after 65535 iterations per invocation, silently: split the
  // directions over dispatches (the fixed-point sums do not depend on the split). One ray is
  // budgeted as the estimate kernel budgets a query (gpu_backend.cpp's shape_of): twice
  // gpu_query_cost, + 32. Its bare bound (+ 8) was not enough for the BVH: on the cornell box at
  // 600 directions in one dispatch 28 % of the lit hits were lost (renderer_gpu_parity_test).
  const long long per_dir = 2 * gpu_query_cost(&scene, s.visibility, grid.resolution) + 32;
  const int dirs_per = static_cast<int>(std::max(1LL, gpu_loop_budget / per_dir));
  const GLuint groups = gl::groups_for(std::max<std::size_t>(n_pixels, 1), VPLKIT_GBG_LOCAL_SIZE);
  const vplkit::gpu::light_params light = vplkit::gpu::make_light_params(view.light);
  std::vector<gl::buffer> blocks;
  int dispatches = 0;
  // The tracer's own buffers (exact: the BVH), bound once for every accumulation dispatch.
  const std::uint32_t bvh_nodes = bind_visibility_buffers(
      scene, s.visibility,
      visibility_bindings{VPLKIT_GBG_BINDING_BVH_NODES, VPLKIT_GBG_BINDING_BVH_TRIANGLES, VPLKIT_GBG_BINDING_VOXEL_RANK,
                          VPLKIT_GBG_BINDING_VOXEL_OFFSETS, VPLKIT_GBG_BINDING_VOXEL_ENTRIES,
                          VPLKIT_GBG_BINDING_VOXEL_TRIANGLES});
  {
    gl::timer_query tq;
    tq.begin();
    for (int begin = 0; begin < s.dirs; begin += dirs_per) {
      const int end = std::min(s.dirs, begin + dirs_per);
      vplkit::gpu::gbg_accumulate_params p{};
      p.light = light;
      p.grid_min = glm::vec4(grid.bounds_min, 0.0f);
      p.grid_max = glm::vec4(grid.bounds_max, 0.0f);
      p.grid_resolution = glm::ivec4(grid.resolution, 0);
      p.width = W;
      p.height = H;
      p.resolution = R;
      p.n_dirs = s.dirs;
      p.accumulator = paper_acc ? 0 : 1;
      p.dir_begin = begin;
      p.dir_end = end;
      p.count_gather_points = begin == 0 ? 1 : 0;
      p.seed = builder_seed(s.seed, 2);
      p.dmin = s.dmin;
      p.depth_tolerance = depth_tol;
      p.offset_voxels = float(vplkit::voxel_surface_offset_default);
      p.scale = float(scale);
      p.max_units = float(max_units);
      p.bvh_node_count = bvh_nodes;
      // The triangle voxel tracer's end rule (used only under VPLKIT_GBG_TRIANGLE_VOXELS), as the
      // CPU's triangle_voxel_tracer.
      p.end_tolerance_voxels = float(vplkit::triangle_voxel_default_end_tolerance);
      blocks.push_back(gl::buffer::from_bytes(&p, sizeof p));
      scene.gbuffer.bind(VPLKIT_GBG_BINDING_GBUFFER);
      scene.dprsm.bind(VPLKIT_GBG_BINDING_DPRSM);
      scene.voxels.bind(VPLKIT_GBG_BINDING_VOXELS);
      b_acc.bind(VPLKIT_GBG_BINDING_ACC);
      b_stats.bind(VPLKIT_GBG_BINDING_STATS);
      glBindBufferBase(GL_UNIFORM_BUFFER, VPLKIT_GBG_BINDING_PARAMS, blocks.back().id());
      gl::dispatch_linear(acc_prog, groups);
      ++dispatches;
    }
    vplkit::gpu::gbg_finish_params fp{};
    fp.light = light;
    fp.resolution = R;
    fp.n_dirs = s.dirs;
    fp.fill_holes = 1;
    fp.inv_scale = float(1.0 / scale);
    blocks.push_back(gl::buffer::from_bytes(&fp, sizeof fp));
    b_acc.bind(VPLKIT_GBG_FINISH_BINDING_ACC);
    b_stats.bind(VPLKIT_GBG_FINISH_BINDING_STATS);
    scene.dprsm.bind(VPLKIT_GBG_FINISH_BINDING_DPRSM);
    b_weights.bind(VPLKIT_GBG_FINISH_BINDING_WEIGHTS);
    glBindBufferBase(GL_UNIFORM_BUFFER, VPLKIT_GBG_FINISH_BINDING_PARAMS, blocks.back().id());
    const GLuint fg = gl::groups_for(static_cast<std::size_t>(R), VPLKIT_GBG_FINISH_LOCAL_SIZE);
    gl::dispatch(fin_prog, fg, fg, 2);
    tq.end();
    timer.add("gbg weights + hole fill (gpu)", tq.milliseconds(), "gpu");
  }
  gbg_gpu_weights out;
  if (read_back) out.weights = b_weights.read<float>(n);
  const std::vector<std::uint32_t> st = b_stats.read<std::uint32_t>(VPLKIT_GBG_STATS_SIZE);
  const std::uint32_t g_points = st[VPLKIT_GBG_STAT_GATHER_POINTS];
  out.scale = scale;
  out.lit_hits = static_cast<long long>(st[VPLKIT_GBG_STAT_LIT_HITS]);
  out.gather_points = static_cast<int>(g_points);
  out.buffer = std::move(b_weights);
  det["gbg"] = {{"gather_points", g_points},
                {"rays", static_cast<long long>(g_points) * s.dirs},
                {"hits", st[VPLKIT_GBG_STAT_HITS]},
                {"lit_hits", st[VPLKIT_GBG_STAT_LIT_HITS]},
                {"reached_texels", st[VPLKIT_GBG_STAT_REACHED_TEXELS]},
                {"holes", st[VPLKIT_GBG_STAT_HOLES]},
                {"filled", st[VPLKIT_GBG_STAT_FILLED]},
                {"accumulator", to_string(s.gbg_accumulator)},
                {"backend", "gpu"},
                {"fixed_point_scale", scale},
                {"fixed_point_max_units", max_units},
                {"saturated_hits", st[VPLKIT_GBG_STAT_SATURATED_HITS]},
                {"dispatches", dispatches}};
  return out;
}

gpu_mixtures build_distributions_gpu(const frame_buffers& b, const render_settings& s, stage_timer& timer,
                                     nlohmann::json& det) {
  const vplkit::dprsm_view<float> view = b.dprsm.view();
  const gpu_scene_buffers& scene = scene_on_gpu(b, "build_distributions_gpu");
  const std::size_t n = static_cast<std::size_t>(view.texel_count());
  gl::buffer weights;
  int D = 1;
  const builder_kind builder = distribution_builder(s);  // ris: its candidate source's builder
  switch (builder) {
    case builder_kind::global: {
      gpu_weights w = build_brsm_weights_gpu(b, s, false, timer);
      det["global_subset"] = w.used.front();
      weights = std::move(w.weights);
      break;
    }
    case builder_kind::local: {
      gpu_weights w = build_brsm_weights_gpu(b, s, true, timer);
      det["local_subsets"] = w.used;
      D = w.regions;
      weights = std::move(w.weights);
      break;
    }
    case builder_kind::gbg: {
      gbg_gpu_weights w = build_gbg_weights_gpu(b, s, timer, det, false);
      // Into a buffer with room for the fallback's weights (a GPU-side copy).
      weights = gl::buffer::filled(2 * n * 4, 0);
      glBindBuffer(GL_COPY_READ_BUFFER, w.buffer.id());
      glBindBuffer(GL_COPY_WRITE_BUFFER, weights.id());
      glCopyBufferSubData(GL_COPY_READ_BUFFER, GL_COPY_WRITE_BUFFER, 0, 0, static_cast<GLsizeiptr>(n * 4));
      glBindBuffer(GL_COPY_READ_BUFFER, 0);
      glBindBuffer(GL_COPY_WRITE_BUFFER, 0);
      gl::check_gl("copy of the GBG weights");
      break;
    }
    case builder_kind::flux: {
      // --candidate-source flux: each texel's power (vplkit::build_flux_weights) by the pack's
      // flux_weights.comp on the DPRSM where it lies, into a buffer with room for the fallback's
      // weights. (Built on the host from the DPRSM read back, this took 45-54 ms per frame on an
      // NVIDIA H200 at 2 x 512^2 texels, three times global's whole 16-VPL frame.)
      weights = gl::buffer::filled(2 * n * 4, 0);
      gl::timer_query tq;
      tq.begin();
      vplkit::gpu::flux_weights_params fp{};
      fp.light = vplkit::gpu::make_light_params(view.light);
      fp.resolution = view.resolution;
      const gl::buffer params = gl::buffer::from_bytes(&fp, sizeof fp);
      scene.dprsm.bind(VPLKIT_FLUX_WEIGHTS_BINDING_DPRSM);
      weights.bind(VPLKIT_FLUX_WEIGHTS_BINDING_WEIGHTS);
      glBindBufferBase(GL_UNIFORM_BUFFER, VPLKIT_FLUX_WEIGHTS_BINDING_PARAMS, params.id());
      gl::dispatch_linear(gl::cached_kernel("vplkit/builders/flux_weights.comp"),
                          gl::groups_for(n, VPLKIT_FLUX_WEIGHTS_LOCAL_SIZE));
      tq.end();
      timer.add("flux weights (gpu)", tq.milliseconds(), "gpu");
      break;
    }
    case builder_kind::none:
    case builder_kind::candidate_source:  // resolved to its builder by distribution_builder
      throw vplkit::invalid_input(std::string("build_distributions_gpu: --method ") + to_string(s.meth) +
                                  " has no GPU builder");
  }
  gpu_mixtures mix = build_mixtures_gpu(weights, D, scene.dprsm, view, s.eps, timer, det);
  if (s.sampler == sampler_choice::share_tree) mix.share_trees = build_share_trees_gpu(weights, D, n, timer, det);
  if (mixture_components::wanted(s)) {
    auto t = timer.scoped("weights read-back (cpu)");
    mix.weights = weights.read<float>(static_cast<std::size_t>(D) * n);
  }
  if (builder == builder_kind::local) {
    // N_NG rounds of one VPL per region's CDF, as build_distributions_cpu.
    mix.local_rounds = std::max(1, s.vpls / D);
    if (s.meth == method::local) {
      det["local_rounds"] = mix.local_rounds;
      det["local_combination"] = to_string(s.local_combination);
    }
  }
  det["builders"] = "gpu";
  return mix;
}

}  // namespace vplrender
