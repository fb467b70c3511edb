// SPDX-License-Identifier: MIT
// vplkit GLSL pack: what builders and estimators know of the camera's visible points; mirrors
// include/vplkit/core/gather_point.hpp (T = float): vplkit_gather_point, vplkit_gather_point_valid
// (decided as the C++ decides it), vplkit_gbuffer_view (the sizes; the arrays are the accessor),
// vplkit_ray_hit, the two normals' helpers (vplkit_gather_point_shading_normal, _above,
// _accepts_direction). ACCESSOR, declared here and referenced only by builders/gather_subset.glsl:
//   vplkit_gather_point vplkit_load_gather_point(int pixel);   // pixel = y * width + x
// docs/glsl/core.md.
#ifndef VPLKIT_CORE_GATHER_POINT_GLSL
#define VPLKIT_CORE_GATHER_POINT_GLSL

#include "vplkit/core/unit_or_zero.glsl"

struct vplkit_gather_point {
  vec3 position;
  vec3 normal;  // need not be unit length; zero means "no surface" (background pixel)
  vec3 albedo;  // diffuse reflectance rho_x
  // The shading normal, on the geometric normal's side; zero means "the same as normal" (the C++
  // comment says where each is used).
  vec3 shading_normal;
};

// What a ray cast returns: the first surface point along a ray, if any, and what the tracer knows
// of the surface there: its geometric normal (zero: unknown, as the voxel-entry tracer) and the
// normal of the light's cosine (zero: the same as normal). The C++ says where each is used.
struct vplkit_ray_hit {
  bool hit;
  vec3 position;
  vec3 normal;
  vec3 shading_normal;
};

bool vplkit_ray_hit_has_normal(vplkit_ray_hit h) {
  return h.normal.x != 0.0 || h.normal.y != 0.0 || h.normal.z != 0.0;
}

// The hit's geometric normal turned to the side of point p.
vec3 vplkit_ray_hit_normal_towards(vplkit_ray_hit h, vec3 p) {
  return dot(h.normal, p - h.position) < 0.0 ? -h.normal : h.normal;
}

// The hit's shading normal on the side of n_g, or n_g where none is set.
vec3 vplkit_ray_hit_shading_normal(vplkit_ray_hit h, vec3 n_g) {
  vec3 n_s = h.shading_normal;
  if (!(n_s.x != 0.0 || n_s.y != 0.0 || n_s.z != 0.0)) return n_g;
  return dot(n_s, n_g) < 0.0 ? -n_s : n_s;
}

// The C++ view's arrays are the accessor; the sizes remain.
struct vplkit_gbuffer_view {
  int width;
  int height;
};

vplkit_gather_point vplkit_load_gather_point(int pixel);

// Finite (not NaN, not +-inf), decided on the bits.
bool vplkit_gather_point_isfinite(float x) { return vplkit_is_finite(x); }

// Background pixels (zero or non-finite normal, non-finite position) are skipped by every builder
// and estimator.
bool vplkit_gather_point_valid(vplkit_gather_point g) {
  precise float n2 = g.normal.x * g.normal.x + g.normal.y * g.normal.y + g.normal.z * g.normal.z;
  return n2 > 0.0 && vplkit_gather_point_isfinite(n2) && vplkit_gather_point_isfinite(g.position.x) &&
         vplkit_gather_point_isfinite(g.position.y) && vplkit_gather_point_isfinite(g.position.z);
}

// The normal of the receiver's cosine: the shading normal, or the geometric one where none is set.
vec3 vplkit_gather_point_shading_normal(vplkit_gather_point g) {
  bool set = g.shading_normal.x != 0.0 || g.shading_normal.y != 0.0 || g.shading_normal.z != 0.0;
  return set ? g.shading_normal : g.normal;
}

// True where the unit direction wd leaves x above its geometric surface.
bool vplkit_gather_point_above(vplkit_gather_point g, vec3 wd) {
  return dot(vplkit_unit_or_zero(g.normal), wd) > 0.0;
}

// Directions sampled around the shading normal that point below the geometric surface count as
// zero samples; with one normal nothing is rejected.
bool vplkit_gather_point_accepts_direction(vplkit_gather_point g, vec3 wd) {
  vec3 ns = vplkit_gather_point_shading_normal(g);
  bool one_normal = ns.x == g.normal.x && ns.y == g.normal.y && ns.z == g.normal.z;
  return one_normal || vplkit_gather_point_above(g, wd);
}

// A gather point stored as three vec4 (the kernels' G-buffer layout): position, geometric normal
// and albedo in .xyz, the shading normal in the three .w (all 0: none, the geometric normal shades).
vplkit_gather_point vplkit_unpack_gather_point(vec4 position_sx, vec4 normal_sy, vec4 albedo_sz) {
  return vplkit_gather_point(position_sx.xyz, normal_sy.xyz, albedo_sz.xyz,
                             vec3(position_sx.w, normal_sy.w, albedo_sz.w));
}

int vplkit_gbuffer_view_pixel_count(vplkit_gbuffer_view v) {
  return v.width * v.height;
}

#endif  // VPLKIT_CORE_GATHER_POINT_GLSL
