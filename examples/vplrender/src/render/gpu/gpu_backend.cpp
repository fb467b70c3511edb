// SPDX-License-Identifier: MIT
#include "render/gpu/gpu_backend.hpp"

#include "raster/gpu_scene_buffers.hpp"
#include "render/cpu/cpu_visibility.hpp"
#include "render/gpu/gpu_allocating.hpp"
#include "render/gpu/gpu_builders.hpp"
#include "render/gpu/gpu_visibility.hpp"
#include "render/gpu/loop_budget.hpp"
#include "render/mixture_components.hpp"

#include <headless_gl/compute.hpp>

#include <vplkit/core/gather_point.hpp>
#include <vplkit/estimators/vpl_sum.hpp>

#include <glm/common.hpp>
#include <glm/vec4.hpp>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#ifndef VPLRENDER_SHADER_DIR
#error "VPLRENDER_SHADER_DIR must name examples/vplrender/shaders (set by core.cmake)"
#endif

namespace vplrender {

namespace {

// mixture_components in the layout of estimate.comp's binding 7 (VrComponents): 12 uints per
// component k = 2 d + c, then the arrays they point into. Roulette: the front face's CDF and
// guide offsets and total, the back face's, b_front, b_back, front_scale, back_scale (the C++
// roulette's own values, so the GPU picks its face bit for bit), the face size and guide size
// (both faces have R^2 entries). Alias: the bins' offset (3 uints per bin), 0, total, 0 ..., the
// table size.
std::vector<std::uint32_t> pack_components(const mixture_components& c) {
  const std::size_t k_count = std::max(c.alias.size(), c.roulette.size());
  std::vector<std::uint32_t> out(12 * std::max<std::size_t>(k_count, 1), 0u);
  auto bits = [](float f) {
    std::uint32_t u;
    std::memcpy(&u, &f, 4);
    return u;
  };
  auto append = [&](const auto& v) {
    const std::size_t at = out.size();
    out.resize(at + v.size() * sizeof(v[0]) / 4);
    std::memcpy(out.data() + at, v.data(), v.size() * sizeof(v[0]));
    return static_cast<std::uint32_t>(at);
  };
  for (std::size_t k = 0; k < c.alias.size(); ++k) {
    const std::uint32_t bins = append(c.alias[k].bins());
    out[12 * k] = bins;
    out[12 * k + 2] = bits(c.alias[k].total());
    out[12 * k + 10] = static_cast<std::uint32_t>(c.alias[k].size());
  }
  for (std::size_t k = 0; k < c.roulette.size(); ++k) {
    const vplkit::face_roulette<float>& f = c.roulette[k];
    const std::uint32_t front_cdf = append(f.front().cdf()), front_guide = append(f.front().guide());
    const std::uint32_t back_cdf = append(f.back().cdf()), back_guide = append(f.back().guide());
    const std::uint32_t rec[12] = {front_cdf,
                                   front_guide,
                                   bits(f.front().total()),
                                   back_cdf,
                                   back_guide,
                                   bits(f.back().total()),
                                   bits(f.front_probability()),
                                   bits(f.back_probability()),
                                   bits(f.front_scale()),
                                   bits(f.back_scale()),
                                   static_cast<std::uint32_t>(f.front().size()),
                                   static_cast<std::uint32_t>(f.front().guide_size())};
    std::memcpy(&out[12 * k], rec, sizeof(rec));
  }
  return out;
}

// VR_METHOD values of estimate.comp, and k_exact: exact.comp, the kernel of --method exact.
enum kernel_kind { k_reference = 0, k_vpl_sampling = 1, k_local = 2, k_gather = 3, k_mis = 4, k_exact = 5 };

kernel_kind kernel_of(method m) {
  switch (m) {
    case method::reference: return k_reference;
    case method::global:
    case method::gbg: return k_vpl_sampling;
    case method::local: return k_local;
    case method::gather: return k_gather;
    case method::mis:
    case method::mis_as_published: return k_mis;
    case method::exact: return k_exact;
    case method::ris: throw vplkit::invalid_input("--method ris: no GPU kernel yet (run_estimator refuses it)");
  }
  return k_reference;
}

// What the rays are traced against: --method exact always traces the triangles.
visibility_choice visibility_of(const render_settings& es) {
  return es.meth == method::exact ? visibility_choice::exact : es.visibility;
}

// estimate.comp compiled once per kind, visibility and lit test, exact.comp once (the process's
// program cache).
const vplkit::gl::program& kernel(kernel_kind k, visibility_choice v, bool shadow_ray) {
  if (k == k_exact) return vplkit::gl::cached_kernel(std::string(VPLRENDER_SHADER_DIR) + "/exact.comp");
  return vplkit::gl::cached_kernel(std::string(VPLRENDER_SHADER_DIR) + "/estimate.comp",
                                   "#define VR_METHOD " + std::to_string(static_cast<int>(k)) + "\n" +
                                       estimate_visibility_define(v) + (shadow_ray ? "#define VR_LIT_SHADOW_RAY\n" : ""));
}

// Worst-case loop iterations of one unit of work (a texel, sample, round, direction or MIS step),
// the number of units, and the iterations every pass spends besides its units.
struct work_shape {
  long long cost = 1;
  long long units = 0;
  long long fixed = 0;
};

// Loop iterations ray_scene.glsl's texture lookup may spend: vr_wrap_integral's doubling loop (at
// most 104 iterations, only for uv beyond 2^24 / size) for x and for y.
constexpr long long texture_wrap_cost = 2 * 104;

work_shape shape_of(const render_settings& es, int R, long long query_cost, int regions, int rounds) {
  // One query's loops (gpu_query_cost), doubled for the two-sided voxel test's two marches (a
  // margin for the other kinds).
  const long long dda = 2LL * query_cost + 32;
  const long long texels = 2LL * R * R;
  long long log2n = 1;
  while ((1LL << log2n) < texels) ++log2n;
  const long long cdf = 2 * (log2n + 4);  // guided search (binary search in the worst bucket), twice
  // A patch reference texel runs its m x m strata, each a query.
  const long long strata = es.vpl_mode == vpl_mode_choice::patch ? 1LL * reference_patch_strata * reference_patch_strata : 1;
  work_shape s;
  switch (kernel_of(es.meth)) {
    case k_reference: s.cost = strata * (dda + 4); s.units = texels; break;
    case k_vpl_sampling: s.cost = dda + cdf + 4; s.units = es.vpls; break;
    case k_local: s.cost = regions * (dda + cdf + regions + 4); s.units = rounds; break;
    case k_gather: s.cost = dda + 4; s.units = es.dirs; break;
    case k_mis: s.cost = 2 * dda + cdf + 8; s.units = std::max(es.dirs, es.vpls); break;
    // A direction: its first hit and the hit's shadow ray; a pass: the gather point's camera ray.
    case k_exact:
      s.cost = 2 * query_cost + texture_wrap_cost + 32;
      s.units = es.dirs;
      s.fixed = query_cost;
      break;
  }
  return s;
}

// Directions (samples, texels, ...) per pass under the loop budget.
long long units_per_pass(const work_shape& s) { return std::max(1LL, (gpu_loop_budget - s.fixed) / s.cost); }

}  // namespace

int gpu_pass_count(const render_settings& es, int dprsm_resolution, const vplkit::ivec3& voxel_resolution,
                   int regions) {
  const int rounds = std::max(1, es.vpls / std::max(1, regions));
  const work_shape s =
      shape_of(es, dprsm_resolution, gpu_query_cost(nullptr, visibility_of(es), voxel_resolution), regions, rounds);
  const long long chunk = units_per_pass(s);
  return static_cast<int>((s.units + chunk - 1) / chunk);
}

render_result render_gpu(const frame_buffers& b, const render_settings& es, stage_timer& timer,
                         const progress_fn& progress) {
  namespace gl = vplkit::gl;
  // A GPU frame's G-buffer and DPRSM live on the GPU: the views give their sizes and the light.
  const gpu_scene_buffers& scene = scene_on_gpu(b, "render_gpu");
  const vplkit::gbuffer_view<float> g = b.gbuf.view();
  const vplkit::dprsm_view<float> view = b.dprsm.view();
  const vplkit::voxel_grid_view<float> grid = b.grid.occupancy().view();
  const int W = g.width, H = g.height;
  const std::size_t n_pixels = static_cast<std::size_t>(W) * static_cast<std::size_t>(H);
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
  // methods without a builder (reference, gather) sample no distribution at all.
  const bool with_dists = has_distribution(es.meth);
  gpu_mixtures gm;
  if (with_dists) gm = build_distributions_gpu(b, es, timer, det);
  const int local_rounds = with_dists ? gm.local_rounds : 0;
  const kernel_kind kind = kernel_of(es.meth);
  // --method exact: the host's ray scene gives the offsets (checked first: its error names the method).
  const ray_scene* exact_rays = kind == k_exact ? &frame_ray_scene(b, "--method exact") : nullptr;
  if (kind == k_exact && !scene.shading.unavailable.empty())
    throw vplkit::invalid_input("--method exact on the GPU: " + scene.shading.unavailable);
  const std::uint32_t slot_base = with_dists ? gm.slot_base : 0u;
  const int n_dists = with_dists ? gm.count : 0;

  // Without distributions the kernel still binds both buffers: one zero word each.
  gl::buffer b_data = with_dists ? std::move(gm.data) : gl::buffer::filled(4, 0);
  gl::buffer b_meta = with_dists ? std::move(gm.meta) : gl::buffer::filled(4, 0);
  auto estimate_running = stage_timer::running("estimate (gpu)");
  const std::size_t state_bytes = 48 * std::max<std::size_t>(n_pixels, 1);
  const std::size_t out_bytes = 16 * std::max<std::size_t>(n_pixels, 1);
  gl::buffer b_state = gpu_allocating(state_bytes, "the per-pixel estimator state",
                                      [&] { return gl::buffer::filled(state_bytes, 0); });
  gl::buffer b_out = gpu_allocating(out_bytes, "the per-pixel estimates", [&] { return gl::buffer::filled(out_bytes, 0xFF); });
  // --sampler alias / --face-selection roulette: the components built on the host from the
  // weights read back (mixture_components.hpp), uploaded; else one zero word.
  const bool components = with_dists && mixture_components::wanted(es);
  gl::buffer b_components = gl::buffer::filled(4, 0);
  if (components) {
    auto t = timer.scoped("sampler tables (cpu)");
    const dprsm_data host = host_dprsm(b);  // the fallback's texels (read back for a GPU frame)
    b_components = gl::buffer::from_vector(
        pack_components(build_mixture_components(gm.weights.data(), gm.count, host.view(), es)));
  }
  det["face_selection"] = to_string(es.face_selection);
  det["sampler"] = to_string(es.sampler);
  if (uses_vpls(es.meth)) det["vpl_mode"] = to_string(es.vpl_mode);
  if (es.meth == method::reference && es.vpl_mode == vpl_mode_choice::patch)
    det["reference_strata"] = reference_patch_strata;

  const bool shadow_ray = es.lit_test == lit_test_choice::shadow_ray && vis == visibility_choice::exact &&
                          kind != k_exact;
  if (kind == k_gather || kind == k_mis)
    det["lit_test"] = to_string(shadow_ray ? lit_test_choice::shadow_ray : lit_test_choice::shadow_map);
  const gl::program& prog = kernel(kind, vis, shadow_ray);
  prog.use();
  auto set_i = [&](const char* n, int v) { glUniform1i(prog.uniform_location(n), v); };
  auto set_f = [&](const char* n, float v) { glUniform1f(prog.uniform_location(n), v); };
  auto set_v = [&](const char* n, const vec3& v) { glUniform3f(prog.uniform_location(n), v.x, v.y, v.z); };
  set_i("u_width", W);
  set_i("u_height", H);
  set_i("u_dprsm_res", view.resolution);
  set_v("u_light_pos", view.light.position);
  set_v("u_light_int", view.light.intensity);
  set_v("u_frame_pos", view.light.frame.position);
  set_v("u_axis_x", view.light.frame.axis_x);
  set_v("u_axis_y", view.light.frame.axis_y);
  set_v("u_axis_z", view.light.frame.axis_z);
  set_v("u_grid_min", grid.bounds_min);
  set_v("u_grid_max", grid.bounds_max);
  glUniform3i(prog.uniform_location("u_grid_res"), grid.resolution.x, grid.resolution.y, grid.resolution.z);
  set_f("u_dmin", es.dmin);
  set_f("u_depth_tol", depth_tol);
  glUniform1ui(prog.uniform_location("u_seed"), es.seed);
  set_i("u_n_dirs", es.dirs);
  set_i("u_n_vpls", es.vpls);
  set_i("u_n_samples", kind == k_local ? local_rounds : es.vpls);
  set_i("u_n_dists", n_dists);
  set_i("u_direct", es.direct ? 1 : 0);
  set_i("u_mis_mode", es.meth == method::mis_as_published ? 1 : 0);
  set_i("u_cdf_search", es.cdf_search == cdf_search_choice::binary ? 1 : 0);
  set_i("u_sampler", !components ? 0 : es.sampler == sampler_choice::alias ? 1 : 2);
  set_i("u_local_combination", es.local_combination == local_combination_choice::average ? 1 : 0);
  set_i("u_vpl_mode", es.vpl_mode == vpl_mode_choice::patch ? 1 : 0);  // vplkit_vpl_point / vplkit_vpl_patch
  set_i("u_strata", reference_patch_strata);
  glUniform1ui(prog.uniform_location("u_slot_base"), slot_base);
  gl::check_gl("estimate.comp uniforms");
  scene.gbuffer.bind(0);
  scene.dprsm.bind(1);
  scene.voxels.bind(2);
  b_data.bind(3);
  b_meta.bind(4);
  b_state.bind(5);
  b_out.bind(6);
  b_components.bind(7);
  glUniform1ui(prog.uniform_location("u_bvh_node_count"),
               bind_visibility_buffers(scene, vis, visibility_bindings{8, 9, 10, 11, 12, 13, 14}));
  if (kind != k_exact && vis == visibility_choice::exact) {
    // estimate.comp's exact tracer gives its hits' shading normals (ray_scene.glsl): the corner
    // normals at binding 10, as exact.comp reads them.
    scene.shading.triangles.bind(10);
    gl::check_gl("estimate.comp shading buffer");
  }
  if (kind == k_exact) {
    // exact.comp: the hits' shading (10, 11: the voxel triangle lists' bindings, unused with exact
    // visibility) and the host ray scene's offset, size and eye, so both backends move the same
    // points by the same amounts.
    const ray_scene& rs = *exact_rays;
    scene.shading.triangles.bind(10);
    scene.shading.pool.bind(11);
    set_f("u_surface_offset", rs.surface_offset());
    set_f("u_scene_size", rs.size());
    set_v("u_eye", rs.scene_camera().eye);
    gl::check_gl("exact.comp buffers and uniforms");
  }

  const int regions = std::max(1, n_dists);
  const work_shape shape =
      shape_of(es, view.resolution, gpu_query_cost(&scene, vis, grid.resolution), regions, local_rounds);
  const long long chunk = units_per_pass(shape);
  const long long units = std::max(1LL, shape.units);
  const int passes = static_cast<int>((units + chunk - 1) / chunk);
  const GLuint groups = gl::groups_for(n_pixels, prog.local_size()[0]);
  const char* kernel_file =
      kind == k_exact ? "examples/vplrender/shaders/exact.comp" : "examples/vplrender/shaders/estimate.comp";
  det["gpu"] = {{"kernel", kernel_file},
                {"passes", passes},
                {"units_per_pass", chunk},
                {"loop_budget", gpu_loop_budget},
                {"query_cost", gpu_query_cost(&scene, vis, grid.resolution)},
                {"builders", with_dists ? "gpu (weights and CDFs stay on the GPU; totals read back)" : "none"},
                {"cdf", with_dists ? "gpu (cdf_build.comp)" : "none"},
                {"direct_light", es.direct ? "gpu (estimate.comp)" : "off"}};
  {
    gl::timer_query tq;
    tq.begin();
    for (int k = 0; k < passes; ++k) {
      const long long begin = k * chunk, end = std::min(units, begin + chunk);
      set_i("u_begin", static_cast<int>(begin));
      set_i("u_end", static_cast<int>(end));
      set_i("u_first_pass", k == 0 ? 1 : 0);
      set_i("u_last_pass", k == passes - 1 ? 1 : 0);
      gl::dispatch_linear(prog, groups);
      if (progress && passes > 1) {
        glFinish();
        progress("render (gpu)", static_cast<std::uint64_t>(k + 1), static_cast<std::uint64_t>(passes));
      }
    }
    tq.end();
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
        glm::vec3 c = glm::vec3(out[static_cast<std::size_t>(p)]);  // direct light included (estimate.comp)
        c = vplkit::estimator_finite_or_zero(glm::max(c, glm::vec3(0.0f)));
        float* o = result.image.at(x, y);
        o[0] = c.x;
        o[1] = c.y;
        o[2] = c.z;
      }
  }
  return result;
}

}  // namespace vplrender
