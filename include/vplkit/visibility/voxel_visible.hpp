// SPDX-License-Identifier: MIT
#pragma once
// Point-to-point visibility through the voxel grid (docs/math.md section 7; the paper's Alg. 6,
// lines 8-10). L = voxel_length (the largest voxel edge) is the unit of every offset and tolerance.
//
// voxel_visible (the paper's test, one-sided):
//   o = surface_ray_origin(x, n_x),  dist = |y - o|,
//   visible  <=>  the first occupied voxel on the ray o -> y is entered beyond dist - psi,
//                 psi = tolerance_voxels * L   (closed: entered exactly at dist - psi = occluded).
// voxel_visible_two_sided: both ends are lifted off their surfaces, o = surface_ray_origin(x, n_x),
//   o_y = surface_ray_origin(y, n_y), and the test above runs from o to o_y.
//
// Why the offset defaults to 1.75 voxels (just above sqrt(3)): a conservative voxelisation marks
// every voxel touching a surface, and every point of such a voxel lies within one voxel diagonal
// (<= sqrt(3) L) of the surface. A point lifted more than sqrt(3) L along the normal of a locally
// flat surface is therefore outside the surface's own shell, whatever the surface's tilt. With one
// voxel (the paper's "about one voxel") a tilted surface still occludes itself.
// The one-sided test has the same problem at y: the ray enters y's shell up to
// (shell thickness) / cos(angle to n_y) before y, unbounded at grazing angles, so psi can only
// trade occlusion errors near y against light leaking through walls within psi of y.
// Measured (docs/api/visibility.md): on a tilted floor + wall, voxelised at 32^3 .. 128^3, the
// one-sided test with offset 1.75 and psi = 2 keeps 76-82 % of the (unoccluded) VPL contribution;
// the two-sided test with offset 1.75, psi = 0 keeps 92-100 % and leaks through no wall.
// Prefer the two-sided test whenever y has a normal (every VPL does).
#include <vplkit/core/vector.hpp>
#include <vplkit/visibility/dda.hpp>
#include <vplkit/visibility/voxel_grid.hpp>

#include <cmath>

namespace vplkit {

constexpr double voxel_surface_offset_default = 1.75;
constexpr double voxel_visible_default_tolerance = 2.0;
constexpr double voxel_visible_two_sided_default_tolerance = 0.0;

// Ray origin for rays leaving the surface at x with normal n_x (need not be unit length): x moved
// offset_voxels * L along n_x. A zero or non-finite normal leaves x where it is. Also the origin
// of the GBG gathering rays (then trace with dda_trace_hit_point).
template <class T>
inline vec3<T> surface_ray_origin(const voxel_grid_view<T>& g, vec3<T> x, vec3<T> n_x,
                                  T offset_voxels = T(voxel_surface_offset_default)) {
  vec3<T> n(T(0));
  if (!dda_unit_direction(n_x, n)) return x;
  return x + (offset_voxels * voxel_length(g)) * n;
}

// Is there no occupied voxel on the segment o -> target before |target - o| - psi? The shared
// core of both tests (o already lifted off its surface). Points closer than psi are visible.
template <class T>
inline bool voxel_segment_clear(const voxel_grid_view<T>& g, vec3<T> o, vec3<T> target, T tolerance_voxels) {
  const vec3<T> to_target = target - o;
  const T t_max = glm::length(to_target) - tolerance_voxels * voxel_length(g);
  if (!(t_max > T(0))) return true;
  return !dda_first_hit(g, o, to_target, t_max).hit;
}

// The paper's test: is y visible from the surface point x (normal n_x)? Non-finite x or y: not
// visible (no contribution rather than a NaN one).
template <class T>
inline bool voxel_visible(const voxel_grid_view<T>& g, vec3<T> x, vec3<T> n_x, vec3<T> y,
                          T offset_voxels = T(voxel_surface_offset_default),
                          T tolerance_voxels = T(voxel_visible_default_tolerance)) {
  if (!detail::voxel_vec3_finite(x) || !detail::voxel_vec3_finite(y)) return false;
  return voxel_segment_clear(g, surface_ray_origin(g, x, n_x, offset_voxels), y, tolerance_voxels);
}

// Both ends lifted: are the surface points x (normal n_x) and y (normal n_y) mutually visible?
template <class T>
inline bool voxel_visible_two_sided(const voxel_grid_view<T>& g, vec3<T> x, vec3<T> n_x, vec3<T> y, vec3<T> n_y,
                                    T offset_voxels = T(voxel_surface_offset_default),
                                    T tolerance_voxels = T(voxel_visible_two_sided_default_tolerance)) {
  if (!detail::voxel_vec3_finite(x) || !detail::voxel_vec3_finite(y)) return false;
  return voxel_segment_clear(g, surface_ray_origin(g, x, n_x, offset_voxels),
                             surface_ray_origin(g, y, n_y, offset_voxels), tolerance_voxels);
}

}  // namespace vplkit
