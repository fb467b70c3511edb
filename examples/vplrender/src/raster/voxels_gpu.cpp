// SPDX-License-Identifier: MIT
#include "raster/voxels_gpu.hpp"

#include <headless_gl/voxelize_gpu.hpp>

#include <vplkit/visibility/voxelize.hpp>

namespace vplrender {

gpu_voxelization voxelize_gpu(const scene& s, int resolution) {
  const voxel_mesh m = make_voxel_mesh(s);
  const vplkit::voxel_bounds<float> b = scene_voxel_bounds(m);
  vplkit::gl::gpu_voxelize_input in;
  in.bounds_min = b.min;
  in.bounds_max = b.max;
  in.resolution = glm::ivec3(resolution);
  in.positions = &m.positions;
  in.indices = &m.indices;
  in.margin_voxels = static_cast<float>(vplkit::voxelize_default_margin);
  double ms = 0.0;
  scene_voxels grid = vplkit::gl::voxelize_triangles_on_gpu(in, &ms);
  return gpu_voxelization{std::move(grid), ms};
}

}  // namespace vplrender
