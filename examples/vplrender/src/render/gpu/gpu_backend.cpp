#include "render/gpu/gpu_backend.hpp"

#include "render/gpu/gpu_builders.hpp"

#include <headless_gl/compute.hpp>

#include <vplkit/builders/gbg_accumulate_params.h>
#include <vplkit/builders/gbg_finish_params.h>
#include <vplkit/builders/gbg_weights.hpp>
#include <vplkit/builders/vpl_distribution.hpp>
#include <vplkit/core/error.hpp>
#include <vplkit/estimators/vpl_sum.hpp>
#include <vplkit/visibility/voxel_visible.hpp>
#include <vplkit/vpl/luminance.hpp>

#include <glm/vec4.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <map>
#include <sstream>
#include <vector>

#ifndef VPLRENDER_SHADER_DIR
#error "VPLRENDER_SHADER_DIR must name examples/vplrender/shaders (set by core.cmake)"
#endif

namespace vplrender {

namespace {

// VR_METHOD values of estimate.comp.
enum kernel_kind { k_reference = 0, k_vpl_sampling = 1, k_local = 2, k_gather = 3, k_mis = 4 };

kernel_kind kernel_of(method m) {
  switch (m) {
    case method::reference: return k_reference;
    case method::global:
    case method::gbg: return k_vpl_sampling;
    case method::local: return k_local;
    case method::gather: return k_gather;
    case method::mis:
    case method::mis_as_published: return k_mis;
  }
  return k_reference;
}

const vplkit::gl::program& kernel(kernel_kind k) {
  static std::map<int, vplkit::gl::program> cache;  // compiled once per process and kind
  auto it = cache.find(k);
  if (it != cache.end()) return it->second;
  const std::string path = std::string(VPLRENDER_SHADER_DIR) + "/estimate.comp";
  std::ifstream f(path, std::ios::binary);
  if (!f) throw vplkit::gl::gl_error("cannot read " + path);
  std::ostringstream text;
  text << "#version 430\n" << f.rdbuf();
  vplkit::gl::program prog = vplkit::gl::program::compute_with_includes(
      text.str(), path, {}, "#define VR_METHOD " + std::to_string(static_cast<int>(k)) + "\n");
  return cache.emplace(k, std::move(prog)).first->second;
}

// Worst-case loop iterations of one unit of work (a texel, sample, round, direction or MIS step)
// and the number of units.
struct work_shape {
  long long cost = 1;
  long long units = 0;
};

work_shape shape_of(const estimator_settings& es, int R, const vplkit::ivec3& vr, int regions, int rounds) {
  // One voxel march crosses at most rx + ry + rz voxels; doubled for the two-sided test's loops.
  const long long dda = 2LL * (vr.x + vr.y + vr.z) + 32;
  const long long texels = 2LL * R * R;
  long long log2n = 1;
  while ((1LL << log2n) < texels) ++log2n;
  const long long cdf = 2 * (log2n + 4);  // guided search (binary search in the worst bucket), twice
  work_shape s;
  switch (kernel_of(es.meth)) {
    case k_reference: s.cost = dda + 4; s.units = texels; break;
    case k_vpl_sampling: s.cost = dda + cdf + 4; s.units = es.vpls; break;
    case k_local: s.cost = regions * (dda + cdf + regions + 4); s.units = rounds; break;
    case k_gather: s.cost = dda + 4; s.units = es.dirs; break;
    case k_mis: s.cost = 2 * dda + cdf + 8; s.units = std::max(es.dirs, es.vpls); break;
  }
  return s;
}

const vplkit::gl::program& pack_kernel(const std::string& rel) {
  static std::map<std::string, vplkit::gl::program> cache;
  auto it = cache.find(rel);
  if (it != cache.end()) return it->second;
  // The pack's own include root (headless_gl's default) resolves both the kernel and its includes.
  vplkit::gl::program prog = vplkit::gl::program::compute_with_includes(
      "#version 430\n#include \"" + rel + "\"\n", rel);
  return cache.emplace(rel, std::move(prog)).first->second;
}

}  // namespace

bool gpu_estimator_available(method) { return true; }

bool gpu_builder_available(method m) {
  return m == method::global || m == method::local || m == method::gbg || m == method::mis ||
         m == method::mis_as_published;
}

gbg_gpu_weights build_gbg_weights_gpu(const gbuffer_data& gb, const dprsm_data& dd,
                                      const vplkit::voxel_grid_view<float>& grid, const estimator_settings& es,
                                      stage_timer& timer, nlohmann::json& det, bool read_back) {
  namespace gl = vplkit::gl;
  const vplkit::gbuffer_view<float> g = gb.view();
  const vplkit::dprsm_view<float> view = dd.view();
  g.validate();
  view.validate();
  if (es.dirs < 1) throw vplkit::invalid_input("build_gbg_weights_gpu: --dirs must be >= 1");
  const int W = g.width, H = g.height, R = view.resolution;
  const std::size_t n_pixels = static_cast<std::size_t>(W) * static_cast<std::size_t>(H);
  const std::size_t n = static_cast<std::size_t>(view.texel_count());
  const float depth_tol = gathering_depth_tolerance(grid);
  int gather_points = 0;
  for (std::size_t p = 0; p < n_pixels; ++p)
    if (vplkit::gather_point_valid(g.at(static_cast<int>(p)))) ++gather_points;

  // Fixed point as gbg_weights.glsl recommends: max_units = 2^(63 - ceil(log2(|G| n_dirs))) keeps any
  // texel's sum below 2^63; scale = 2^floor(log2(max_units / v_bound)) with v_bound the gathering
  // accumulator's largest per-hit value, I / (pi d1min^2) in luminance, d1min the nearest lit
  // texel's distance to the light less the depth tolerance. A power of two, so 1 / scale is exact.
  const double hits_max = std::max(1.0, double(std::max(gather_points, 1)) * es.dirs);
  const double max_units = std::ldexp(1.0, 63 - static_cast<int>(std::ceil(std::log2(hits_max))));
  double d1min = 1e30;
  for (std::size_t t = 0; t < n; ++t)
    if (dd.albedo[t] != glm::vec3(0.0f))
      d1min = std::min(d1min, double(glm::length(dd.position[t] - view.light.position)));
  d1min = std::max(d1min - double(depth_tol), 1e-3);
  // The paper accumulator (luminance of eq. 5 clamped at dmin) is bounded instead by
  // luminance(I) Omega_max / (pi^2 dmin^2), Omega_max = 4 (2/R)^2 (gbg_weights.glsl); dmin > 0 here.
  const bool paper_acc = es.gbg_accumulator == gbg_accumulator_choice::paper;
  const double lum_i = std::max(double(vplkit::luminance(view.light.intensity)), 1e-30);
  const double dmin_b = std::max(double(es.dmin), 1e-6);
  const double v_bound = paper_acc ? lum_i * (16.0 / (double(R) * R)) / (9.869604401089358 * dmin_b * dmin_b)
                                   : lum_i / (3.141592653589793 * d1min * d1min);
  const double scale = std::ldexp(1.0, static_cast<int>(std::floor(std::log2(max_units / v_bound))));

  std::vector<glm::vec4> gbuf(3 * std::max<std::size_t>(n_pixels, 1), glm::vec4(0.0f));
  for (std::size_t i = 0; i < n_pixels; ++i) {
    gbuf[3 * i] = glm::vec4(gb.position[i], 0.0f);
    gbuf[3 * i + 1] = glm::vec4(gb.normal[i], 0.0f);
    gbuf[3 * i + 2] = glm::vec4(gb.albedo[i], 0.0f);
  }
  std::vector<glm::vec4> dprsm(3 * n, glm::vec4(0.0f));
  for (std::size_t i = 0; i < n; ++i) {
    dprsm[3 * i] = glm::vec4(dd.position[i], 0.0f);
    dprsm[3 * i + 1] = glm::vec4(dd.normal[i], 0.0f);
    dprsm[3 * i + 2] = glm::vec4(dd.albedo[i], 0.0f);
  }
  std::vector<std::uint32_t> words(grid.words, grid.words + vplkit::voxel_word_count(grid.resolution));
  if (words.empty()) words.push_back(0u);

  const gl::program& acc_prog = pack_kernel("vplkit/builders/gbg_accumulate.comp");
  const gl::program& fin_prog = pack_kernel("vplkit/builders/gbg_finish.comp");
  gl::buffer b_gbuf = gl::buffer::from_vector(gbuf);
  gl::buffer b_dprsm = gl::buffer::from_vector(dprsm);
  gl::buffer b_words = gl::buffer::from_vector(words);
  gl::buffer b_acc = gl::buffer::filled(2 * n * 4, 0);
  gl::buffer b_stats = gl::buffer::filled(VPLKIT_GBG_STATS_SIZE * 4, 0);
  gl::buffer b_weights = gl::buffer::filled(n * 4, 0);

  // llvmpipe leaves every loop after 65535 iterations per invocation: one ray marches at most
  // nx + ny + nz voxels (+ 8 for the rest of its body), so split the directions over dispatches
  // (the fixed-point sums do not depend on the split).
  const long long per_dir = static_cast<long long>(grid.resolution.x) + grid.resolution.y + grid.resolution.z + 8;
  const int dirs_per = static_cast<int>(std::max(1LL, gpu_loop_budget / per_dir));
  const GLuint groups = gl::groups_for(std::max<std::size_t>(n_pixels, 1), VPLKIT_GBG_LOCAL_SIZE);
  const GLuint gx = std::min<GLuint>(groups, 65535u);
  const GLuint gy = (groups + gx - 1) / gx;
  const vplkit::gpu::light_params light = vplkit::gpu::make_light_params(view.light);
  std::vector<gl::buffer> blocks;
  int dispatches = 0;
  {
    gl::timer_query tq;
    tq.begin();
    for (int begin = 0; begin < es.dirs; begin += dirs_per) {
      const int end = std::min(es.dirs, begin + dirs_per);
      vplkit::gpu::gbg_accumulate_params p{};
      p.light = light;
      p.grid_min = glm::vec4(grid.bounds_min, 0.0f);
      p.grid_max = glm::vec4(grid.bounds_max, 0.0f);
      p.grid_resolution = glm::ivec4(grid.resolution, 0);
      p.width = W;
      p.height = H;
      p.resolution = R;
      p.n_dirs = es.dirs;
      p.accumulator = paper_acc ? 0 : 1;
      p.dir_begin = begin;
      p.dir_end = end;
      p.count_gather_points = begin == 0 ? 1 : 0;
      p.seed = builder_seed(es.seed, 2);
      p.dmin = es.dmin;
      p.depth_tolerance = depth_tol;
      p.offset_voxels = float(vplkit::voxel_surface_offset_default);
      p.scale = float(scale);
      p.max_units = float(max_units);
      blocks.push_back(gl::buffer::from_bytes(&p, sizeof p));
      b_gbuf.bind(VPLKIT_GBG_BINDING_GBUFFER);
      b_dprsm.bind(VPLKIT_GBG_BINDING_DPRSM);
      b_words.bind(VPLKIT_GBG_BINDING_VOXELS);
      b_acc.bind(VPLKIT_GBG_BINDING_ACC);
      b_stats.bind(VPLKIT_GBG_BINDING_STATS);
      glBindBufferBase(GL_UNIFORM_BUFFER, VPLKIT_GBG_BINDING_PARAMS, blocks.back().id());
      gl::dispatch(acc_prog, gx, gy);
      ++dispatches;
    }
    vplkit::gpu::gbg_finish_params fp{};
    fp.light = light;
    fp.resolution = R;
    fp.n_dirs = es.dirs;
    fp.fill_holes = 1;
    fp.inv_scale = float(1.0 / scale);
    blocks.push_back(gl::buffer::from_bytes(&fp, sizeof fp));
    b_acc.bind(VPLKIT_GBG_FINISH_BINDING_ACC);
    b_stats.bind(VPLKIT_GBG_FINISH_BINDING_STATS);
    b_dprsm.bind(VPLKIT_GBG_FINISH_BINDING_DPRSM);
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
                {"rays", static_cast<long long>(g_points) * es.dirs},
                {"hits", st[VPLKIT_GBG_STAT_HITS]},
                {"lit_hits", st[VPLKIT_GBG_STAT_LIT_HITS]},
                {"reached_texels", st[VPLKIT_GBG_STAT_REACHED_TEXELS]},
                {"holes", st[VPLKIT_GBG_STAT_HOLES]},
                {"filled", st[VPLKIT_GBG_STAT_FILLED]},
                {"accumulator", to_string(es.gbg_accumulator)},
                {"backend", "gpu"},
                {"fixed_point_scale", scale},
                {"fixed_point_max_units", max_units},
                {"saturated_hits", st[VPLKIT_GBG_STAT_SATURATED_HITS]},
                {"dispatches", dispatches}};
  return out;
}

int gpu_pass_count(const estimator_settings& es, int dprsm_resolution, const vplkit::ivec3& voxel_resolution,
                   int regions) {
  const int rounds = std::max(1, es.vpls / std::max(1, regions));
  const work_shape s = shape_of(es, dprsm_resolution, voxel_resolution, regions, rounds);
  const long long chunk = std::max(1LL, gpu_loop_budget / s.cost);
  return static_cast<int>((s.units + chunk - 1) / chunk);
}

cpu_render_result render_gpu(const gbuffer_data& gb, const dprsm_data& dd, const vplkit::voxel_grid_view<float>& grid,
                             const estimator_settings& es, stage_timer& timer, const progress_fn& progress) {
  namespace gl = vplkit::gl;
  const vplkit::gbuffer_view<float> g = gb.view();
  const vplkit::dprsm_view<float> view = dd.view();
  g.validate();
  view.validate();
  const int W = g.width, H = g.height;
  const std::size_t n_pixels = static_cast<std::size_t>(W) * static_cast<std::size_t>(H);
  cpu_render_result result;
  result.image = image_rgb(W, H);
  nlohmann::json& det = result.details;
  det["threads"] = estimator_threads(es.threads);  // CPU builders
  det["dmin"] = es.dmin;
  const float depth_tol = gathering_depth_tolerance(grid);
  det["depth_tolerance"] = depth_tol;
  det["cdf_search"] = to_string(es.cdf_search);
  // Builders and CDFs on the GPU (gpu_builders.cpp, gpu_cdf.cpp): the mixtures stay there. The
  // methods without a builder (reference, gather) sample no distribution at all.
  const bool gpu_dists = gpu_builder_available(es.meth);
  gpu_mixtures gm;
  if (gpu_dists) gm = build_distributions_gpu(gb, dd, grid, es, timer, det);
  const int local_rounds = gpu_dists ? gm.local_rounds : 0;
  const kernel_kind kind = kernel_of(es.meth);

  std::vector<glm::vec4> gbuf(3 * std::max<std::size_t>(n_pixels, 1), glm::vec4(0.0f));
  std::vector<glm::vec4> dprsm(3 * static_cast<std::size_t>(view.texel_count()), glm::vec4(0.0f));
  std::vector<std::uint32_t> words;
  {
    auto t = timer.scoped("upload (cpu)");
    for (std::size_t i = 0; i < n_pixels; ++i) {
      gbuf[3 * i] = glm::vec4(gb.position[i], 0.0f);
      gbuf[3 * i + 1] = glm::vec4(gb.normal[i], 0.0f);
      gbuf[3 * i + 2] = glm::vec4(gb.albedo[i], 0.0f);
    }
    for (std::size_t i = 0; i < dprsm.size() / 3; ++i) {
      dprsm[3 * i] = glm::vec4(dd.position[i], 0.0f);
      dprsm[3 * i + 1] = glm::vec4(dd.normal[i], 0.0f);
      dprsm[3 * i + 2] = glm::vec4(dd.albedo[i], 0.0f);
    }
    words.assign(grid.words, grid.words + vplkit::voxel_word_count(grid.resolution));
    if (words.empty()) words.push_back(0u);
  }
  const std::uint32_t slot_base = gpu_dists ? gm.slot_base : 0u;
  const int n_dists = gpu_dists ? gm.count : 0;

  gl::buffer b_gbuf = gl::buffer::from_vector(gbuf);
  gl::buffer b_dprsm = gl::buffer::from_vector(dprsm);
  gl::buffer b_words = gl::buffer::from_vector(words);
  // Without distributions the kernel still binds both buffers: one zero word each.
  gl::buffer b_data = gpu_dists ? std::move(gm.data) : gl::buffer::filled(4, 0);
  gl::buffer b_meta = gpu_dists ? std::move(gm.meta) : gl::buffer::filled(4, 0);
  gl::buffer b_state = gl::buffer::filled(48 * std::max<std::size_t>(n_pixels, 1), 0);
  gl::buffer b_out = gl::buffer::filled(16 * std::max<std::size_t>(n_pixels, 1), 0xFF);

  const gl::program& prog = kernel(kind);
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
  set_i("u_local_combination", es.local_combination == local_combination_choice::average ? 1 : 0);
  glUniform1ui(prog.uniform_location("u_slot_base"), slot_base);
  gl::check_gl("estimate.comp uniforms");
  b_gbuf.bind(0);
  b_dprsm.bind(1);
  b_words.bind(2);
  b_data.bind(3);
  b_meta.bind(4);
  b_state.bind(5);
  b_out.bind(6);

  const int regions = std::max(1, n_dists);
  const work_shape shape = shape_of(es, view.resolution, grid.resolution, regions, local_rounds);
  const long long chunk = std::max(1LL, gpu_loop_budget / shape.cost);
  const long long units = std::max(1LL, shape.units);
  const int passes = static_cast<int>((units + chunk - 1) / chunk);
  const GLuint groups = gl::groups_for(n_pixels, prog.local_size()[0]);
  const GLuint gx = std::min<GLuint>(groups, 65535u);
  const GLuint gy = (groups + gx - 1) / gx;
  det["gpu"] = {{"kernel", "examples/vplrender/shaders/estimate.comp"},
                {"passes", passes},
                {"units_per_pass", chunk},
                {"loop_budget", gpu_loop_budget},
                {"builders", gpu_dists ? "gpu (weights and CDFs stay on the GPU; totals read back)"
                                                            : "none"},
                {"cdf", gpu_dists ? "gpu (cdf_build.comp)" : "none"},
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
      gl::dispatch(prog, gx, gy);
      if (progress && passes > 1) {
        glFinish();
        progress("render (gpu)", static_cast<std::uint64_t>(k + 1), static_cast<std::uint64_t>(passes));
      }
    }
    tq.end();
    timer.add("estimate (gpu)", tq.milliseconds(), "gpu");
  }
  const std::vector<glm::vec4> out = b_out.read<glm::vec4>(n_pixels);
  {
    auto t = timer.scoped("read-back (cpu)");
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) {
        const int p = y * W + x;
        const vplkit::gather_point<float> gp = g.at(p);
        glm::vec3 c(0.0f);
        if (vplkit::gather_point_valid(gp)) {
          c = glm::vec3(out[static_cast<std::size_t>(p)]);  // direct light included (estimate.comp)
          c = vplkit::estimator_finite_or_zero(glm::max(c, glm::vec3(0.0f)));
        }
        float* o = result.image.at(x, y);
        o[0] = c.x;
        o[1] = c.y;
        o[2] = c.z;
      }
  }
  return result;
}

}  // namespace vplrender
