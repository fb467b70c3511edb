// SPDX-License-Identifier: MIT
#pragma once
// Host side of the pack's GPU voxelisation (glsl/vplkit/visibility/voxelize.comp and
// prefix_sum.comp) on the current GL context: the binary occupancy grid, and the triangle voxel
// grid (occupancy, rank, per-voxel counts, offsets, lists) built entirely on the GPU, then read
// back into the C++ types. The triangle records (make_voxel_triangles) are computed on the host,
// so both sides query the same numbers. Used by the parity tests.
#include <vplkit/visibility/triangle_voxel_grid.hpp>
#include <vplkit/visibility/voxel_grid.hpp>

#include <glm/vec3.hpp>

#include <cstdint>
#include <vector>

namespace vplkit::gl {

struct gpu_voxelize_input {
  glm::vec3 bounds_min, bounds_max;
  ivec3 resolution;
  const std::vector<glm::vec3>* positions = nullptr;
  const std::vector<std::uint32_t>* indices = nullptr;  // 3 per triangle
  float margin_voxels = 1e-4f;                          // vplkit::voxelize_default_margin
};

// voxelize.comp, mode 0. `ms`: device time of the dispatches (timer_query).
voxel_grid<float> voxelize_on_gpu(const gpu_voxelize_input& in, double* ms = nullptr);

// voxelize.comp modes 0, 1, 2 with prefix_sum.comp between them (5 dispatch groups). `ms`: device
// time of all of them. The lists' order within a voxel is whatever the atomics gave.
triangle_voxel_grid<float> voxelize_triangles_on_gpu(const gpu_voxelize_input& in, double* ms = nullptr);

// prefix_sum.comp over the first `count` elements of `in`: out[i] = sum of f(in[j]), j < i, with
// f = bitCount (bit_count) or the value; with write_total one more element, the total. Throws
// when the total does not fit 32 bits.
std::vector<std::uint32_t> prefix_sum_on_gpu(const std::vector<std::uint32_t>& in, std::size_t count, bool bit_count,
                                             bool write_total);

}  // namespace vplkit::gl
