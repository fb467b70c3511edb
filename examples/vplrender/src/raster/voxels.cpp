// SPDX-License-Identifier: MIT
#include "raster/voxels.hpp"

#include <vplkit/visibility/voxelize.hpp>
#include <vplkit/visibility/voxelize_triangles.hpp>

namespace vplrender {

voxel_mesh make_voxel_mesh(const scene& s) {
  voxel_mesh m;
  m.positions.reserve(s.triangles.size() * 3);
  for (const triangle& t : s.triangles)
    for (const vec3& p : t.p) {
      m.indices.push_back(static_cast<std::uint32_t>(m.positions.size()));
      m.positions.push_back(p);
    }
  return m;
}

voxel_corners make_voxel_corners(const scene& s) {
  voxel_corners c;
  c.positions.reserve(s.triangles.size() * 3);
  c.normals.reserve(s.triangles.size() * 3);
  for (const triangle& t : s.triangles)
    for (int k = 0; k < 3; ++k) {
      c.positions.push_back(t.p[static_cast<std::size_t>(k)]);
      c.normals.push_back(t.n[static_cast<std::size_t>(k)]);
    }
  return c;
}

vplkit::voxel_bounds<float> scene_voxel_bounds(const voxel_mesh& m) {
  return vplkit::fit_voxel_bounds(m.positions.data(), m.positions.size());
}

scene_voxels voxelize_cpu(const scene& s, int resolution) {
  const voxel_mesh m = make_voxel_mesh(s);
  const vplkit::voxel_bounds<float> b = scene_voxel_bounds(m);
  return vplkit::voxelize_triangles(b.min, b.max, glm::ivec3(resolution), m.positions.data(), m.positions.size(),
                                    m.indices.data(), m.indices.size());
}

}  // namespace vplrender
