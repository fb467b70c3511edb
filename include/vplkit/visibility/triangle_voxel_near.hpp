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
//
// Per occupied voxel it asks one plane where the voxel's triangles all share one (the grid's
// planes, triangle_voxel_grid.hpp: the same plane's numbers, so the same answer as asking each of
// them), and every listed triangle's plane only where they do not (creases, corners, curved
// geometry), or where the view has no planes. triangle_voxel_surface_within_scan asks every
// triangle everywhere: the same answers, bit for bit (tests/unit, tests/parity); it is what the
// test was before the per-voxel planes, kept as the reference and for bench_triangle_voxel_near.
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

namespace detail {

// Is the plane p farther than plane_tolerance from x and not farther than reach? NaN (a bad
// triangle's plane): no.
template <class T>
inline bool voxel_near_plane_within(const voxel_plane<T>& p, vec3<T> x, T reach, T plane_tolerance) {
  const T s = std::abs(glm::dot(p.normal, x) - p.offset);
  return s > plane_tolerance && s <= reach;
}

}  // namespace detail

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
        if (g.planes != nullptr && !voxel_plane_is_several(g.planes[r])) {  // one plane for the voxel
          if (detail::voxel_near_plane_within(g.planes[r], x, reach, plane_tolerance)) return true;
          continue;
        }
        for (std::uint32_t e = g.offsets[r]; e < g.offsets[r + 1]; ++e)
          if (detail::voxel_near_plane_within(g.triangles[g.entries[e]].plane, x, reach, plane_tolerance)) return true;
      }
  return false;
}

// The same answers from every listed triangle's plane (the grid's planes not used).
template <class T>
inline bool triangle_voxel_surface_within_scan(triangle_voxel_view<T> g, vec3<T> x, T reach, T plane_tolerance) {
  g.planes = nullptr;
  return triangle_voxel_surface_within(g, x, reach, plane_tolerance);
}

}  // namespace vplkit
