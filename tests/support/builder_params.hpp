// SPDX-License-Identifier: MIT
#pragma once
// The parameter blocks of the builder kernels glsl/vplkit/builders/*.comp as the GPU tests fill
// them, GL- and Vulkan-free so that the GL parity test (support/gbg_kernels.hpp), the Vulkan test
// (tests/vulkan/vulkan_builders_test.cpp) and the GPU benchmark dispatch the same blocks: the
// GBG setup and its fixed point, the accumulate / finish blocks, global_weights.comp's block and
// its flattened subsets. Not part of the library.
#include <synthetic_scene.hpp>

#include <vplkit/builders/gbg_accumulate_params.h>
#include <vplkit/builders/gbg_finish_params.h>
#include <vplkit/builders/gbg_weights.hpp>
#include <vplkit/builders/global_weights_params.h>
#include <vplkit/visibility/visibility_callables.hpp>
#include <vplkit/visibility/voxel_grid.hpp>
#include <vplkit/vpl/luminance.hpp>

#include <glm/vec4.hpp>

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

// The C++ builder's parameters for the same build (T = float).
inline vplkit::gbg_params<float> gbg_cpu_params(const gbg_setup& st, bool fill) {
  vplkit::gbg_params<float> p;
  p.n_dirs = st.n_dirs;
  p.dmin = st.dmin;
  p.depth_tolerance = st.tol;
  p.seed = st.seed;
  p.accumulator = st.accumulator == 0 ? vplkit::gbg_accumulator::paper : vplkit::gbg_accumulator::gathering;
  p.fill_holes = fill;
  return p;
}

// global_weights.comp's inputs for N subsets (one per region): the subsets end to end, each
// region's range [offsets[r], offsets[r + 1]) of them, and the block. An empty input still gets
// one entry (-1, skipped), as a buffer may not be empty.
struct global_weights_inputs {
  std::vector<std::int32_t> flat;
  std::vector<std::uint32_t> offsets = {0u};
  vplkit::gpu::global_weights_params params{};
};

inline global_weights_inputs make_global_weights_inputs(const std::vector<std::vector<int>>& subsets,
                                                        const dprsm_data<float>& dp, int pixel_count, float dmin) {
  global_weights_inputs in;
  for (const auto& sub : subsets) {
    in.flat.insert(in.flat.end(), sub.begin(), sub.end());
    in.offsets.push_back(std::uint32_t(in.flat.size()));
  }
  if (in.flat.empty()) in.flat.push_back(-1);
  in.params.light = vplkit::gpu::make_light_params(dp.light);
  in.params.resolution = dp.resolution;
  in.params.regions = int(subsets.size());
  in.params.pixel_count = pixel_count;
  in.params.dmin = dmin;
  return in;
}

// A GBG build over an all-background copy of a G-buffer: nothing accumulates, so any fixed point
// will do; every stat in zero_stats must come back 0, and the holes must be the C++ build's (every
// texel that carries a VPL).
struct all_background_gbg {
  static constexpr int zero_stats[] = {VPLKIT_GBG_STAT_GATHER_POINTS,  VPLKIT_GBG_STAT_HITS,
                                       VPLKIT_GBG_STAT_LIT_HITS,       VPLKIT_GBG_STAT_SATURATED_HITS,
                                       VPLKIT_GBG_STAT_REACHED_TEXELS, VPLKIT_GBG_STAT_FILLED};
  gbuffer_data<float> gbuffer;
  gbg_setup setup;
  std::uint32_t cpu_holes = 0;

  all_background_gbg(const gbuffer_data<float>& like, const vplkit::dprsm_view<float>& view,
                     const vplkit::voxel_grid<float>& grid)
      : gbuffer(like) {
    std::fill(gbuffer.normal.begin(), gbuffer.normal.end(), vplkit::vec3<float>(0));
    setup.tol = 0.3f;
    setup.scale = 1024.0f;
    setup.max_units = std::ldexp(1.0f, 40);
    vplkit::gbg_params<float> params;
    params.depth_tolerance = setup.tol;
    vplkit::gbg_stats cs;
    vplkit::build_gbg_weights(gbuffer.view(), view, vplkit::voxel_tracer<float>{grid.view()}, params, &cs);
    cpu_holes = std::uint32_t(cs.holes);
  }
};

}  // namespace vplkit_test
