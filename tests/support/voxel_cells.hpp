// SPDX-License-Identifier: MIT
#pragma once
// Voxel grids cell by cell, for the voxelisation tests on the CPU, GL and Vulkan (not part of the
// library, nor of Catch): the occupied cells, the margin at which the C++ double SAT starts to
// mark a cell (what tells a GPU rounding difference at the margin shell from a wrong voxel), and
// voxelize.comp's parameter block.
#include <vplkit/visibility/triangle_box_overlap.hpp>
#include <vplkit/visibility/voxel_grid.hpp>
#include <vplkit/visibility/voxelize_params.h>

#include <glm/vec4.hpp>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace vplkit_test {

// The occupied cells in z, y, x order.
template <class T>
std::vector<vplkit::ivec3> occupied_voxels(const vplkit::voxel_grid<T>& g) {
  std::vector<vplkit::ivec3> out;
  const vplkit::ivec3 r = g.resolution();
  for (int z = 0; z < r.z; ++z)
    for (int y = 0; y < r.y; ++y)
      for (int x = 0; x < r.x; ++x)
        if (g.test(vplkit::ivec3(x, y, z))) out.push_back(vplkit::ivec3(x, y, z));
  return out;
}

// The smallest margin (in voxels, up to `cap`) at which the C++ double SAT marks cell c for some
// triangle of the mesh (positions, indices); cap + 1 if none. Bisection to 1e-9 voxel.
template <class Mesh>
double voxel_flip_margin(const vplkit::voxel_grid<float>& g, const Mesh& m, vplkit::ivec3 c, double cap) {
  using v3d = vplkit::vec3<double>;
  const v3d bmin(g.bounds_min());
  const v3d size = (v3d(g.bounds_max()) - bmin) / v3d(g.resolution());
  const v3d centre = v3d(c) + v3d(0.5);
  double best = cap + 1.0;
  for (std::size_t t = 0; t < m.indices.size() / 3; ++t) {
    v3d v[3];
    for (int k = 0; k < 3; ++k) v[k] = (v3d(m.positions[m.indices[3 * t + std::size_t(k)]]) - bmin) / size;
    if (!vplkit::triangle_box_overlap(centre, v3d(0.5 + cap), v[0], v[1], v[2])) continue;
    double lo = 0.0, hi = cap;
    if (vplkit::triangle_box_overlap(centre, v3d(0.5), v[0], v[1], v[2])) hi = 0.0;
    while (hi - lo > 1e-9) {
      const double mid = 0.5 * (lo + hi);
      (vplkit::triangle_box_overlap(centre, v3d(0.5 + mid), v[0], v[1], v[2]) ? hi : lo) = mid;
    }
    best = std::min(best, hi);
  }
  return best;
}

// voxelize.comp's block: voxelise `triangles` triangles into a grid shaped like `like`.
inline vplkit::gpu::voxelize_params voxelize_block(const vplkit::voxel_grid<float>& like, std::size_t triangles,
                                                   float margin_voxels) {
  vplkit::gpu::voxelize_params p{};
  p.bounds_min = glm::vec4(like.bounds_min(), 0.0f);
  p.bounds_max = glm::vec4(like.bounds_max(), 0.0f);
  p.resolution = glm::ivec4(like.resolution(), 0);
  p.triangle_count = std::uint32_t(triangles);
  p.margin_voxels = margin_voxels;
  return p;
}

}  // namespace vplkit_test
