#pragma once
// gbg_accumulate.comp + gbg_finish.comp driven on a synthetic scene (synthetic_scene.hpp), for the
// GBG parity test (tests/parity/parity_builders_test.cpp) and the GPU benchmark
// (tests/bench/bench_gpu_kernels.cpp), which must run the same dispatches: the parameter blocks
// from the kernels' own headers, the fixed point gbg_weights.glsl recommends, the buffers and the
// two dispatches. Not part of the library; needs a current GL context (gl_kernels.hpp).
#include <gl_kernels.hpp>
#include <std430_types.hpp>
#include <synthetic_scene.hpp>

#include <vplkit/builders/gbg_accumulate_params.h>
#include <vplkit/builders/gbg_finish_params.h>
#include <vplkit/paraboloid/texel_grid.hpp>
#include <vplkit/visibility/voxel_grid.hpp>
#include <vplkit/vpl/luminance.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace vplkit_test {

// What a GBG build is given besides the scene.
struct gbg_setup {
  int n_dirs = 16;
  float dmin = 0.05f;
  float tol = 0.0f;  // depth tolerance of the DPRSM lookup
  std::uint32_t seed = 21u;
  int accumulator = 1;  // 0 paper, 1 gathering
  float scale = 0.0f;   // fixed point (choose_gbg_fixed_point)
  float max_units = 0.0f;
};

// Fixed-point parameters as gbg_weights.glsl recommends: max_units = 2^(63 - ceil(log2 H)),
// H = |G| n_dirs, scale = 2^floor(log2(max_units / v_bound)) with v_bound the largest value one
// hit can add (the accumulator's bound over the DPRSM's texels).
inline void choose_gbg_fixed_point(gbg_setup& st, int gather_points, const dprsm_data<float>& dp) {
  const double H = double(gather_points) * st.n_dirs;
  st.max_units = float(std::ldexp(1.0, 63 - int(std::ceil(std::log2(H)))));
  const double lum_i = double(vplkit::luminance(dp.light.intensity));
  double v_bound;
  if (st.accumulator == 1) {
    double d1min = 1e30;
    for (std::size_t t = 0; t < dp.position.size(); ++t)
      if (dp.albedo[t] != vplkit::vec3<float>(0))
        d1min = std::min(d1min, double(glm::length(dp.position[t] - dp.light.position)));
    d1min = std::max(d1min - double(st.tol), 1e-3);
    v_bound = lum_i / (3.141592653589793 * d1min * d1min);
  } else {
    const double omega_max = 4.0 * (2.0 / dp.resolution) * (2.0 / dp.resolution);
    const double dm = std::max(double(st.dmin), 1e-3);
    v_bound = lum_i * omega_max / (3.141592653589793 * 3.141592653589793 * dm * dm);
  }
  st.scale = float(std::ldexp(1.0, int(std::floor(std::log2(double(st.max_units) / v_bound)))));
}

// gbg_accumulate.comp's block for the directions [dir_begin, dir_end) of a W x H G-buffer.
inline vplkit::gpu::gbg_accumulate_params gbg_accumulate_block(const dprsm_data<float>& dp,
                                                               const vplkit::voxel_grid<float>& grid, int width,
                                                               int height, const gbg_setup& st, int dir_begin,
                                                               int dir_end, bool count_gather_points) {
  vplkit::gpu::gbg_accumulate_params p{};
  p.light = vplkit::gpu::make_light_params(dp.light);
  p.grid_min = glm::vec4(grid.bounds_min(), 0.0f);
  p.grid_max = glm::vec4(grid.bounds_max(), 0.0f);
  p.grid_resolution = glm::ivec4(grid.resolution(), 0);
  p.width = width;
  p.height = height;
  p.resolution = dp.resolution;
  p.n_dirs = st.n_dirs;
  p.accumulator = st.accumulator;
  p.dir_begin = dir_begin;
  p.dir_end = dir_end;
  p.count_gather_points = count_gather_points ? 1 : 0;
  p.seed = st.seed;
  p.dmin = st.dmin;
  p.depth_tolerance = st.tol;
  p.offset_voxels = 1.75f;
  p.scale = st.scale;
  p.max_units = st.max_units;
  return p;
}

