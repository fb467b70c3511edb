// SPDX-License-Identifier: MIT
#pragma once
// Is another surface near a point? The question the clamp compensation asks before it traces any
// ray (estimators/clamp_compensation.hpp): its directions add something only where a surface other
// than the gather point's own plane lies within dmin, and on most pixels none does. One look at
// the triangle voxel grid (triangle_voxel_grid.hpp) answers it for every direction at once.
//
// triangle_voxel_surface_within(g, x, reach, plane_tolerance) is conservative: it returns false
// only when every triangle listed by a voxel that meets the box of half-size reach (plus a small
// slack) around x either has its plane within plane_tolerance of x (a plane through x: x's own
// surface, a coplanar neighbour, a crease through x) or farther than reach from x (then none of its
// points is within reach). Every point of a triangle lies in a voxel that lists it, so false
// guarantees that every surface point within reach of x lies in a plane through x. True is
// returned as well when it cannot look (a box of more than voxel_near_max_side voxels per axis, a
// non-finite x or reach, a negative reach): the caller then traces.
#include <vplkit/core/vector.hpp>
#include <vplkit/visibility/triangle_voxel_grid.hpp>
#include <vplkit/visibility/voxel_grid.hpp>
#include <vplkit/visibility/voxel_rank.hpp>

#include <cmath>
#include <cstdint>
#include <limits>

namespace vplkit {

// The widest box looked at, in voxels per axis: beyond it the answer is "maybe" (true).
constexpr int voxel_near_max_side = 8;

template <class T>
inline bool triangle_voxel_surface_within(const triangle_voxel_view<T>& g, vec3<T> x, T reach, T plane_tolerance) {
  if (!detail::voxel_vec3_finite(x) || !(reach >= T(0)) || !(reach <= std::numeric_limits<T>::max()) ||
      !(plane_tolerance >= T(0)))
    return true;
  // Voxels meeting [x - reach, x + reach], widened by a thousandth of a voxel against the rounding
  // of the coordinates (a triangle on a voxel face is listed by the voxels on both sides).
  const T slack = T(1e-3);
  const vec3<T> lo = world_to_voxel_coord(g.grid, x) - reach / voxel_size(g.grid) - vec3<T>(slack);
  const vec3<T> hi = world_to_voxel_coord(g.grid, x) + reach / voxel_size(g.grid) + vec3<T>(slack);
  const ivec3 a(voxel_floor_to_int(lo.x), voxel_floor_to_int(lo.y), voxel_floor_to_int(lo.z));
  const ivec3 b(voxel_floor_to_int(hi.x), voxel_floor_to_int(hi.y), voxel_floor_to_int(hi.z));
  if (b.x - a.x >= voxel_near_max_side || b.y - a.y >= voxel_near_max_side || b.z - a.z >= voxel_near_max_side)
    return true;
  for (int z = a.z; z <= b.z; ++z)
    for (int y = a.y; y <= b.y; ++y)
      for (int xi = a.x; xi <= b.x; ++xi) {
        const std::int64_t r = voxel_occupied_index(g.grid, g.rank, ivec3(xi, y, z));
        if (r < 0) continue;
        for (std::uint32_t e = g.offsets[r]; e < g.offsets[r + 1]; ++e) {
          const voxel_plane<T>& p = g.triangles[g.entries[e]].plane;
          const T s = std::abs(glm::dot(p.normal, x) - p.offset);
          if (s > plane_tolerance && s <= reach) return true;  // NaN s (a bad triangle): not near
        }
      }
  return false;
}

}  // namespace vplkit
