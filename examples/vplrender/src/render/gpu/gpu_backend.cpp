// SPDX-License-Identifier: MIT
#include "render/gpu/gpu_backend.hpp"

#include "raster/gpu_scene_buffers.hpp"
#include "render/gpu/estimate_kernels.hpp"
#include "render/gpu/gpu_allocating.hpp"
#include "render/gpu/gpu_builders.hpp"
#include "render/gpu/gpu_dprsm_planes.hpp"
#include "render/gpu/gpu_tiles.hpp"
#include "render/gpu/gpu_visibility.hpp"
#include "render/gpu/loop_budget.hpp"
#include "render/method_traits.hpp"
#include "render/mixture_components.hpp"
#include "render/share_tree_mixture.hpp"
#include "render/ris_spatial.hpp"

#include "estimate_params.h"
#include "estimate_ris_params.h"

#include <headless_gl/compute.hpp>

#include <vplkit/core/float_bits.hpp>
#include <vplkit/core/gather_point.hpp>
#include <vplkit/distribution/discrete_cdf.hpp>
#include <vplkit/estimators/ris_params.h>
#include <vplkit/estimators/ris_pool_params.h>
#include <vplkit/estimators/vpl_sum.hpp>

#include <glm/common.hpp>
#include <glm/vec4.hpp>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