inline vplkit::gpu::gbg_finish_params gbg_finish_block(const dprsm_data<float>& dp, const gbg_setup& st, bool fill) {
  vplkit::gpu::gbg_finish_params fp{};
  fp.light = vplkit::gpu::make_light_params(dp.light);
  fp.resolution = dp.resolution;
  fp.n_dirs = st.n_dirs;
  fp.fill_holes = fill ? 1 : 0;
  fp.inv_scale = 1.0f / st.scale;
  return fp;
}

// The buffers of one build: inputs uploaded once; the sums and stats zeroed, the weights filled
// with `weights_fill` bytes (0xFF: a texel the finish skips is NaN).
struct gbg_buffers {
  vplkit::gl::buffer gbuffer, dprsm, voxels, acc, stats, weights;
  int pixels = 0, resolution = 0;
  // Looked up once: the benchmark times accumulate() and finish().
  const vplkit::gl::program& accumulate_kernel = pack_kernel("vplkit/builders/gbg_accumulate.comp");
  const vplkit::gl::program& finish_kernel = pack_kernel("vplkit/builders/gbg_finish.comp");
  gbg_buffers(const gbuffer_data<float>& gb, const dprsm_data<float>& dp, const vplkit::voxel_grid<float>& grid,
              unsigned char weights_fill)
      : gbuffer(vplkit::gl::buffer::from_vector(
            surfels(gb.position, gb.normal, gb.albedo, gb.shading_normal.empty() ? nullptr : &gb.shading_normal))),
        dprsm(vplkit::gl::buffer::from_vector(surfels(dp.position, dp.normal, dp.albedo))),
        voxels(vplkit::gl::buffer::from_vector(grid.words())),
        acc(vplkit::gl::buffer::filled(std::size_t(2 * vplkit::texel_count(dp.resolution)) * 4, 0)),
        stats(vplkit::gl::buffer::filled(VPLKIT_GBG_STATS_SIZE * 4, 0)),
        weights(vplkit::gl::buffer::filled(std::size_t(vplkit::texel_count(dp.resolution)) * 4, weights_fill)),
        pixels(gb.width * gb.height),
        resolution(dp.resolution) {}

  // One gbg_accumulate.comp dispatch over every pixel with the block in `params`.
  void accumulate(const vplkit::gl::buffer& params) const {
    dispatch(accumulate_kernel,
             {vplkit::gl::groups_for(std::size_t(pixels), VPLKIT_GBG_LOCAL_SIZE), 1, 1},
             {storage_at(VPLKIT_GBG_BINDING_GBUFFER, gbuffer), storage_at(VPLKIT_GBG_BINDING_DPRSM, dprsm),
              storage_at(VPLKIT_GBG_BINDING_VOXELS, voxels), storage_at(VPLKIT_GBG_BINDING_ACC, acc),
              storage_at(VPLKIT_GBG_BINDING_STATS, stats), uniform_at(VPLKIT_GBG_BINDING_PARAMS, params)});
  }
  // gbg_finish.comp over both faces.
  void finish(const vplkit::gl::buffer& params) const {
    const GLuint g = vplkit::gl::groups_for(std::size_t(resolution), VPLKIT_GBG_FINISH_LOCAL_SIZE);
    dispatch(finish_kernel, {g, g, 2},
             {storage_at(VPLKIT_GBG_FINISH_BINDING_ACC, acc), storage_at(VPLKIT_GBG_FINISH_BINDING_STATS, stats),
              storage_at(VPLKIT_GBG_FINISH_BINDING_DPRSM, dprsm),
              storage_at(VPLKIT_GBG_FINISH_BINDING_WEIGHTS, weights),
              uniform_at(VPLKIT_GBG_FINISH_BINDING_PARAMS, params)});
  }
};

}  // namespace vplkit_test
