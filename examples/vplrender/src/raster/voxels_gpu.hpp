#pragma once
// The voxel grid on the GPU: the pack's kernel glsl/vplkit/visibility/voxelize.comp over the same
// bounds as voxelize_cpu (needs the current headless GL context).
#include "scene/scene.hpp"

#include <headless_gl/compute.hpp>

#include <vplkit/visibility/voxel_grid.hpp>

namespace vplrender {

struct gpu_voxelization {
  vplkit::voxel_grid<float> grid;  // read back (the CPU copy)
  vplkit::gl::buffer words;        // the same words, left on the GPU
  double ms = 0.0;                 // GPU time of the dispatch (timer query)
  double readback_ms = 0.0;        // the read-back of the words (wall clock)
};

// Same bounds, resolution and margin as voxelize_cpu.
gpu_voxelization voxelize_gpu(const scene& s, int resolution);

}  // namespace vplrender