namespace vplrender {

static_assert(VR_SHARE_TREE_STREAM_SALT == share_tree_stream_salt,
              "estimate_params.h and render/share_tree_mixture.hpp name one tree stream");

namespace {

// mixture_components in the layout of the estimate kernels' components buffer
// (VR_ESTIMATE_BINDING_COMPONENTS, estimate_distributions.glsl): 12 uints per
// component k = 2 d + c, then the arrays they point into. Roulette: the front face's CDF and
// guide offsets and total, the back face's, b_front, b_back, front_scale, back_scale (the C++
// roulette's own values, so the GPU picks its face bit for bit), the face size and guide size
// (both faces have R^2 entries). Alias: the bins' offset (3 uints per bin), 0, total, 0 ..., the
// table size.
std::vector<std::uint32_t> pack_components(const mixture_components& c) {
  const std::size_t k_count = std::max(c.alias.size(), c.roulette.size());
  std::vector<std::uint32_t> out(12 * std::max<std::size_t>(k_count, 1), 0u);
  auto append = [&](const auto& v) {
    const std::size_t at = out.size();
    out.resize(at + v.size() * sizeof(v[0]) / 4);
    std::memcpy(out.data() + at, v.data(), v.size() * sizeof(v[0]));
    return static_cast<std::uint32_t>(at);
  };
  for (std::size_t k = 0; k < c.alias.size(); ++k) {
    const std::uint32_t bins = append(c.alias[k].bins());
    out[12 * k] = bins;
    out[12 * k + 2] = vplkit::float_bits(c.alias[k].total());
    out[12 * k + 10] = static_cast<std::uint32_t>(c.alias[k].size());
  }
  for (std::size_t k = 0; k < c.roulette.size(); ++k) {
    const vplkit::face_roulette<float>& f = c.roulette[k];
    const std::uint32_t front_cdf = append(f.front().cdf()), front_guide = append(f.front().guide());
    const std::uint32_t back_cdf = append(f.back().cdf()), back_guide = append(f.back().guide());
    const std::uint32_t rec[12] = {front_cdf,
                                   front_guide,
                                   vplkit::float_bits(f.front().total()),
                                   back_cdf,
                                   back_guide,
                                   vplkit::float_bits(f.back().total()),
                                   vplkit::float_bits(f.front_probability()),
                                   vplkit::float_bits(f.back_probability()),
                                   vplkit::float_bits(f.front_scale()),
                                   vplkit::float_bits(f.back_scale()),
                                   static_cast<std::uint32_t>(f.front().size()),
                                   static_cast<std::uint32_t>(f.front().guide_size())};
    std::memcpy(&out[12 * k], rec, sizeof(rec));
  }
  return out;
}

// What the rays are traced against: a method that always traces the triangles (exact) uses exact
// visibility whatever --visibility says.
visibility_choice visibility_of(const render_settings& es) {
  return traits(es.meth).exact_rays ? visibility_choice::exact : es.visibility;
}

// Gathering's lit test by a shadow ray: the method's gathering rays or the clamp's compensation
// directions, --lit-test shadow-ray, exact visibility (the estimate kernels' VR_LIT_SHADOW_RAY).
bool gpu_lit_test_shadow_ray(const render_settings& es) {
  return (traits(es.meth).gathers || gpu_clamp_compensation(es)) && es.lit_test == lit_test_choice::shadow_ray &&
         visibility_of(es) == visibility_choice::exact;
}

// "#define A 1\n#define B\n" as ["A 1", "B"] for the report.
nlohmann::json define_list(const std::string& preamble) {
  nlohmann::json out = nlohmann::json::array();
  std::size_t at = 0;
  while (at < preamble.size()) {
    const std::size_t eol = std::min(preamble.find('\n', at), preamble.size());
    const std::string line = preamble.substr(at, eol - at);
    const std::string prefix = "#define ";
    if (line.compare(0, prefix.size(), prefix) == 0) out.push_back(line.substr(prefix.size()));
    at = eol + 1;
  }
  return out;
}

// The mixtures of gm as estimate_params.h's records, and the CDF addressing: distribution k's cdf
// at data[k cdf_stride], its guide at data[guide_base + k guide_stride] (gpu_cdf.cpp's layout,
// checked here: the kernel reads it by that arithmetic, with no slot table).
std::vector<gpu::mixture_record> mixture_records(const gpu_mixtures& gm, gpu::estimate_params& P) {
  const std::size_t D = static_cast<std::size_t>(gm.count);
  const bool with_fallback = gm.totals.size() > D;
  P.cdf_stride = static_cast<std::uint32_t>(gm.n + 1);
  P.guide_base = static_cast<std::uint32_t>(gm.guide_offset.front());
  P.guide_stride = static_cast<std::uint32_t>(gm.m + 1);
  for (std::size_t k = 0; k < gm.cdf_offset.size(); ++k)
    if (gm.cdf_offset[k] != k * P.cdf_stride || gm.guide_offset[k] != P.guide_base + k * P.guide_stride)
      throw std::logic_error("render_gpu: the CDF data does not have the layout estimate_distributions.glsl reads");
  // The kernel's uint arithmetic reaches every word: the data holds fewer than 2^32 of them.
  if (gm.guide_offset.back() + gm.m + 1 > 0xFFFFFFFFu)
    throw vplkit::invalid_input("render_gpu: " + std::to_string(gm.cdf_offset.size()) +
                                " distributions of " + std::to_string(gm.n) + " texels exceed 2^32 words of CDF data");
  const vplkit::discrete_cdf<float> no_fallback;  // eps = 0: size 0 (make_vpl_distribution)
  const glm::uvec4 fallback =
      with_fallback ? glm::uvec4(static_cast<std::uint32_t>(D), static_cast<std::uint32_t>(gm.n),
                                 static_cast<std::uint32_t>(gm.m), vplkit::float_bits(gm.totals[D]))
                    : glm::uvec4(0u, 0u, static_cast<std::uint32_t>(no_fallback.guide_size()), vplkit::float_bits(0.0f));
  std::vector<gpu::mixture_record> out(std::max<std::size_t>(D, 1));
  const gpu_share_trees& trees = gm.share_trees;
  if (!trees.totals.empty() && trees.totals.size() != D)
    throw std::logic_error("render_gpu: " + std::to_string(trees.totals.size()) + " share trees for " +
                           std::to_string(D) + " mixtures");
  for (std::size_t d = 0; d < D; ++d) {
    out[d].learned = glm::uvec4(static_cast<std::uint32_t>(d), static_cast<std::uint32_t>(gm.n),
                                static_cast<std::uint32_t>(gm.m), vplkit::float_bits(gm.totals[d]));
    if (!trees.totals.empty()) {
      // --sampler share-tree: the learned part is tree d (vplkit_share_tree's fields). The split was
      // made on the CDF's total: both are positive exactly when a weight is at least FLT_MIN.
      if ((trees.totals[d] > 0.0f) != (gm.totals[d] > 0.0f))
        throw std::logic_error("render_gpu: share tree " + std::to_string(d) + " and its CDF disagree on emptiness");
      out[d].learned = glm::uvec4(static_cast<std::uint32_t>(d), static_cast<std::uint32_t>(gm.n), trees.leaves,
                                  vplkit::float_bits(trees.totals[d]));
    }
    out[d].fallback = fallback;
    out[d].mix = glm::vec4(gm.effective_eps[d], gm.fallback_scale[d], gm.learned_scale[d], 0.0f);
  }
  return out;
}

// --method ris and ris-mis with spatial reuse: rounds of a candidate and a reuse dispatch
// (estimate_ris_params.h).
bool ris_reuses(const render_settings& es) {
  const method_traits& t = traits(es.meth);
  return t.estimator == estimator_kind::ris && es.ris_spatial > 0;
}

// The rounds of a reuse: ris's --vpls samples; ris-mis's steps, max(--dirs, n2) with n2 = --vpls
// (0 without candidates), as render/cpu/ris_render.hpp's render_ris_mis_cpu.
int ris_reuse_rounds(const render_settings& es) {
  if (traits(es.meth).variant == 0) return std::max(1, es.vpls);
  const int n_ris = es.ris_candidates > 0 ? std::max(0, es.vpls) : 0;
  return std::max(1, std::max(std::max(0, es.dirs), n_ris));
}

// The RIS parameters for es on a W x H image (estimate_ris_params.h; the estimate block's P.ris).
gpu::ris_params ris_params_for(const render_settings& es, int W, int H) {
  const vplkit::ris_spatial_settings<float> sp = ris_spatial_settings_for(W, H, es.ris_spatial);
  gpu::ris_params R{};
  R.candidates = es.ris_candidates;
  R.neighbours = sp.neighbours;
  R.radius = sp.radius;
  R.mis = sp.mis == vplkit::ris_reuse_mis::balance ? 1 : 0;
  R.regions_x = es.regions_x;
  R.regions_y = es.regions_y;
  R.min_normal_cos = sp.min_normal_cos;
  R.max_plane_slope = sp.max_plane_slope;
  return R;
}

// A per-pixel buffer of `bytes` that starts this render with every byte `fill`: the one kept in
// `slot` from an earlier render of the same size (cleared on the GPU, nothing allocated), else a
// new one in its place.
vplkit::gl::buffer& pixel_buffer(gpu_pixel_buffers& cache, vplkit::gl::buffer& slot, std::size_t bytes,
                                 unsigned char fill, const char* what) {
  namespace gl = vplkit::gl;
  if (slot.size_bytes() != bytes) {
    slot = gl::buffer();  // the old size's storage goes before the new one is made
    slot = gpu_allocating(bytes, what, [&] { return gl::buffer::filled(bytes, fill); });
    ++cache.allocations;
    return slot;
  }
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, slot.id());
  glClearBufferData(GL_SHADER_STORAGE_BUFFER, GL_R8UI, GL_RED_INTEGER, GL_UNSIGNED_BYTE, &fill);
  glBindBuffer(GL_SHADER_STORAGE_BUFFER, 0);
  gl::check_gl(what);
  return slot;
}

}  // namespace

