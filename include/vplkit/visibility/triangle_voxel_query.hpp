// SPDX-License-Identifier: MIT
#pragma once
// Visibility and first hits decided by the triangles a triangle_voxel_grid lists (docs/math.md
// section 7.2; docs/api/visibility.md, "Triangle voxels"). L = voxel_length.
//
// The segment x -> y is marched with the DDA (dda_walk) and blocked by a listed triangle it crosses
// strictly inside (grown by 1e-3 L within its plane, so that no segment leaks between the triangles
// of a mesh). The END RULE ignores a triangle whose plane passes within end_tolerance (default
// 0.01 L) of x or of y: that removes self-occlusion at the ends and at concave junctions and loses
// no occluder but those in a 0.01-voxel band. Why, and why 0.01: docs/math.md section 7.2 and
// docs/api/visibility.md. A wall of any thickness blocks: every point of a triangle lies in a
// voxel that lists it, and the march visits a voxel containing every point of the segment.
//
// The OFFSET CONTRACT (triangle_voxel_visible_offset, triangle_voxel_first_hit_offset) is exact
// visibility's instead (bvh_visibility.hpp, docs/math.md section 7.3): both ends moved off their
// surfaces along their normals by an offset, the segment between the moved ends tested whole
// (crossings at s in (0, 1]), no end rule, triangles grown by triangle_voxel_offset_slack (32 float
// ulps of the grid's largest coordinate, not 1e-3 voxel). With the same offset it answers what a
// ray tracer over the same triangles answers, up to that slack: on Sponza at 64x64, 0.013 % of 151
// million gather-point/VPL pairs differ from Embree's answer, against 1.13 % under the end rule,
// whose misses sit where a segment grazes a surface an end lies on (docs/math.md 7.2, "Where the
// end rule and the offset differ"; vplrender's tools/voxel_contract_pairs.cpp measures it).
#include <vplkit/core/vector.hpp>
#include <vplkit/visibility/bvh_visibility.hpp>
#include <vplkit/visibility/dda.hpp>
#include <vplkit/visibility/triangle_voxel_grid.hpp>
#include <vplkit/visibility/voxel_grid.hpp>

#include <cmath>
#include <cstdint>
#include <limits>

