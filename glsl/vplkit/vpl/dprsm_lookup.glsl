// SPDX-License-Identifier: MIT
// vplkit GLSL pack: is a surface point lit by the light, and through which DPRSM texel? Mirrors
// include/vplkit/vpl/dprsm_lookup.hpp (T = float): the shadow-map test of the gathering estimator,
// the GBG builder and the direct light (docs/math.md section 4). y is lit when it does not lie
// behind the texel's plane (through y_t, normal n_t); the C++ comments give the reasoning.
//
// ACCESSORS used (declared in dprsm_view.glsl, defined by the including shader):
//   vec3 vplkit_load_dprsm_position(int texel);
//   vec3 vplkit_load_dprsm_normal(int texel);
//   vec3 vplkit_load_dprsm_albedo(int texel);
#ifndef VPLKIT_VPL_DPRSM_LOOKUP_GLSL
#define VPLKIT_VPL_DPRSM_LOOKUP_GLSL

#include "vplkit/core/constants.glsl"
#include "vplkit/core/gather_point.glsl"
#include "vplkit/core/normal_range.glsl"
#include "vplkit/core/unit_or_zero.glsl"
#include "vplkit/vpl/dprsm_view.glsl"
#include "vplkit/vpl/vpl.glsl"

struct vplkit_dprsm_lookup_result {
  int texel;      // flat texel index y projects into (-1 when y coincides with the light)
  bool lit;       // texel valid, saw a surface, and y is not behind that surface
  bool in_front;  // lit, and in front of that surface beyond the tolerance (another surface)
};

// dprsm_plane_side: where a point lies against the surface a texel saw.
const int vplkit_dprsm_plane_behind = 0;
const int vplkit_dprsm_plane_on = 1;
const int vplkit_dprsm_plane_in_front = 2;

// Below this cosine between the light ray and the texel's plane the centre's depth stands in.
const float vplkit_dprsm_plane_min_cos = 1e-3;

// The lit test's own slack at distance d: half the widest texel footprint, and rounding.
float vplkit_dprsm_lookup_slack(float d, int resolution) {
  return d * (2.0 / float(resolution) + 1e-4);
}

// y behind, on or in front of the plane (y_t, n_t) within tolerance + slack along the light ray,
// tested as n . (y - y_t) against -+tol cos(alpha); else (grazing, plane facing away) against the
// centre's depth. A bad tolerance or a distance that is not finite and positive: behind.
int vplkit_dprsm_plane_side_of(vec3 c, vec3 y_t, vec3 n_t, vec3 y, float d_y, float tolerance, int resolution) {
  // Beyond 2^126: behind (the division below would go through a flushed reciprocal), as the C++.
  if (!(tolerance >= 0.0) || !(d_y > 0.0) || !(d_y <= 8.5070591730234616e37)) return vplkit_dprsm_plane_behind;
  float tol = tolerance + vplkit_dprsm_lookup_slack(d_y, resolution);
  vec3 n = vplkit_unit_or_zero(n_t);
  float h = dot(n, c - y_t);
  float cos_a = -dot(n, (y - c) / d_y);
  if (h > 0.0 && cos_a > vplkit_dprsm_plane_min_cos) {
    float s = dot(n, y - y_t), band = tol * cos_a;
    if (!(s >= -band)) return vplkit_dprsm_plane_behind;
    return s > band ? vplkit_dprsm_plane_in_front : vplkit_dprsm_plane_on;
  }
  float d_t = length(y_t - c);
  if (!(d_y <= d_t + tol)) return vplkit_dprsm_plane_behind;
  return d_y < d_t - tol ? vplkit_dprsm_plane_in_front : vplkit_dprsm_plane_on;
}

// The lit test: y not behind the texel's plane.
bool vplkit_dprsm_plane_lit(vec3 c, vec3 y_t, vec3 n_t, vec3 y, float d_y, float tolerance, int resolution) {
  return vplkit_dprsm_plane_side_of(c, y_t, n_t, y, d_y, tolerance, resolution) != vplkit_dprsm_plane_behind;
}

