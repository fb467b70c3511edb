#pragma once
// The voxel grid on the GPU: the pack's kernel glsl/vplkit/visibility/voxelize.comp over the same
// bounds as voxelize_cpu (needs the current headless GL context).
#include "scene/scene.hpp"

#include <vplkit/visibility/voxel_grid.hpp>

namespace vplrender {

// ms: GPU time of the dispatch (timer query). Same bounds, resolution and margin as voxelize_cpu.
vplkit::voxel_grid<float> voxelize_gpu(const scene& s, int resolution, double* ms = nullptr);

}  // namespace vplrender
