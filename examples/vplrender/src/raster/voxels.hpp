// SPDX-License-Identifier: MIT
#pragma once
// The scene's voxel grid (docs/math.md section 7): bounds = the triangles' box padded by 1% of its
// largest extent and made cubic (vplkit::fit_voxel_bounds), `resolution` voxels per axis. It is a
// triangle voxel grid: the conservative occupancy (vplkit::voxelize's, what --visibility
// paper-voxels marches) plus, per occupied voxel, the triangles through it, so that --visibility
// voxels decides by the triangles (no self-occlusion at junctions, section 7.2).
#include "scene/scene.hpp"

#include <vplkit/visibility/triangle_corners.hpp>
#include <vplkit/visibility/triangle_voxel_grid.hpp>
#include <vplkit/visibility/voxelize.hpp>

#include <cstdint>
#include <vector>

namespace vplrender {

// Flattened non-indexed positions and indices 0..3n-1 (what vplkit::voxelize and voxelize.comp take).
struct voxel_mesh {
  std::vector<vec3> positions;
  std::vector<std::uint32_t> indices;
};
voxel_mesh make_voxel_mesh(const scene& s);

using scene_voxels = vplkit::triangle_voxel_grid<float>;
using scene_voxels_view = vplkit::triangle_voxel_view<float>;

// The bounds both voxelisers use.
vplkit::voxel_bounds<float> scene_voxel_bounds(const voxel_mesh& m);

// CPU voxelisation (vplkit::voxelize_triangles; its occupancy is vplkit::voxelize's).
scene_voxels voxelize_cpu(const scene& s, int resolution);

// The scene's corners in the grid's triangle order (make_voxel_mesh's, the scene's): what the CPU
// voxel tracer shades its hits with under --voxel-contract exact (vplkit::triangle_corner_view).
struct voxel_corners {
  std::vector<vec3> positions, normals;
  vplkit::triangle_corner_view<float> view() const {
    return vplkit::triangle_corner_view<float>{positions.data(), normals.data(), positions.size() / 3};
  }
};
voxel_corners make_voxel_corners(const scene& s);

}  // namespace vplrender
