// SPDX-License-Identifier: MIT
#pragma once
// The voxel grid on the GPU: the pack's kernels glsl/vplkit/visibility/voxelize.comp (occupancy,
// count and fill modes) and prefix_sum.comp over the same bounds as voxelize_cpu, through
// support/headless_gl/voxelize_gpu (needs the current headless GL context). The grid is read back
// (the CPU copy every stage reads); raster/gpu_scene_buffers.hpp uploads it in the kernels' layout.
#include "raster/voxels.hpp"
#include "scene/scene.hpp"

namespace vplrender {

struct gpu_voxelization {
  scene_voxels grid;  // read back
  double ms = 0.0;    // GPU time of the dispatches (timer query)
};

// Same bounds, resolution and margin as voxelize_cpu; the same occupancy, rank and offsets, and
// the same lists as sets (renderer_gl_pipeline_test).
gpu_voxelization voxelize_gpu(const scene& s, int resolution);

}  // namespace vplrender
