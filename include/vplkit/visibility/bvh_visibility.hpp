// SPDX-License-Identifier: MIT
#pragma once
// Exact visibility through a BVH, as the two callables the estimators take (the exact
// counterparts of voxel_visibility and voxel_tracer in visibility/visibility_callables.hpp):
//   bvh_visibility<T>{view}(x, n_x, y, n_y) -> bool        mutual visibility of two surface points
//   bvh_tracer<T>{view}(x, n_x, dir)        -> ray_hit<T>  first surface hit leaving surface x
// glsl/vplkit/visibility/bvh_visibility.glsl mirrors them.
//
// Self-intersection: both ends of a segment, and the origin of a traced ray, are moved off their
// surface along their normal (as given: the side the point is seen from) by
//   offset = offset_relative * D + 2^-15 * M,
// D = the largest extent of the hierarchy's root box (the scene's size), M = its largest
// |coordinate| (how far the scene lies from the world origin). The segment between the moved
// ends is then tested whole, (0, 1].
// Why an offset along the normal and not a shrunk parameter range [eps, 1 - eps]: the points
// come from rasterised G-buffers and DPRSMs, so they lie off the true surface by interpolation
// error, possibly below it; a segment leaving such a point at a grazing angle crosses its own
// surface at a parameter distance of error / sin(angle), which no fixed eps bounds, while an
// offset larger than the error clears the surface at every angle. The first term covers that
// error relative to the scene (default 1e-4 of its size: a contact gap of 0.1 mm in a 1 m room);
// the second is 256 float ulps of the largest coordinate, the rounding of points far from the
// origin (Waechter and Binder, "A fast and robust method for avoiding self-intersection", Ray
// Tracing Gems, 2019, use 256 ulps for the same reason). The price: an occluder closer than the
// offset to an end point is missed (light leaks through gaps thinner than the offset).
// Which side: the normal's. A G-buffer's and a DPRSM's normals face the camera and the light, and
// the estimators give no weight to a y behind x's surface (cos clamped at 0), so a pair that
// matters always leaves x on its normal's side. Flipping the normal towards the other end instead
// would make nearly coplanar pairs (cos ~ 0) land on opposite sides by the sign of rounding noise.
// As with voxel_visible_two_sided, y behind x's surface is hidden by x's own surface. Normals need
// not be unit length; a zero or non-finite normal leaves the point where it is.
// Non-finite x or y: not visible (no contribution rather than a NaN one); x == y: visible.
#include <vplkit/core/vector.hpp>
#include <vplkit/core/gather_point.hpp>
#include <vplkit/visibility/bvh_layout.hpp>
#include <vplkit/visibility/bvh_traverse.hpp>

#include <cmath>

namespace vplkit {

constexpr double bvh_offset_relative_default = 1e-4;
constexpr double bvh_offset_coordinate_scale = 1.0 / 32768.0;  // 2^-15 = 256 float ulps of a coordinate

// The distance end points are moved off their surfaces: offset_relative * D + 2^-15 * M (see the
// header); 0 for an empty hierarchy.
template <class T>
inline T bvh_surface_offset(const bvh_view<T>& b, T offset_relative = T(bvh_offset_relative_default)) {
  if (b.node_count == 0) return T(0);
  const vec3<T> lo = b.nodes[0].bounds_min, hi = b.nodes[0].bounds_max;
  const vec3<T> ext = hi - lo;
  const T d = std::fmax(ext.x, std::fmax(ext.y, ext.z));
  const vec3<T> m3(std::fmax(std::abs(lo.x), std::abs(hi.x)), std::fmax(std::abs(lo.y), std::abs(hi.y)),
                   std::fmax(std::abs(lo.z), std::abs(hi.z)));
  const T m = std::fmax(m3.x, std::fmax(m3.y, m3.z));
  return offset_relative * d + T(bvh_offset_coordinate_scale) * m;
}

// x moved by `offset` along the unit normal.
template <class T>
inline vec3<T> bvh_offset_point(vec3<T> x, vec3<T> n, T offset) {
  return x + offset * detail::bvh_unit_vector(n);
}

// Are the surface points x (normal n_x) and y (normal n_y) mutually visible?
template <class T>
inline bool bvh_visible(const bvh_view<T>& b, vec3<T> x, vec3<T> n_x, vec3<T> y, vec3<T> n_y,
                        T offset_relative = T(bvh_offset_relative_default)) {
  if (!detail::bvh_vec3_finite(x) || !detail::bvh_vec3_finite(y)) return false;
  const T offset = bvh_surface_offset(b, offset_relative);
  const vec3<T> o = bvh_offset_point(x, n_x, offset);
  const vec3<T> p = bvh_offset_point(y, n_y, offset);
  return !bvh_occluded(b, o, p - o, T(0), T(1));
}

// The first surface hit by the ray leaving surface x (normal n_x) along dir, from x moved off its
// surface (bvh_offset_point). The hit position is the barycentric point on the triangle hit
// (bvh_hit::position), exact to float rounding, unlike the voxel tracer's voxel-entry point: a
// DPRSM depth test on it needs only the texel's own depth spread as tolerance.
template <class T>
inline ray_hit<T> bvh_trace(const bvh_view<T>& b, vec3<T> x, vec3<T> n_x, vec3<T> dir,
                            T offset_relative = T(bvh_offset_relative_default)) {
  const vec3<T> o = bvh_offset_point(x, n_x, bvh_surface_offset(b, offset_relative));
  const bvh_hit<T> h = bvh_closest_hit(b, o, dir);
  ray_hit<T> r;
  r.hit = h.hit;
  if (h.hit) {
    r.position = h.position;
    r.normal = h.normal;
  }
  return r;
}

template <class T>
struct bvh_visibility {
  bvh_view<T> bvh;
  T offset_relative = T(bvh_offset_relative_default);
  bool operator()(vec3<T> x, vec3<T> n_x, vec3<T> y, vec3<T> n_y) const {
    return bvh_visible(bvh, x, n_x, y, n_y, offset_relative);
  }
};

template <class T>
struct bvh_tracer {
  bvh_view<T> bvh;
  T offset_relative = T(bvh_offset_relative_default);
  ray_hit<T> operator()(vec3<T> x, vec3<T> n_x, vec3<T> dir) const { return bvh_trace(bvh, x, n_x, dir, offset_relative); }
};

}  // namespace vplkit
