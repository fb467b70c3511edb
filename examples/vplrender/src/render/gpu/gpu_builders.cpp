#include "render/gpu/gpu_builders.hpp"

#include "render/gpu/gpu_backend.hpp"

#include <vplkit/builders/gather_subset.hpp>
#include <vplkit/builders/gather_subset_params.h>
#include <vplkit/builders/global_weights_params.h>
#include <vplkit/builders/local_weights.hpp>
#include <vplkit/core/error.hpp>

#include <glm/vec4.hpp>

#include <algorithm>
#include <map>
#include <string>

namespace vplrender {

namespace {

namespace gl = vplkit::gl;

const gl::program& pack_program(const std::string& rel) {
  static std::map<std::string, gl::program> cache;  // compiled once per process
  auto it = cache.find(rel);
  if (it != cache.end()) return it->second;
  gl::program prog = gl::program::compute_with_includes("#version 430\n#include \"" + rel + "\"\n", rel);
  return cache.emplace(rel, std::move(prog)).first->second;
}

gl::buffer surfels(const std::vector<vec3>& p, const std::vector<vec3>& nrm, const std::vector<vec3>& a) {
  std::vector<glm::vec4> s(3 * std::max<std::size_t>(p.size(), 1), glm::vec4(0.0f));
  for (std::size_t i = 0; i < p.size(); ++i) {
    s[3 * i] = glm::vec4(p[i], 0.0f);
    s[3 * i + 1] = glm::vec4(nrm[i], 0.0f);
    s[3 * i + 2] = glm::vec4(a[i], 0.0f);
  }
  return gl::buffer::from_vector(s);
}

}  // namespace

gl::buffer dprsm_surfel_buffer(const dprsm_data& d) { return surfels(d.position, d.normal, d.albedo); }

gpu_weights build_brsm_weights_gpu(const gbuffer_data& gb, const dprsm_data& dd, const estimator_settings& es,
                                   bool local, stage_timer& timer) {
  const vplkit::gbuffer_view<float> g = gb.view();
  const vplkit::dprsm_view<float> view = dd.view();
  g.validate();
  view.validate();
  const int count = local ? es.local_subset : es.global_subset;
  if (count < 0) throw vplkit::invalid_input("build_brsm_weights_gpu: negative subset size");
  // The same rectangles, seeds and streams as build_distributions_cpu (stratified_gather_subset
  // over the image; local_gather_subsets over the regions).
  std::vector<vplkit::pixel_rect> rects;
  if (local) {
    const vplkit::image_regions regions(g.width, g.height, es.regions_x, es.regions_y);
    for (int i = 0; i < regions.count(); ++i) rects.push_back(regions.region_rect(i));
  } else {
    rects.push_back(vplkit::full_image_rect(g));
  }
  const int N = static_cast<int>(rects.size());
  const std::uint32_t seed = builder_seed(es.seed, local ? 1u : 0u);
  const std::size_t n = static_cast<std::size_t>(view.texel_count());

  gpu_weights out;
  out.regions = N;
  gl::timer_query tq;
  tq.begin();
  gl::buffer b_gbuf = surfels(gb.position, gb.normal, gb.albedo);
  gl::buffer b_dprsm = dprsm_surfel_buffer(dd);
  // Region i's strata at [i count, i count + shape.count); the rest stays -1 (skipped).
  const std::size_t cap = static_cast<std::size_t>(N) * static_cast<std::size_t>(count);
  gl::buffer b_subset = gl::buffer::filled(std::max<std::size_t>(cap, 1) * 4, 0xFF);
  std::vector<std::uint32_t> offsets;
  for (int i = 0; i <= N; ++i) offsets.push_back(static_cast<std::uint32_t>(i) * static_cast<std::uint32_t>(count));
  gl::buffer b_offsets = gl::buffer::from_vector(offsets);
  std::vector<gl::buffer> blocks;
  const gl::program& sp = pack_program("vplkit/builders/gather_subset.comp");
  for (int i = 0; i < N; ++i) {
    const vplkit::pixel_rect& r = rects[static_cast<std::size_t>(i)];
    const vplkit::gather_subset_grid_shape shape = vplkit::gather_subset_grid(r, count);
    if (shape.count <= 0) continue;
    const std::uint32_t first = static_cast<std::uint32_t>(i) * static_cast<std::uint32_t>(count);
    const vplkit::gpu::gather_subset_params p =
        vplkit::gpu::make_gather_subset_params(g, r, count, seed, first, vplkit::gather_subset_default_attempts, first);
    blocks.push_back(gl::buffer::from_bytes(&p, sizeof p));
    b_gbuf.bind(VPLKIT_GATHER_SUBSET_BINDING_GBUFFER);
    b_subset.bind(VPLKIT_GATHER_SUBSET_BINDING_PIXELS);
    glBindBufferBase(GL_UNIFORM_BUFFER, VPLKIT_GATHER_SUBSET_BINDING_PARAMS, blocks.back().id());
    gl::dispatch(sp, gl::groups_for(static_cast<std::size_t>(shape.count), VPLKIT_GATHER_SUBSET_LOCAL_SIZE));
  }
  out.weights = gl::buffer::filled((static_cast<std::size_t>(N) + 1) * n * 4, 0);
  vplkit::gpu::global_weights_params wp{};
  wp.light = vplkit::gpu::make_light_params(view.light);
  wp.resolution = view.resolution;
  wp.regions = N;
  wp.pixel_count = g.width * g.height;
  wp.dmin = es.dmin;
  blocks.push_back(gl::buffer::from_bytes(&wp, sizeof wp));
  b_gbuf.bind(VPLKIT_GLOBAL_WEIGHTS_BINDING_GBUFFER);
  b_dprsm.bind(VPLKIT_GLOBAL_WEIGHTS_BINDING_DPRSM);
  b_subset.bind(VPLKIT_GLOBAL_WEIGHTS_BINDING_SUBSET);
  b_offsets.bind(VPLKIT_GLOBAL_WEIGHTS_BINDING_OFFSETS);
  out.weights.bind(VPLKIT_GLOBAL_WEIGHTS_BINDING_WEIGHTS);
  glBindBufferBase(GL_UNIFORM_BUFFER, VPLKIT_GLOBAL_WEIGHTS_BINDING_PARAMS, blocks.back().id());
  gl::dispatch(pack_program("vplkit/builders/global_weights.comp"), gl::groups_for(n, VPLKIT_GLOBAL_WEIGHTS_LOCAL_SIZE),
               static_cast<GLuint>(N));
  // |S_i| for the report: the subsets are a few hundred ints.
  const std::vector<std::int32_t> picks = b_subset.read<std::int32_t>(cap);
  out.used.assign(static_cast<std::size_t>(N), 0);
  for (std::size_t k = 0; k < cap; ++k)
    if (picks[k] >= 0) ++out.used[k / static_cast<std::size_t>(count)];
  tq.end();
  timer.add(local ? "local weights (gpu)" : "global weights (gpu)", tq.milliseconds(), "gpu");
  return out;
}

gpu_mixtures build_distributions_gpu(const gbuffer_data& gb, const dprsm_data& dd,
                                     const vplkit::voxel_grid_view<float>& grid, const estimator_settings& es,
                                     stage_timer& timer, nlohmann::json& det) {
  const vplkit::dprsm_view<float> view = dd.view();
  const std::size_t n = static_cast<std::size_t>(view.texel_count());
  gl::buffer weights;
  int D = 1;
  switch (es.meth) {
    case method::global: {
      gpu_weights w = build_brsm_weights_gpu(gb, dd, es, false, timer);
      det["global_subset"] = w.used.front();
      weights = std::move(w.weights);
      break;
    }
    case method::local: {
      gpu_weights w = build_brsm_weights_gpu(gb, dd, es, true, timer);
      det["local_subsets"] = w.used;
      D = w.regions;
      weights = std::move(w.weights);
      break;
    }
    case method::gbg:
    case method::mis:
    case method::mis_as_published: {
      gbg_gpu_weights w = build_gbg_weights_gpu(gb, dd, grid, es, timer, det, false);
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
    case method::reference:
    case method::gather:
      throw vplkit::invalid_input("build_distributions_gpu: the method has no builder");
  }
  const gl::buffer b_dprsm = dprsm_surfel_buffer(dd);
  gpu_mixtures mix = build_mixtures_gpu(weights, D, b_dprsm, view, es.eps, timer, det);
  if (es.meth == method::local) {
    // N_NG rounds of one VPL per region's CDF, as build_distributions_cpu.
    mix.local_rounds = std::max(1, es.vpls / D);
    det["local_rounds"] = mix.local_rounds;
    det["local_combination"] = to_string(es.local_combination);
  }
  det["builders"] = "gpu";
  return mix;
}

}  // namespace vplrender
