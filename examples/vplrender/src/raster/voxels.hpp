#pragma once
// The scene's voxel grid (docs/math.md section 7): bounds = the triangles' box padded by 1% of its
// largest extent and made cubic (vplkit::fit_voxel_bounds), `resolution` voxels per axis.
#include "scene/scene.hpp"

#include <vplkit/visibility/voxel_grid.hpp>

#include <cstdint>
#include <vector>

namespace vplrender {

// Flattened non-indexed positions and indices 0..3n-1 (what vplkit::voxelize and voxelize.comp take).
struct voxel_mesh {
  std::vector<vec3> positions;
  std::vector<std::uint32_t> indices;
};
voxel_mesh make_voxel_mesh(const scene& s);

// Conservative CPU voxelisation (vplkit::voxelize).
vplkit::voxel_grid<float> voxelize_cpu(const scene& s, int resolution);

}  // namespace vplrender
