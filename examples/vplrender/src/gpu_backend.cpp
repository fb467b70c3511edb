#include "gpu_backend.hpp"

#include <headless_gl/compute.hpp>

#include <vplkit/core/error.hpp>
#include <vplkit/estimators/vpl_sum.hpp>

#include <glm/vec4.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
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

std::uint32_t float_bits(float x) {
  std::uint32_t u;
  std::memcpy(&u, &x, sizeof u);
  return u;
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

}  // namespace

bool gpu_estimator_available(method) { return true; }

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
  const cpu_distributions built = build_distributions_cpu(gb, dd, grid, es, timer, progress, det);
  const kernel_kind kind = kernel_of(es.meth);

  std::vector<glm::vec4> gbuf(3 * std::max<std::size_t>(n_pixels, 1), glm::vec4(0.0f));
  std::vector<glm::vec4> dprsm(3 * static_cast<std::size_t>(view.texel_count()), glm::vec4(0.0f));
  std::vector<std::uint32_t> words, dist_data, meta;
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
    // Mixture d uses slots 2d (learned) and 2d + 1 (fallback); every slot stores cdf then guide.
    const std::size_t D = built.dists.size();
    std::vector<std::uint32_t> slots;
    auto add_slot = [&](const vplkit::discrete_cdf<float>& c) {
      slots.push_back(static_cast<std::uint32_t>(dist_data.size()));
      for (float x : c.cdf()) dist_data.push_back(float_bits(x));
      slots.push_back(static_cast<std::uint32_t>(dist_data.size()));
      dist_data.insert(dist_data.end(), c.guide().begin(), c.guide().end());
    };
    for (std::size_t d = 0; d < D; ++d) {
      const auto& m = built.dists[d];
      add_slot(m.learned());
      add_slot(m.fallback());
      const std::uint32_t rec[12] = {static_cast<std::uint32_t>(2 * d),
                                     static_cast<std::uint32_t>(m.learned().size()),
                                     static_cast<std::uint32_t>(m.learned().guide_size()),
                                     float_bits(m.learned().total()),
                                     static_cast<std::uint32_t>(2 * d + 1),
                                     static_cast<std::uint32_t>(m.fallback().size()),
                                     static_cast<std::uint32_t>(m.fallback().guide_size()),
                                     float_bits(m.fallback().total()),
                                     float_bits(m.effective_eps()),
                                     float_bits(m.fallback_scale()),
                                     float_bits(m.learned_scale()),
                                     0u};
      meta.insert(meta.end(), rec, rec + 12);
    }
    meta.insert(meta.end(), slots.begin(), slots.end());
    if (meta.empty()) meta.push_back(0u);
    if (dist_data.empty()) dist_data.push_back(0u);
  }
  const std::uint32_t slot_base = static_cast<std::uint32_t>(12 * built.dists.size());

  gl::buffer b_gbuf = gl::buffer::from_vector(gbuf);
  gl::buffer b_dprsm = gl::buffer::from_vector(dprsm);
  gl::buffer b_words = gl::buffer::from_vector(words);
  gl::buffer b_data = gl::buffer::from_vector(dist_data);
  gl::buffer b_meta = gl::buffer::from_vector(meta);
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
  set_i("u_n_samples", kind == k_local ? built.local_rounds : es.vpls);
  set_i("u_n_dists", static_cast<int>(built.dists.size()));
  set_i("u_mis_mode", es.meth == method::mis_as_published ? 1 : 0);
  glUniform1ui(prog.uniform_location("u_slot_base"), slot_base);
  gl::check_gl("estimate.comp uniforms");
  b_gbuf.bind(0);
  b_dprsm.bind(1);
  b_words.bind(2);
  b_data.bind(3);
  b_meta.bind(4);
  b_state.bind(5);
  b_out.bind(6);

  const int regions = std::max(1, static_cast<int>(built.dists.size()));
  const work_shape shape = shape_of(es, view.resolution, grid.resolution, regions, built.local_rounds);
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
                {"builders", "cpu (uploaded)"},
                {"cdf", "cpu (vplkit::make_vpl_distribution, uploaded)"},
                {"direct_light", "cpu (after read-back)"}};
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
    auto t = timer.scoped("read-back + direct (cpu)");
    for (int y = 0; y < H; ++y)
      for (int x = 0; x < W; ++x) {
        const int p = y * W + x;
        const vplkit::gather_point<float> gp = g.at(p);
        glm::vec3 c(0.0f);
        if (vplkit::gather_point_valid(gp)) {
          c = glm::vec3(out[static_cast<std::size_t>(p)]);
          if (es.direct) c += direct_light(gp, view);
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
