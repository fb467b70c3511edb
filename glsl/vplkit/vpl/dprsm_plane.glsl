// SPDX-License-Identifier: MIT
// vplkit GLSL pack: the plane record of a DPRSM texel, mirroring include/vplkit/vpl/dprsm_plane.hpp
// (T = float; the C++ struct dprsm_plane<float> {normal, height} is this vec4 (xyz, w), 16 bytes):
//   vec4(n_u, +h)  valid, saw a surface (albedo != 0), faces the light (h > 0): can hide;
//   vec4(n_u, -h)  the same plane of a texel that saw nothing: hides nothing, keeps its plane;
//   vec4(0)        invalid, or h not > 0 (facing away, the light on the plane, no normal).
// n_u = vplkit_unit_or_zero(n), h = n_u . (c - y). h is computed `precise`, as the C++ glm::dot
// rounds it ((x + y) + z, no FMA): the record is then the same value wherever it is computed (the
// builder kernel dprsm_planes.comp, or vplkit_dprsm_view_plane_at in an estimate kernel without
// records), and differs from the C++ only through unit_or_zero's inversesqrt (2 ulp).
#ifndef VPLKIT_VPL_DPRSM_PLANE_GLSL
#define VPLKIT_VPL_DPRSM_PLANE_GLSL

#include "vplkit/core/unit_or_zero.glsl"

// The record of a texel at y with normal n (any length) and albedo rho, `valid` as
// vplkit_texel_is_valid, for the light at c.
vec4 vplkit_dprsm_plane_of(vec3 c, bool valid, vec3 y, vec3 n, vec3 rho) {
  if (!valid) return vec4(0.0);
  vec3 n_u = vplkit_unit_or_zero(n);
  precise vec3 d = c - y;
  precise float h = (n_u.x * d.x + n_u.y * d.y) + n_u.z * d.z;
  if (!(h > 0.0) || vplkit_is_nan(h)) return vec4(0.0);  // NaN on the bits (normal_range.glsl)
  bool saw_surface = rho.x > 0.0 || rho.y > 0.0 || rho.z > 0.0;
  return vec4(n_u, saw_surface ? h : -h);
}

// Can this plane hide a neighbour's plane points (valid, saw a surface, faces the light)?
bool vplkit_dprsm_plane_can_hide(vec4 plane) { return plane.w > 0.0; }

#endif  // VPLKIT_VPL_DPRSM_PLANE_GLSL
