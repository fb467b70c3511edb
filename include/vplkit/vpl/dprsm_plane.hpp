// SPDX-License-Identifier: MIT
#pragma once
// The plane record of a DPRSM texel: what the patch-sampled VPLs (dprsm_patch.hpp) need of a
// texel's plane, in one 16-byte record so that a GPU reads it with one vector load. The plane is
// the one through the texel's point y_t with its unit normal n_u = unit_or_zero(n_t); its height
// over the light c is h = n_u . (c - y_t) (a plane point along the unit light direction w lies at
// h / (-n_u . w)). The record is
//   {n_u, +h}  a valid texel that saw a surface (albedo != 0) and faces the light (h > 0): its
//              plane can hide a neighbour's plane points (dprsm_patch_point_hidden);
//   {n_u, -h}  the same plane of a texel that saw nothing (albedo 0): it hides nothing, but its
//              own patch keeps its plane (|height| = h), as the direct computation does;
//   {0, 0}     an invalid texel (outside its face's disk), or h not > 0 (facing away, the light
//              on the plane, a zero or non-finite normal, non-finite h): no plane at all.
// So `height > 0` is exactly the hidden test's "this neighbour has a plane that can hide", and
// |height| with normal is exactly what dprsm_patch_vpl computes for its own texel when h > 0. The
// values are the direct computation's own expressions (unit_or_zero, glm::dot in x, y, z order),
// so a record and the direct path give the same bits in C++; the GLSL mirror computes h with
// `precise` in that order (dprsm_plane.glsl says why).
//
// Records depend on the light position: build them for the light of the view that reads them
// (build_dprsm_planes, dprsm_view::planes).
#include <vplkit/core/unit_or_zero.hpp>
#include <vplkit/core/vector.hpp>

#include <cmath>

namespace vplkit {

// std430 vec4: xyz the unit normal n_u, w the signed height (see above). 16 bytes for T = float.
template <class T>
struct dprsm_plane {
  vec3<T> normal{T(0)};
  T height = T(0);
};

// The record of a texel at y with normal n (any length) and albedo rho, `valid` as texel_is_valid,
// for the light at c.
template <class T>
inline dprsm_plane<T> dprsm_plane_of(vec3<T> c, bool valid, vec3<T> y, vec3<T> n, vec3<T> rho) {
  dprsm_plane<T> p;
  if (!valid) return p;
  const vec3<T> n_u = unit_or_zero(n);
  const T h = glm::dot(n_u, c - y);
  if (!(h > T(0))) return p;
  const bool saw_surface = rho.x > T(0) || rho.y > T(0) || rho.z > T(0);
  p.normal = n_u;
  p.height = saw_surface ? h : -h;
  return p;
}

// Can this plane hide a neighbour's plane points (valid, saw a surface, faces the light)?
template <class T>
inline bool dprsm_plane_can_hide(const dprsm_plane<T>& p) {
  return p.height > T(0);
}

}  // namespace vplkit
