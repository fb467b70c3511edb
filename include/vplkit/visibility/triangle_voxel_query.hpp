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
#include <vplkit/core/vector.hpp>
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

}  // namespace vplkit