namespace vplkit {

constexpr double triangle_voxel_default_end_tolerance = 0.01;  // voxels
constexpr double triangle_voxel_edge_slack = 1e-3;              // voxels

// Is p (on the triangle's plane) inside the triangle grown by `slack` (world units)?
template <class T>
inline bool voxel_triangle_contains(const voxel_triangle<T>& tri, vec3<T> p, T slack) {
  const T s0 = glm::dot(tri.edge[0].normal, p) - tri.edge[0].offset;
  const T s1 = glm::dot(tri.edge[1].normal, p) - tri.edge[1].offset;
  const T s2 = glm::dot(tri.edge[2].normal, p) - tri.edge[2].offset;
  return s0 >= -slack && s1 >= -slack && s2 >= -slack;
}

// Is the segment x -> y free of the grid's triangles (the rules of the header)? x == y is
// visible; a non-finite x or y is not.
template <class T>
inline bool triangle_voxel_visible(const triangle_voxel_view<T>& g, vec3<T> x, vec3<T> y,
                                   T end_tolerance_voxels = T(triangle_voxel_default_end_tolerance)) {
  if (!detail::voxel_vec3_finite(x) || !detail::voxel_vec3_finite(y)) return false;
  const vec3<T> dir = y - x;
  const T len = std::sqrt(glm::dot(dir, dir));
  if (!(len > T(0))) return true;
  const T L = voxel_length(g.grid);
  const T eps = end_tolerance_voxels * L, slack = T(triangle_voxel_edge_slack) * L;
  dda_walk<T> w = dda_walk_begin(g.grid, x, dir, len);
  const int max_iterations = dda_max_iterations(g.grid.resolution);
  for (int it = 0; w.running && it < max_iterations; ++it) {
    if (g.bricks != nullptr && !voxel_brick_occupied(g.grid.resolution, g.bricks, w.voxel)) {
      dda_walk_leave_brick(g.grid, w);
      continue;
    }
    const std::int64_t r = voxel_occupied_index(g.grid, g.rank, w.voxel);
    if (r >= 0) {
      // The voxel's stretch of the segment, in the fraction s of x -> y (the local crossing rule).
      const T s_in = (w.t - slack) / len, s_out = (dda_walk_exit(w) + slack) / len;
      for (std::uint32_t e = g.offsets[r], end = g.offsets[r + 1]; e < end; ++e) {
        const voxel_triangle<T>& tri = g.triangles[g.entries[e]];
        const T d0 = glm::dot(tri.plane.normal, x) - tri.plane.offset;
        const T d1 = glm::dot(tri.plane.normal, y) - tri.plane.offset;
        if (!(std::abs(d0) > eps) || !(std::abs(d1) > eps) || (d0 > T(0)) == (d1 > T(0))) continue;
        const T s = d0 / (d0 - d1);
        if (s < s_in || s > s_out) continue;
        if (voxel_triangle_contains(tri, x + s * dir, slack)) return false;
      }
    }
    dda_walk_next(g.grid, w);
  }
  return true;
}

template <class T>
struct triangle_voxel_hit {
  bool hit;
  T t;                    // distance along the unit direction (0 on a miss)
  vec3<T> point;          // origin + t * unit direction, on the triangle (origin on a miss)
  std::uint32_t triangle; // its index (0xFFFFFFFF on a miss)
};

// The first triangle met by origin + t * normalize(dir), 0 < t <= t_max (triangles whose plane
// passes within end_tolerance of the origin ignored: the origin's own surface). In each occupied
// voxel the nearest crossing no farther than the voxel's exit (+ the slack) wins; a crossing
// beyond it lies in a later voxel, which lists the same triangle.
template <class T>
inline triangle_voxel_hit<T> triangle_voxel_first_hit(const triangle_voxel_view<T>& g, vec3<T> origin, vec3<T> dir,
                                                      T t_max = std::numeric_limits<T>::infinity(),
                                                      T end_tolerance_voxels = T(triangle_voxel_default_end_tolerance)) {
  const triangle_voxel_hit<T> miss{false, T(0), origin, 0xFFFFFFFFu};
  dda_walk<T> w = dda_walk_begin(g.grid, origin, dir, t_max);
  if (!w.running) return miss;
  const T L = voxel_length(g.grid);
  const T eps = end_tolerance_voxels * L, slack = T(triangle_voxel_edge_slack) * L;
  const int max_iterations = dda_max_iterations(g.grid.resolution);
  for (int it = 0; w.running && it < max_iterations; ++it) {
    if (g.bricks != nullptr && !voxel_brick_occupied(g.grid.resolution, g.bricks, w.voxel)) {
      dda_walk_leave_brick(g.grid, w);
      continue;
    }
    const std::int64_t r = voxel_occupied_index(g.grid, g.rank, w.voxel);
    if (r >= 0) {
      const T t_out = dda_walk_exit(w) + slack;
      T best = std::numeric_limits<T>::infinity();
      std::uint32_t best_tri = 0xFFFFFFFFu;
      for (std::uint32_t e = g.offsets[r], end = g.offsets[r + 1]; e < end; ++e) {
        const voxel_triangle<T>& tri = g.triangles[g.entries[e]];
        const T d0 = glm::dot(tri.plane.normal, origin) - tri.plane.offset;
        const T den = glm::dot(tri.plane.normal, w.d);
        if (!(std::abs(d0) > eps) || den == T(0)) continue;
        const T tc = -d0 / den;
        if (!(tc > T(0)) || tc > t_max || tc > t_out || !(tc < best)) continue;
        if (voxel_triangle_contains(tri, origin + tc * w.d, slack)) {
          best = tc;
          best_tri = g.entries[e];
        }
      }
      if (best_tri != 0xFFFFFFFFu) return triangle_voxel_hit<T>{true, best, origin + best * w.d, best_tri};
    }
    dda_walk_next(g.grid, w);
  }
  return miss;
}

// ---- The offset contract (exact visibility's, on the listed triangles) ----

// The grid's ends offset: bvh_surface_offset's formula, offset_relative * D + 2^-15 * M, over the
// grid's box (D its largest extent, M its largest |coordinate|). The box is the triangles' padded
// one (fit_voxel_bounds), so this is about 2 % above the offset of a BVH over the same triangles;
// a host that has that offset passes it instead.
namespace detail {
// M: the largest |coordinate| of the grid's box.
template <class T>
inline T triangle_voxel_largest_coordinate(const voxel_grid_view<T>& g) {
  const vec3<T> lo = g.bounds_min, hi = g.bounds_max;
  return std::fmax(std::fmax(std::fmax(std::abs(lo.x), std::abs(hi.x)), std::fmax(std::abs(lo.y), std::abs(hi.y))),
                   std::fmax(std::abs(lo.z), std::abs(hi.z)));
}
}  // namespace detail

template <class T>
inline T triangle_voxel_surface_offset(const voxel_grid_view<T>& g, T offset_relative = T(bvh_offset_relative_default)) {
  const vec3<T> ext = g.bounds_max - g.bounds_min;
  const T d = std::fmax(ext.x, std::fmax(ext.y, ext.z));
  return offset_relative * d + T(bvh_offset_coordinate_scale) * detail::triangle_voxel_largest_coordinate(g);
}

// How far the offset contract grows each triangle within its plane: 2^-18 M (32 float ulps of the
// grid's largest |coordinate|), above the inside test's rounding (a few ulps of M) so that no
// segment passes between two triangles sharing an edge, and far below the end rule's 1e-3 voxel,
// which blocks segments that graze an edge.
template <class T>
inline T triangle_voxel_offset_slack(const voxel_grid_view<T>& g) {
  return detail::triangle_voxel_largest_coordinate(g) * T(1.0 / 262144.0);
}

// Is the segment a -> b free of the grid's triangles, counting a crossing at s in (0, 1] (b itself
// included, a excluded, as bvh_occluded's t range)? Each triangle grown by `slack` (world units).
// a == b is free; non-finite a or b is not.
template <class T>
inline bool triangle_voxel_segment_free(const triangle_voxel_view<T>& g, vec3<T> a, vec3<T> b, T slack) {
  if (!detail::voxel_vec3_finite(a) || !detail::voxel_vec3_finite(b)) return false;
  const vec3<T> dir = b - a;
  const T len = std::sqrt(glm::dot(dir, dir));
  if (!(len > T(0))) return true;
  const T L = voxel_length(g.grid), stretch = T(triangle_voxel_edge_slack) * L;
  dda_walk<T> w = dda_walk_begin(g.grid, a, dir, len);
  const int max_iterations = dda_max_iterations(g.grid.resolution);
  for (int it = 0; w.running && it < max_iterations; ++it) {
    if (g.bricks != nullptr && !voxel_brick_occupied(g.grid.resolution, g.bricks, w.voxel)) {
      dda_walk_leave_brick(g.grid, w);
      continue;
    }
    const std::int64_t r = voxel_occupied_index(g.grid, g.rank, w.voxel);
    if (r >= 0) {
      // The voxel's stretch of the segment (widened as the end rule's, so that a crossing on a
      // voxel face is found from both sides).
      const T s_in = (w.t - stretch) / len, s_out = (dda_walk_exit(w) + stretch) / len;
      for (std::uint32_t e = g.offsets[r], end = g.offsets[r + 1]; e < end; ++e) {
        const voxel_triangle<T>& tri = g.triangles[g.entries[e]];
        const T d0 = glm::dot(tri.plane.normal, a) - tri.plane.offset;
        const T d1 = glm::dot(tri.plane.normal, b) - tri.plane.offset;
        // A plane through a (d0 == 0) or a degenerate triangle (normal 0) is never crossed in
        // (0, 1]; b on the plane (d1 == 0) is a crossing at s = 1.
        if (d0 == T(0) || (d1 != T(0) && (d0 > T(0)) == (d1 > T(0)))) continue;
        const T s = d0 / (d0 - d1);
        if (s < s_in || s > s_out) continue;
        if (voxel_triangle_contains(tri, a + s * dir, slack)) return false;
      }
    }
    dda_walk_next(g.grid, w);
  }
  return true;
}

// Mutual visibility under the offset contract: x and y moved `offset` along their normals
// (bvh_offset_point: a zero or non-finite normal leaves its point), the segment between them
// tested whole with triangle_voxel_offset_slack. What bvh_visible answers over the same triangles
// with the same offset, up to that slack. Non-finite x or y: not visible.
template <class T>
inline bool triangle_voxel_visible_offset(const triangle_voxel_view<T>& g, vec3<T> x, vec3<T> n_x, vec3<T> y,
                                          vec3<T> n_y, T offset) {
  if (!detail::voxel_vec3_finite(x) || !detail::voxel_vec3_finite(y)) return false;
  return triangle_voxel_segment_free(g, bvh_offset_point(x, n_x, offset), bvh_offset_point(y, n_y, offset),
                                     triangle_voxel_offset_slack(g.grid));
}

// The first triangle met by the ray leaving surface x along dir under the offset contract: from x
// moved `offset` along n_x, every listed triangle (grown by triangle_voxel_offset_slack) counts at
// t > 0. t is measured from the moved origin along the unit direction, and t_max from it as well:
// a hit within reach of x lies within reach + offset of the moved origin (bvh_trace's reach rule).
template <class T>
inline triangle_voxel_hit<T> triangle_voxel_first_hit_offset(const triangle_voxel_view<T>& g, vec3<T> x, vec3<T> n_x,
                                                             vec3<T> dir, T offset,
                                                             T t_max = std::numeric_limits<T>::infinity()) {
  const vec3<T> origin = bvh_offset_point(x, n_x, offset);
  const triangle_voxel_hit<T> miss{false, T(0), origin, 0xFFFFFFFFu};
  if (!detail::voxel_vec3_finite(origin)) return miss;
  dda_walk<T> w = dda_walk_begin(g.grid, origin, dir, t_max);
  if (!w.running) return miss;
  const T slack = triangle_voxel_offset_slack(g.grid), stretch = T(triangle_voxel_edge_slack) * voxel_length(g.grid);
  const int max_iterations = dda_max_iterations(g.grid.resolution);
  for (int it = 0; w.running && it < max_iterations; ++it) {
    if (g.bricks != nullptr && !voxel_brick_occupied(g.grid.resolution, g.bricks, w.voxel)) {
      dda_walk_leave_brick(g.grid, w);
      continue;
    }
    const std::int64_t r = voxel_occupied_index(g.grid, g.rank, w.voxel);
    if (r >= 0) {
      const T t_out = dda_walk_exit(w) + stretch;
      T best = std::numeric_limits<T>::infinity();
      std::uint32_t best_tri = 0xFFFFFFFFu;
      for (std::uint32_t e = g.offsets[r], end = g.offsets[r + 1]; e < end; ++e) {
        const voxel_triangle<T>& tri = g.triangles[g.entries[e]];
        const T d0 = glm::dot(tri.plane.normal, origin) - tri.plane.offset;
        const T den = glm::dot(tri.plane.normal, w.d);
        if (d0 == T(0) || den == T(0)) continue;
        const T tc = -d0 / den;
        if (!(tc > T(0)) || tc > t_max || tc > t_out || !(tc < best)) continue;
        if (voxel_triangle_contains(tri, origin + tc * w.d, slack)) {
          best = tc;
          best_tri = g.entries[e];
        }
      }
      if (best_tri != 0xFFFFFFFFu) return triangle_voxel_hit<T>{true, best, origin + best * w.d, best_tri};
    }
    dda_walk_next(g.grid, w);
  }
  return miss;
}

}  // namespace vplkit