int gpu_pass_count(const render_settings& es, int dprsm_resolution, const vplkit::ivec3& voxel_resolution,
                   int regions) {
  const int rounds = std::max(1, es.vpls / std::max(1, regions));
  const shape_inputs in{dprsm_resolution, gpu_query_cost(nullptr, visibility_of(es), voxel_resolution), regions,
                        rounds, gpu_lit_test_shadow_ray(es)};
  if (ris_reuses(es)) return 2 * ris_reuse_rounds(es);  // a candidate and a reuse dispatch per round
  int passes = 0;
  for (const gpu_kernel_stage& stage : gpu_kernel_for(es.meth).stages) {
    const work_shape s = stage.shape(es, in);
    const long long chunk = units_per_pass(s);
    passes += static_cast<int>((std::max(1LL, s.units) + chunk - 1) / chunk);
  }
  return passes;
}

namespace {

// The clamp compensation's passes (clamp_compensation.comp; the parameter block P and its buffer,
// the terms and the list bound by the caller): the pixels whose near-surface test says maybe are
// listed, then an indirect dispatch over the list traces their directions, split under the loop
// budget like the estimate's units. Timed by the caller's two queries (the list, the directions),
// which it reads once the estimate kernel is issued: reading them here would make the CPU wait for
// the GPU before it issues the estimate. Returns the report's record (without the times).
nlohmann::json run_clamp_compensation_passes(const render_settings& es, visibility_choice vis, bool shadow_ray,
                                             const shape_inputs& in, bool budget, std::size_t n_pixels,
                                             gpu::estimate_params& P, vplkit::gl::buffer& b_params,
                                             const vplkit::gl::buffer& list, vplkit::gl::timer_query& tq_list,
                                             vplkit::gl::timer_query& tq_dirs) {
  namespace gl = vplkit::gl;
  auto running = stage_timer::running(clamp_compensation_stage_gpu);
  const gpu_kernel_stage stage{clamp_compensation_kernel, clamp_compensation_shape};
  const gl::program& mark = gpu_kernel_program(stage, clamp_compensation_defines(es, vis, shadow_ray, VR_CLAMP_PASS_MARK));
  const gl::program& groups =
      gpu_kernel_program(stage, clamp_compensation_defines(es, vis, shadow_ray, VR_CLAMP_PASS_DISPATCH));
  const gl::program& dirs =
      gpu_kernel_program(stage, clamp_compensation_defines(es, vis, shadow_ray, VR_CLAMP_PASS_DIRECTIONS));
  const work_shape shape = stage.shape(es, in);
  const long long units = std::max(1LL, shape.units);
  long long chunk = budget ? std::min(units, units_per_pass(shape)) : units;
  if (es.max_units_per_pass > 0) chunk = std::min<long long>(chunk, es.max_units_per_pass);
  const int passes = static_cast<int>((units + chunk - 1) / chunk);
  // Two timers one after the other (they cannot nest): the list, then the directions.
  tq_list.begin();
  b_params.write_bytes(&P, 0, sizeof P);
  gl::dispatch_linear(mark, gl::groups_for(n_pixels, mark.local_size()[0]));
  gl::dispatch(groups, 1);
  glMemoryBarrier(GL_COMMAND_BARRIER_BIT);  // the group counts are read by the indirect dispatches
  tq_list.end();
  tq_dirs.begin();
  glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, list.id());
  for (int k = 0; k < passes; ++k) {
    P.begin = static_cast<int>(k * chunk);
    P.end = static_cast<int>(std::min(units, (k + 1) * chunk));
    P.first_pass = k == 0 ? 1 : 0;
    P.last_pass = k == passes - 1 ? 1 : 0;
    b_params.write_bytes(&P, 0, sizeof P);
    dirs.use();
    glDispatchComputeIndirect(0);
    gl::memory_barrier();
  }
  glBindBuffer(GL_DISPATCH_INDIRECT_BUFFER, 0);
  gl::check_gl("the clamp compensation's passes");
  tq_dirs.end();
  return {{"kernel", gpu_kernel_path(stage)},
          {"passes", passes + 2},
          {"direction_passes", passes},
          {"units_per_pass", chunk},
          {"defines", define_list(clamp_compensation_defines(es, vis, shadow_ray, VR_CLAMP_PASS_DIRECTIONS))}};
}

}  // namespace

