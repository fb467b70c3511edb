// SPDX-License-Identifier: MIT
#pragma once
// gbg_accumulate.comp + gbg_finish.comp driven on a synthetic scene (synthetic_scene.hpp), for the
// GBG parity test (tests/parity/parity_builders_test.cpp) and the GPU benchmark
// (tests/bench/bench_gpu_kernels.cpp), which must run the same dispatches: the buffers and the
// two dispatches, with the parameter blocks of builder_params.hpp (shared with the Vulkan test).
// Not part of the library; needs a current GL context (gl_kernels.hpp).
#include <builder_params.hpp>
#include <gl_kernels.hpp>
#include <std430_types.hpp>
#include <synthetic_scene.hpp>

#include <vplkit/paraboloid/texel_grid.hpp>
#include <vplkit/visibility/voxel_grid.hpp>

#include <cstddef>
#include <vector>

namespace vplkit_test {

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