// Where the light ray towards y meets texel t's plane (y_t, n_t); y where the plane cannot say.
vec3 vplkit_dprsm_plane_point_towards(vec3 c, vec3 y_t, vec3 n_t, vec3 y) {
  vec3 w = vplkit_unit_or_zero(y - c);
  vec3 n = vplkit_unit_or_zero(n_t);
  float h = dot(n, c - y_t);
  float cos_a = -dot(n, w);
  if (!(h > 0.0) || !(cos_a > vplkit_dprsm_plane_min_cos)) return y;
  return c + (h / cos_a) * w;
}

// Did texel t (any int) see a surface: a valid texel with a nonzero albedo?
bool vplkit_dprsm_texel_saw_surface(vplkit_dprsm_view view, int t) {
  if (t < 0 || t >= vplkit_dprsm_view_texel_count(view) || !vplkit_dprsm_view_texel_valid(view, t)) return false;
  vec3 rho = vplkit_load_dprsm_albedo(t);
  return rho.x > 0.0 || rho.y > 0.0 || rho.z > 0.0;
}

// tolerance: world-space error of y's position along the light ray (0 for exact hits); the lit
// test adds its own slack.
vplkit_dprsm_lookup_result vplkit_dprsm_lookup(vplkit_dprsm_view view, vec3 y, float tolerance) {
  vplkit_dprsm_lookup_result r = vplkit_dprsm_lookup_result(-1, false, false);
  vec3 to_y = y - view.light.position;
  float d_y = vplkit_scaled_length(to_y);  // scale-first, as the C++
  if (!(d_y > 0.0)) return r;
  r.texel = vplkit_dprsm_view_texel_of_direction(view, to_y);
  if (!vplkit_dprsm_texel_saw_surface(view, r.texel)) return r;
  int side = vplkit_dprsm_plane_side_of(view.light.position, vplkit_load_dprsm_position(r.texel),
                                        vplkit_load_dprsm_normal(r.texel), y, d_y, tolerance, view.resolution);
  r.lit = side != vplkit_dprsm_plane_behind;
  r.in_front = side == vplkit_dprsm_plane_in_front;
  return r;
}

// L_o towards x of a hit the lookup lk found lit: a hit whose tracer knows its surface shaded as
// that surface (lit side facing the light, the cosine from its shading normal), else with the
// texel's normal (one-sided; a hit known only within depth_tolerance > 0 evaluated on the texel's
// plane in its direction); the texel's albedo either way. The C++ says why.
vec3 vplkit_dprsm_hit_radiance(vplkit_dprsm_view view, vplkit_dprsm_lookup_result lk, vec3 x, vplkit_ray_hit hit,
                               float depth_tolerance) {
  int t = lk.texel;
  vec3 c = view.light.position;
  vec3 y = hit.position;
  if (vplkit_ray_hit_has_normal(hit)) {
    vec3 n_g = vplkit_ray_hit_normal_towards(hit, c);
    if (!(dot(vplkit_unit_or_zero(n_g), vplkit_unit_or_zero(x - y)) > 0.0)) return vec3(0.0);  // unlit side
    return vplkit_reflected_radiance(c, view.light.intensity, y, vplkit_ray_hit_shading_normal(hit, n_g),
                                     vplkit_load_dprsm_albedo(t));
  }
  vec3 n_t = vplkit_load_dprsm_normal(t);
  if (!(dot(vplkit_unit_or_zero(n_t), vplkit_unit_or_zero(x - y)) > 0.0)) return vec3(0.0);  // from behind
  vec3 at = depth_tolerance > 0.0 ? vplkit_dprsm_plane_point_towards(c, vplkit_load_dprsm_position(t), n_t, y) : y;
  return vplkit_reflected_radiance(c, view.light.intensity, at, n_t, vplkit_load_dprsm_albedo(t));
}

#endif  // VPLKIT_VPL_DPRSM_LOOKUP_GLSL