render_result render_gpu(const frame_buffers& b, const render_settings& given, stage_timer& timer,
                         const progress_fn& progress) {
  render_settings es = given;
  es.sampler = resolved_sampler(given);
  namespace gl = vplkit::gl;
  // A GPU frame's G-buffer and DPRSM live on the GPU: the views give their sizes and the light.
  const gpu_scene_buffers& scene = scene_on_gpu(b, "render_gpu");
  const vplkit::gbuffer_view<float> g = b.gbuf.view();
  const vplkit::dprsm_view<float> view = b.dprsm.view();
  const vplkit::voxel_grid_view<float> grid = b.grid.occupancy().view();
  const int W = g.width, H = g.height;
  const std::size_t n_pixels = static_cast<std::size_t>(W) * static_cast<std::size_t>(H);
  const method_traits& mt = traits(es.meth);
  if (!mt.gpu)
    throw vplkit::invalid_input(std::string("--method ") + mt.name + ": no GPU kernel yet (run_estimator refuses it)");
  if (mt.estimator == estimator_kind::ris && mt.variant != 1 && es.ris_source == ris_source_choice::tiles)
    throw vplkit::invalid_input("--method ris --candidate-source tiles: tiles is for --method ris-mis");
  if (!mt.exact_rays && given.visibility == visibility_choice::voxels && given.voxel_contract == voxel_contract_choice::exact)
    throw vplkit::invalid_input("--voxel-contract exact: the GPU backend's voxel march has the plane rule only "
                                "(use --backend cpu, or --visibility exact)");
  const gpu_estimate_kernel& kern = gpu_kernel_for(es.meth);
  if (es.sampler == sampler_choice::share_tree && !draws_share_tree(mt.estimator))
    throw vplkit::invalid_input(std::string("--sampler share-tree: not supported with --method ") + mt.name +
                                " (only global, gbg, local and mis)");
  render_result result;
  result.image = image_rgb(W, H);
  nlohmann::json& det = result.details;
  det["dmin"] = es.dmin;
  const float depth_tol = gathering_depth_tolerance(es, grid);
  det["depth_tolerance"] = depth_tol;
  det["cdf_search"] = to_string(es.cdf_search);
  const visibility_choice vis = visibility_of(es);
  det["visibility"] = to_string(vis);
  // Builders and CDFs on the GPU (gpu_builders.cpp, gpu_cdf.cpp): the mixtures stay there. The
  // methods without a builder (reference, gather, exact) sample no distribution at all.
  const bool with_dists = mt.builder != builder_kind::none;
  gpu_mixtures gm;
  if (with_dists) gm = build_distributions_gpu(b, es, timer, det);
  // --candidate-source tiles: the tiles' distributions over the flux build's (gpu_tiles.hpp).
  const bool tiles = with_dists && mt.estimator == estimator_kind::ris && es.ris_source == ris_source_choice::tiles;
  gpu_tiles tl;
  if (tiles) tl = build_tiles_gpu(b, es, timer, det);
  const int local_rounds = with_dists ? gm.local_rounds : 0;
  // --method exact: the host's ray scene gives the offsets (checked first: its error names the method).
  const bool exact_kernel = mt.estimator == estimator_kind::exact;
  const exact_ray_frame* exact_rays = exact_kernel ? &frame_exact_rays(b, "--method exact") : nullptr;
  if (exact_kernel && !scene.shading.unavailable.empty())
    throw vplkit::invalid_input("--method exact on the GPU: " + scene.shading.unavailable);
  const int n_dists = with_dists ? (tiles ? tl.count : gm.count) : 0;

  // The parameter block (estimate_params.h); begin, end, first_pass and last_pass change per dispatch.
  gpu::estimate_params P{};
  P.light = vplkit::gpu::make_light_params(view.light);
  P.grid_min = glm::vec4(grid.bounds_min, 0.0f);
  P.grid_max = glm::vec4(grid.bounds_max, 0.0f);
  P.grid_resolution = glm::ivec4(grid.resolution.x, grid.resolution.y, grid.resolution.z, 0);
  P.width = W;
  P.height = H;
  P.resolution = view.resolution;
  P.n_dirs = es.dirs;
  P.n_vpls = es.vpls;
  P.n_samples = mt.estimator == estimator_kind::local ? local_rounds : es.vpls;
  P.n_distributions = n_dists;
  P.strata = reference_patch_strata;
  P.seed = es.seed;
  P.dmin = es.dmin;
  P.depth_tolerance = depth_tol;
  if (exact_rays != nullptr) {
    P.surface_offset = exact_rays->surface_offset;
  }
  // The mixtures' records (one per mixture, three vector loads each) and the CDF data as built.
  // Without distributions the kernels still bind both buffers: one zero record and word.
  std::vector<gpu::mixture_record> records =
      with_dists ? mixture_records(gm, P) : std::vector<gpu::mixture_record>(1);
  // Tiles: mixture d is tile d's, its fallback the flux build's (addressed by the layout just set).
  if (tiles) records = tile_mixture_records(tl, records.front(), es.eps);
  gl::buffer b_data = with_dists ? std::move(gm.data) : gl::buffer::filled(4, 0);
  gl::buffer b_mixtures = gl::buffer::from_vector(records);
  auto estimate_running = stage_timer::running("estimate (gpu)");
  const std::size_t out_bytes = 16 * std::max<std::size_t>(n_pixels, 1);
  // The per-pixel buffers are the frame's (gpu_scene_buffers::pixels): kept across renders.
  gpu_pixel_buffers& pixels = scene.pixels;
  const gl::buffer& b_out = pixel_buffer(pixels, pixels.out, out_bytes, 0xFF, "the per-pixel estimates");
  // --sampler alias / --face-selection roulette: the components built on the host from the
  // weights read back (mixture_components.hpp), uploaded; else one zero word.
  // Tile draws use neither (estimate_tiles.glsl), as on the CPU backend.
  const bool components = with_dists && !tiles && mixture_components::wanted(es);
  gl::buffer b_components = gl::buffer::filled(4, 0);
  // --sampler share-tree: the trees' shares take the components' binding (estimate_params.h).
  if (with_dists && es.sampler == sampler_choice::share_tree) b_components = std::move(gm.share_trees.shares);
  if (components) {
    auto t = timer.scoped("sampler tables (cpu)");
    const dprsm_data host = host_dprsm(b);  // the fallback's texels (read back for a GPU frame)
    b_components = gl::buffer::from_vector(
        pack_components(build_mixture_components(gm.weights.data(), gm.count, host.view(), es)));
  }
  det["face_selection"] = to_string(es.face_selection);
  det["sampler"] = to_string(es.sampler);
  if (mt.uses_vpls) det["vpl_mode"] = to_string(es.vpl_mode);
  if (mt.estimator == estimator_kind::reference && es.vpl_mode == vpl_mode_choice::patch)
    det["reference_strata"] = reference_patch_strata;
  // The clamp's compensation traces gathering rays in the VPL kernels too (estimate_clamp_compensation.glsl),
  // with the gathering lit test the CPU backend's tracer gives them.
  const bool compensate = gpu_clamp_compensation(es);
  const bool shadow_ray = gpu_lit_test_shadow_ray(es);
  const bool compacted = gpu_clamp_compensation_compacted(es);
  if (compensate) {
    det["clamp_compensation_dirs"] = clamp_compensation_dirs(es);
    det["clamp_compensation_pass"] = to_string(es.clamp_compensation_pass);
  }
  if (mt.gathers)
    det["lit_test"] = to_string(shadow_ray ? lit_test_choice::shadow_ray : lit_test_choice::shadow_map);

  // The DPRSM's plane records, built by the frame pipeline (or here, first: the builder binds its own
  // buffers, for a frame made by hand).
  gl::buffer b_planes_scratch;
  const gl::buffer& b_planes = dprsm_planes_for(scene, view.resolution, view.light, b_planes_scratch);
  // The bindings of estimate_params.h.
  scene.gbuffer.bind(VR_ESTIMATE_BINDING_GBUFFER);
  scene.dprsm.bind(VR_ESTIMATE_BINDING_DPRSM);
  b_planes.bind(VR_ESTIMATE_BINDING_DPRSM_PLANES);
  scene.voxels.bind(VR_ESTIMATE_BINDING_VOXELS);
  b_data.bind(VR_ESTIMATE_BINDING_CDF_DATA);
  b_mixtures.bind(VR_ESTIMATE_BINDING_MIXTURES);
  b_out.bind(VR_ESTIMATE_BINDING_OUT);
  b_components.bind(VR_ESTIMATE_BINDING_COMPONENTS);
  P.bvh_node_count = bind_visibility_buffers(
      scene, vis,
      visibility_bindings{VR_ESTIMATE_BINDING_BVH_NODES, VR_ESTIMATE_BINDING_BVH_TRIANGLES, VR_ESTIMATE_BINDING_VOXEL_RANK,
                          VR_ESTIMATE_BINDING_VOXEL_OFFSETS, VR_ESTIMATE_BINDING_VOXEL_ENTRIES,
                          VR_ESTIMATE_BINDING_VOXEL_TRIANGLES, VR_ESTIMATE_BINDING_VOXEL_BRICKS});
  // Exact rays give their hits' shading normals (ray_scene.glsl) from the corner normals; exact.comp
  // also shades its hits' albedos from the pool.
  if (vis == visibility_choice::exact) scene.shading.triangles.bind(VR_ESTIMATE_BINDING_TRIANGLE_SHADING);
  // The compensation's near-surface test asks the triangle voxel lists with exact rays too
  // (estimate_clamp_compensation.glsl); with --visibility voxels they are bound already.
  if (compensate && vis == visibility_choice::exact) {
    const gpu_triangle_voxels& t = scene.voxel_triangles;
    t.rank.bind(VR_ESTIMATE_BINDING_VOXEL_RANK);
    t.offsets.bind(VR_ESTIMATE_BINDING_VOXEL_OFFSETS);
    t.entries.bind(VR_ESTIMATE_BINDING_VOXEL_ENTRIES);
    t.triangles.bind(VR_ESTIMATE_BINDING_VOXEL_TRIANGLES);
  }
  if (exact_kernel) scene.shading.pool.bind(VR_ESTIMATE_BINDING_SHADING_POOL);
  gl::buffer b_params = gl::buffer::filled(sizeof P, 0);
  glBindBufferBase(GL_UNIFORM_BUFFER, VR_ESTIMATE_BINDING_PARAMS, b_params.id());
  // --method ris and ris-mis: their parameters in the estimate block (P.ris, estimate_ris_params.h),
  // written with every dispatch's P below, and with spatial reuse the reservoirs between a round's
  // two dispatches (ris_params.h's 32-byte records).
  const bool ris = mt.estimator == estimator_kind::ris;
  const bool ris_reuse = ris_reuses(es);
  // ris-mis --candidate-pool: the pool's entries (one pool per candidate distribution), filled by
  // the first dispatch of the estimate (VR_RIS_PASS_POOL) and read by every later one.
  const bool ris_pool = ris && mt.variant == 1 && es.ris_pool > 0;
  const int ris_pools =
      es.ris_source == ris_source_choice::local || tiles ? std::max(1, n_dists) : 1;
  const std::size_t ris_pool_entries = ris_pool ? std::size_t(es.ris_pool) * std::size_t(ris_pools) : 0;
  if (ris) {
    gpu::ris_params R = ris_params_for(es, W, H);
    if (tiles) {
      R.regions_x = es.tiles_x;
      R.regions_y = es.tiles_y;
      R.tile_block = std::max(1, es.tile_block);
      R.tile_guide_base = tl.guide_base;
      R.tile_share_base = tl.share_base;
      tl.data.bind(VR_RIS_BINDING_TILES);
    }
    if (ris_pool) {
      R.pool_size = static_cast<gpu::uint>(es.ris_pool);
      R.pool_seed = ris_pool_seed(es.seed);
    }
    P.ris = R;
    det["ris"] = {{"candidates", es.ris_candidates}, {"candidate_source", to_string(es.ris_source)},
                  {"spatial", es.ris_spatial}};
    if (mt.variant == 1) det["ris"].update({{"dirs", es.dirs}, {"mis", "balance"}});
    if (ris_reuse) {
      det["ris"].update({{"radius", R.radius}, {"min_normal_cos", R.min_normal_cos},
                         {"max_plane_slope", R.max_plane_slope}});
      // ris-mis's "mis" names its balance against gathering (as on the CPU backend).
      det["ris"][mt.variant == 1 ? "reuse_mis" : "mis"] = "pairwise";
      const std::size_t bytes = sizeof(vplkit::gpu::ris_reservoir_record) * std::max<std::size_t>(n_pixels, 1);
      pixel_buffer(pixels, pixels.reservoirs, bytes, 0, "the per-pixel reservoirs").bind(VR_RIS_BINDING_RESERVOIRS);
    }
    if (ris_pool) {
      det["ris"]["pool"] = es.ris_pool;
      pixel_buffer(pixels, pixels.ris_pool, sizeof(vplkit::gpu::ris_pool_record) * ris_pool_entries, 0,
                   "the candidate pool")
          .bind(VR_RIS_BINDING_POOL);
    }
  }
  gl::check_gl("estimate kernel bindings");

  // llvmpipe's loop budget (loop_budget.hpp): only there (or when forced) are the units split.
  const bool budget = loop_budget_applies(es.loop_budget);
  const long long query_cost = gpu_query_cost(&scene, vis, grid.resolution);
  const shape_inputs in{view.resolution, query_cost, std::max(1, n_dists), local_rounds, shadow_ray};
  struct stage_plan {
    const gpu_kernel_stage* stage;
    long long units, chunk;
    int passes;
    bool split;
  };
  std::vector<stage_plan> plans;
  int passes = 0;
  bool any_split = false;
  if (ris_reuse) {
    // Rounds of a candidate and a reuse dispatch, in the order of render/cpu/ris_render.hpp: a
    // round is not split (its reservoir is one unit), so each must fit the loop budget.
    for (int pass : {ris_pass_candidates, ris_pass_reuse})
      if (budget && ris_round_cost(es, in, pass) > gpu_loop_budget)
        throw vplkit::invalid_input(std::string("--method ") + mt.name + " --spatial " + std::to_string(es.ris_spatial) + " --candidates " +
                                    std::to_string(es.ris_candidates) + ": a round's " +
                                    (pass == ris_pass_candidates ? "candidates" : "reuse") +
                                    " exceed the software GL driver's loop limit; use fewer --candidates");
    const int rounds = ris_reuse_rounds(es);
    plans.push_back({&kern.stages.front(), rounds, 1, rounds, true});
    if (compensate) {  // all of it in the last round's reuse (estimate_ris.comp)
      P.clamp_dirs = clamp_compensation_dirs(es);
      P.clamp_first_unit = rounds;
    }
    passes = 2 * rounds;
    any_split = true;  // the sum and the random stream live in the state buffer between the passes
  }
  for (const gpu_kernel_stage& st : kern.stages) {
    if (ris_reuse) break;
    const work_shape shape = st.shape(es, in);
    // A ris sample (its M candidates; ris-mis: a step) is one unit: the split cannot shorten it.
    if (ris && budget && shape.cost > gpu_loop_budget)
      throw vplkit::invalid_input(std::string("--method ") + mt.name + " --candidates " +
                                  std::to_string(es.ris_candidates) +
                                  ": one sample's candidates exceed the software GL driver's loop limit; use fewer "
                                  "--candidates");
    const long long units = std::max(1LL, shape.units);
    long long chunk = budget ? std::min(units, units_per_pass(shape)) : units;
    if (es.max_units_per_pass > 0) chunk = std::min<long long>(chunk, es.max_units_per_pass);
    const int n = static_cast<int>((units + chunk - 1) / chunk);
    plans.push_back({&st, units, chunk, n, n > 1});
    if (compensate) {  // inline, the directions are the last units (with_clamp_compensation)
      P.clamp_dirs = clamp_compensation_dirs(es);
      P.clamp_first_unit = static_cast<int>(compacted ? units : units - P.clamp_dirs);
    }
    passes += n;
    any_split = any_split || n > 1;
  }
  // The pixel's state between split dispatches: only when a stage is split.
  if (any_split) {
    const std::size_t state_bytes = sizeof(gpu::pixel_state) * std::max<std::size_t>(n_pixels, 1);
    pixel_buffer(pixels, pixels.state, state_bytes, 0, "the per-pixel estimator state").bind(VR_ESTIMATE_BINDING_STATE);
  }
  nlohmann::json kernels = nlohmann::json::array();
  for (const stage_plan& sp : plans)
    for (int pass : ris_reuse ? std::vector<int>{ris_pass_candidates, ris_pass_reuse} : std::vector<int>{ris_pass_estimate})
      kernels.push_back({{"kernel", gpu_kernel_path(*sp.stage)},
                         {"passes", sp.passes},
                         {"units_per_pass", sp.chunk},
                         {"defines", define_list(gpu_kernel_defines(es, vis, components, shadow_ray, sp.split, pass))}});
  det["gpu"] = {{"kernel", gpu_kernel_path(*plans.back().stage)},
                {"stages", kernels},
                {"passes", passes},
                {"units_per_pass", plans.back().chunk},
                {"loop_budget", budget ? nlohmann::json(gpu_loop_budget) : nlohmann::json("none")},
                {"query_cost", query_cost},
                {"builders", with_dists ? "gpu (weights and CDFs stay on the GPU; totals read back)" : "none"},
                {"cdf", with_dists ? "gpu (cdf_build.comp)" : "none"},
                {"direct_light", es.direct ? "gpu (estimate kernel)" : "off"}};
  // The clamp's compensation, compacted: its passes before the estimate kernel, which adds their terms.
  const gl::buffer* b_clamp_list = nullptr;
  gl::timer_query tq_clamp_list, tq_clamp_dirs;
  if (compacted) {
    P.clamp_dirs = clamp_compensation_dirs(es);
    P.clamp_max_groups_x = static_cast<int>(gl::max_work_group_count(0));
    // The terms go to the estimates' buffer (b_out), which the estimate kernel reads before it
    // writes the estimate over them (estimate_io.glsl).
    const gl::buffer& list = pixel_buffer(pixels, pixels.clamp_list, 16 + 4 * std::max<std::size_t>(n_pixels, 1), 0,
                                          "the clamp compensation's pixel list");
    list.bind(VR_ESTIMATE_BINDING_CLAMP_LIST);
    b_clamp_list = &list;
    det["gpu"]["clamp_compensation"] =
        run_clamp_compensation_passes(es, vis, shadow_ray, in, budget, n_pixels, P, b_params, list, tq_clamp_list,
                                      tq_clamp_dirs);
  }
  {
    gl::timer_query tq;
    tq.begin();
    int done = 0;
    if (ris_pool) {  // inside the estimate's time: every frame fills its pool
      const gl::program& fill = gpu_kernel_program(kern.stages.front(),
                                                   gpu_kernel_defines(es, vis, components, shadow_ray, false, ris_pass_pool));
      P.first_pass = 1;
      P.last_pass = 0;
      b_params.write_bytes(&P, 0, sizeof P);
      gl::dispatch_linear(fill, gl::groups_for(ris_pool_entries, fill.local_size()[0]));
    }
    if (ris_reuse) {
      const gl::program& cand = gpu_kernel_program(*plans.front().stage,
                                                   gpu_kernel_defines(es, vis, components, shadow_ray, true, ris_pass_candidates));
      const gl::program& reuse = gpu_kernel_program(*plans.front().stage,
                                                    gpu_kernel_defines(es, vis, components, shadow_ray, true, ris_pass_reuse));
      const GLuint groups = gl::groups_for(n_pixels, cand.local_size()[0]);
      const int rounds = plans.front().passes;
      P.begin = 0;
      P.end = 1;
      for (int r = 0; r < rounds; ++r) {
        // ris-mis's kernel reads the round (its step) from begin: which of its parts run in it.
        if (mt.variant == 1) {
          P.begin = r;
          P.end = r + 1;
        }
        // Candidates: a fresh stream in round 0, then the state's; the state is kept.
        P.first_pass = r == 0 ? 1 : 0;
        P.last_pass = 0;
        b_params.write_bytes(&P, 0, sizeof P);
        gl::dispatch_linear(cand, groups);
        // Reuse: reads the state and the reservoirs; the last round writes the estimate.
        P.first_pass = 0;
        P.last_pass = r == rounds - 1 ? 1 : 0;
        b_params.write_bytes(&P, 0, sizeof P);
        gl::dispatch_linear(reuse, groups);
        done += 2;
        if (progress && passes > 1) {
          glFinish();
          progress("render (gpu)", static_cast<std::uint64_t>(done), static_cast<std::uint64_t>(passes));
        }
      }
    }
    for (const stage_plan& sp : plans) {
      if (ris_reuse) break;
      const gl::program& prog = gpu_kernel_program(*sp.stage, gpu_kernel_defines(es, vis, components, shadow_ray, sp.split));
      const GLuint groups = gl::groups_for(n_pixels, prog.local_size()[0]);
      for (int k = 0; k < sp.passes; ++k) {
        P.begin = static_cast<int>(k * sp.chunk);
        P.end = static_cast<int>(std::min(sp.units, (k + 1) * sp.chunk));
        P.first_pass = k == 0 ? 1 : 0;
        P.last_pass = k == sp.passes - 1 ? 1 : 0;
        b_params.write_bytes(&P, 0, sizeof P);
        gl::dispatch_linear(prog, groups);
        ++done;
        if (progress && passes > 1) {
          glFinish();
          progress("render (gpu)", static_cast<std::uint64_t>(done), static_cast<std::uint64_t>(passes));
        }
      }
    }
    tq.end();
    if (compacted) {  // the compensation's queries, read now that the estimate is issued
      const double list_ms = tq_clamp_list.milliseconds(), dirs_ms = tq_clamp_dirs.milliseconds();
      det["gpu"]["clamp_compensation"]["list_ms"] = list_ms;
      det["gpu"]["clamp_compensation"]["directions_ms"] = dirs_ms;
      timer.add(clamp_compensation_stage_gpu, list_ms + dirs_ms, "gpu");
    }
    timer.add("estimate (gpu)", tq.milliseconds(), "gpu");
  }
  {
    auto t = timer.scoped("read-back (cpu)");
    // The only read-back of the frame: the image. The kernels write 0 where there is no gather
    // point, so no G-buffer is needed here.
    const std::vector<glm::vec4> out = b_out.read<glm::vec4>(n_pixels);
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) {
        const int p = y * W + x;
        glm::vec3 c = glm::vec3(out[static_cast<std::size_t>(p)]);  // direct light included (the estimate kernel; 0 off the scene)
        c = vplkit::estimator_finite_or_zero(glm::max(c, glm::vec3(0.0f)));
        float* o = result.image.at(x, y);
        o[0] = c.x;
        o[1] = c.y;
        o[2] = c.z;
      }
  }
  // How many pixels the compacted compensation listed (after the image's read-back: no wait of its own).
  if (b_clamp_list != nullptr) {
    glm::uvec4 header(0u);
    b_clamp_list->read_bytes(&header, 0, sizeof header);
    det["gpu"]["clamp_compensation"]["pixels"] = header.w;
  }
  return result;
}

}  // namespace vplrender
