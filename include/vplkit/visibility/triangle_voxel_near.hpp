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
// Cost (it runs once per pixel): the box's rows along x are read from the occupancy words (one or
// two per row, so an empty row, the most common, costs a load or two), and per occupied voxel it
// asks one plane where the voxel's triangles all share one (the grid's planes,
// triangle_voxel_grid.hpp: the same plane's numbers, so the same answer as asking each of them),
// and every listed triangle's plane only where they do not (creases, corners, curved geometry) or
// where the view has no planes. triangle_voxel_surface_within_scan looks every voxel up on its own
// and asks every triangle: the same answers, bit for bit (tests/unit, tests/hardcases,
// tests/parity). Measured: bench_triangle_voxel_near (docs/results/clamp_compensation.md).
#include <vplkit/core/vector.hpp>
#include <vplkit/visibility/triangle_voxel_grid.hpp>
#include <vplkit/visibility/voxel_grid.hpp>
#include <vplkit/visibility/voxel_rank.hpp>

#include <glm/common.hpp>

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

// Bits lo .. hi of a word (0 <= lo <= hi <= 31).
inline std::uint32_t voxel_near_bit_range(int lo, int hi) {
  const std::uint32_t upto = hi == 31 ? ~std::uint32_t(0) : (std::uint32_t(1) << (hi + 1)) - 1u;
  return upto & ~((std::uint32_t(1) << lo) - 1u);
}

// Does occupied voxel r hold a surface other than x's planes within reach? One plane where its
// triangles share one (g.planes), else every listed triangle's.
template <class T>
inline bool voxel_near_voxel_within(const triangle_voxel_view<T>& g, std::uint32_t r, vec3<T> x, T reach,
                                    T plane_tolerance) {
  if (g.planes != nullptr && !voxel_plane_is_several(g.planes[r]))
    return voxel_near_plane_within(g.planes[r], x, reach, plane_tolerance);
  for (std::uint32_t e = g.offsets[r]; e < g.offsets[r + 1]; ++e)
    if (voxel_near_plane_within(g.triangles[g.entries[e]].plane, x, reach, plane_tolerance)) return true;
  return false;
}

// The occupied voxels among flat indices i0 .. i1 of word w (bits lo .. hi of it).
template <class T>
inline bool voxel_near_word_within(const triangle_voxel_view<T>& g, std::size_t w, int lo, int hi, vec3<T> x, T reach,
                                   T plane_tolerance) {
  const std::uint32_t word = g.grid.words[w];
  std::uint32_t bits = word & voxel_near_bit_range(lo, hi);
  while (bits != 0u) {
    const std::uint32_t lowest = bits & (0u - bits);
    const std::uint32_t r = g.rank[w] + std::uint32_t(voxel_bit_count(word & (lowest - 1u)));
    if (voxel_near_voxel_within(g, r, x, reach, plane_tolerance)) return true;
    bits &= bits - 1u;
  }
  return false;
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
  ivec3 a(voxel_floor_to_int(lo.x), voxel_floor_to_int(lo.y), voxel_floor_to_int(lo.z));
  ivec3 b(voxel_floor_to_int(hi.x), voxel_floor_to_int(hi.y), voxel_floor_to_int(hi.z));
  if (b.x - a.x >= voxel_near_max_side || b.y - a.y >= voxel_near_max_side || b.z - a.z >= voxel_near_max_side)
    return true;
  // Only the voxels inside the grid can be occupied. A row of the box (b.x - a.x < 8 voxels along
  // x) lies in one or two occupancy words: its occupied voxels are read from them at once, and the
  // empty rows (most of them: a surface crosses a few) cost two word loads.
  const ivec3 res = g.grid.resolution;
  a = glm::max(a, ivec3(0));
  b = glm::min(b, res - ivec3(1));
  if (a.x > b.x) return false;  // (a.y > b.y or a.z > b.z: the loops below do nothing)
  for (int z = a.z; z <= b.z; ++z)
    for (int y = a.y; y <= b.y; ++y) {
      const std::int64_t row = voxel_flat_index(res, ivec3(0, y, z));
      const std::int64_t i0 = row + a.x, i1 = row + b.x;
      for (std::int64_t w = i0 >> 5; w <= i1 >> 5; ++w)  // one word, or two
        if (detail::voxel_near_word_within(g, std::size_t(w), w == i0 >> 5 ? int(i0 & 31) : 0,
                                           w == i1 >> 5 ? int(i1 & 31) : 31, x, reach, plane_tolerance))
          return true;
    }
  return false;
}

// The same answers the simple way: every voxel of the box looked up on its own
// (voxel_occupied_index) and every triangle it lists asked (the grid's planes not used). What the
// test was before the rows and the planes; the reference the tests and bench_triangle_voxel_near
// hold it to.
template <class T>
inline bool triangle_voxel_surface_within_scan(const triangle_voxel_view<T>& g, vec3<T> x, T reach, T plane_tolerance) {
  if (!detail::voxel_vec3_finite(x) || !(reach >= T(0)) || !(reach <= std::numeric_limits<T>::max()) ||
      !(plane_tolerance >= T(0)))
    return true;
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
        for (std::uint32_t e = g.offsets[r]; e < g.offsets[r + 1]; ++e)
          if (detail::voxel_near_plane_within(g.triangles[g.entries[e]].plane, x, reach, plane_tolerance)) return true;
      }
  return false;
}

}  // namespace vplkit
