// SPDX-License-Identifier: MIT
// vplkit GLSL pack: VPL model (docs/math.md sections 2 and 5), mirroring include/vplkit/vpl/vpl.hpp
// (T = float) line for line: flux of a DPRSM texel, contribution of a VPL to a gather point,
// radiance reflected by a directly lit diffuse point. No visibility here: callers multiply by V.
//
// Robustness (as on the CPU): never NaN or Inf for finite inputs.
//  - Normals may have any length (vplkit_unit_or_zero); a zero normal gives 0.
//  - Points closer than vplkit_vpl_coincidence_tolerance (16 eps times their largest coordinate)
//    are the same point: the result is 0 (covers x == y with dmin = 0).
//  - Squared distances are raised to at least vplkit_vpl_distance_sq_floor() = 2^-63, so
//    1 / (pi d^2) <= 2.9e18.
//  - NaN inputs give 0 on the CPU; GPU compilers may assume NaN never occurs (CPU guarantee).
//  - A result, cosine or flux below the smallest normal float is 0 (the normal-range contract,
//    docs/math.md "GPU arithmetic model"): the same on a device that flushes denormals and on one
//    that keeps them. Products that feed a result are written `precise` where the order decides
//    whether an intermediate underflows.
#ifndef VPLKIT_VPL_VPL_GLSL
#define VPLKIT_VPL_VPL_GLSL

#include "vplkit/core/constants.glsl"
#include "vplkit/core/gather_point.glsl"
#include "vplkit/core/normal_range.glsl"
#include "vplkit/core/unit_or_zero.glsl"

struct vplkit_vpl {
  vec3 position;  // y_t
  vec3 normal;    // n_t (any length; normalised where used)
  vec3 flux;      // Phi_t, RGB watts
};

// A texel carries a VPL where its flux is positive in some channel: the one test every builder
// uses. A flux below the smallest normal float counts as none.
bool vplkit_vpl_has_flux(vplkit_vpl v) {
  return v.flux.x >= vplkit_FLT_MIN || v.flux.y >= vplkit_FLT_MIN || v.flux.z >= vplkit_FLT_MIN;
}

// vpl_pi<float>: the same float as vplkit_PI.
const float vplkit_vpl_pi = vplkit_PI;

// 16 * numeric_limits<float>::epsilon() = 16 * 2^-23 = 2^-19 (exact).
const float vplkit_vpl_coincidence_factor = 1.9073486328125e-6;

// Phi_t = rho_t * I_s * Omega_t (RGB), independent of the distance and of the incidence angle.
vec3 vplkit_vpl_flux(vec3 albedo, vec3 intensity, float solid_angle) {
  return vplkit_flush_denormal(albedo * intensity * solid_angle);
}

// sqrt(FLT_MIN) = 2^-63 (exact).
float vplkit_vpl_distance_sq_floor() { return 1.08420217248550443400745280086994171e-19; }

// |a - b|_inf below this means "same point" (scale-relative: coordinates of size s carry rounding
// of about eps * s, so a smaller separation has no direction).
float vplkit_vpl_coincidence_tolerance(vec3 a, vec3 b) {
  float s = max(vplkit_max_abs_component(a), vplkit_max_abs_component(b));
  return vplkit_vpl_coincidence_factor * s;
}

bool vplkit_vpl_points_coincide(vec3 a, vec3 b) {
  return vplkit_max_abs_component(b - a) <= vplkit_vpl_coincidence_tolerance(a, b);
}

// Does x lie on the plane through y with normal n_y, within the rounding of their coordinates?
// (C++ vpl_point_on_plane; `precise`: the decision is made at the rounding level, so y - x and
// the dot product must not be contracted or reordered.) A zero normal: true.
bool vplkit_vpl_point_on_plane(vec3 x, vec3 y, vec3 n_y) {
  precise vec3 w = y - x;
  precise float off_plane = abs(dot(vplkit_unit_or_zero(n_y), w));
  return !(off_plane > vplkit_vpl_coincidence_tolerance(x, y));
}

// The crease rule of every gathering strategy (C++ vpl_hit_on_own_plane): a hit whose plane
// passes through x sends x nothing. A hit without a normal cannot be tested: false.
bool vplkit_vpl_hit_on_own_plane(vec3 x, vplkit_ray_hit h) {
  return vplkit_ray_hit_has_normal(h) && vplkit_vpl_point_on_plane(x, h.position, h.normal);
}

// Geometry term of VPL y (normal n_y) at gather point x, without visibility:
//   G = cos(theta1) cos(theta2) / (pi * max(d2^2, dmin^2)), both cosines clamped at 0.
float vplkit_vpl_geometry_term(vec3 x, vec3 n_x, vec3 y, vec3 n_y, float dmin) {
  if (vplkit_vpl_points_coincide(x, y)) return 0.0;
  vec3 w = y - x;
  vec3 wd = vplkit_unit_or_zero(w);  // x -> y
  float cos2 = max(0.0, vplkit_flush_denormal(dot(vplkit_unit_or_zero(n_x), wd)));
  float cos1 = max(0.0, vplkit_flush_denormal(-dot(vplkit_unit_or_zero(n_y), wd)));
  float cos12 = vplkit_flush_denormal(cos1 * cos2);
  if (!(cos12 > 0.0)) return 0.0;
  float d2sq = max(max(dot(w, w), dmin * dmin), vplkit_vpl_distance_sq_floor());
  // d2sq = Inf (huge separation) gives 0, and so does any d2sq that leaves a denormal.
  return vplkit_flush_denormal(cos12 / (vplkit_vpl_pi * d2sq));
}

// L_t(x) = (rho_x / pi) * Phi_t * G (docs/math.md section 2, paper eq. 5 with the patch area
// restored).
vec3 vplkit_vpl_contribution(vec3 x, vec3 n_x, vec3 rho_x, vplkit_vpl v, float dmin) {
  float g = vplkit_vpl_geometry_term(x, n_x, v.position, v.normal, dmin);
  float brdf_scale = 1.0 / vplkit_vpl_pi;  // diffuse BRDF rho_x / pi
  return vplkit_flush_denormal(rho_x * brdf_scale * v.flux * g);
}

// L_t at a gather point with two normals: theta2 against the shading normal, 0 on or below the
// geometric surface.
vec3 vplkit_vpl_contribution(vplkit_gather_point gp, vplkit_vpl v, float dmin) {
  if (!vplkit_gather_point_above(gp, vplkit_unit_or_zero(v.position - gp.position))) return vec3(0.0);
  return vplkit_vpl_contribution(gp.position, vplkit_gather_point_shading_normal(gp), gp.albedo, v, dmin);
}

// Smallest cos(alpha) vplkit_vpl_patch_area divides by.
const float vplkit_vpl_min_cos_alpha = 1e-6;

// cos(alpha) at y between n_y and the direction to the light, clamped at 0; 0 when y and the light
// coincide or n_y is zero.
float vplkit_vpl_cos_alpha(vec3 light_pos, vec3 y, vec3 n_y) {
  if (vplkit_vpl_points_coincide(light_pos, y)) return 0.0;
  return max(0.0, vplkit_flush_denormal(dot(vplkit_unit_or_zero(n_y), vplkit_unit_or_zero(light_pos - y))));
}

// A_t = Omega_t d1^2 / cos(alpha), cos(alpha) raised to vplkit_vpl_min_cos_alpha. Written with
// ?: rather than max() as in the C++ (a NaN cos takes the floor there). Evaluated as
// ((Omega_t / c) d1) d1, `precise` so that the compiler keeps that order: an intermediate under- or
// overflows only where the result does, and a result below the smallest normal float is 0, as in
// the C++.
float vplkit_vpl_patch_area(float solid_angle, float d1, float cos_alpha) {
  float c = (cos_alpha > vplkit_vpl_min_cos_alpha) ? cos_alpha : vplkit_vpl_min_cos_alpha;
  precise float a = vplkit_flush_denormal(solid_angle) / c;
  precise float b = a * d1;
  precise float area = b * d1;
  return vplkit_flush_denormal(area);
}

// Radiance leaving a diffuse point y lit by the point light (no visibility):
//   L_o(y) = rho_y I_s cos(alpha) / (pi d1^2), cos(alpha) clamped at 0.
// vplkit_reflected_radiance_unit_normal takes y's normal already normalised, n_u =
// vplkit_unit_or_zero(n_y) (the presampled candidates store it, estimators/ris_candidate_pool.glsl):
// the same expressions as vplkit_reflected_radiance, which normalises first.
vec3 vplkit_reflected_radiance_unit_normal(vec3 light_pos, vec3 intensity, vec3 y, vec3 n_u, vec3 rho_y) {
  if (vplkit_vpl_points_coincide(light_pos, y)) return vec3(0.0);
  vec3 w = light_pos - y;
  float cos_a = max(0.0, vplkit_flush_denormal(dot(n_u, vplkit_unit_or_zero(w))));
  if (!(cos_a > 0.0)) return vec3(0.0);  // back-facing or zero normal
  float d1sq = max(dot(w, w), vplkit_vpl_distance_sq_floor());
  return vplkit_flush_denormal(rho_y * intensity * vplkit_flush_denormal(cos_a / (vplkit_vpl_pi * d1sq)));
}

vec3 vplkit_reflected_radiance(vec3 light_pos, vec3 intensity, vec3 y, vec3 n_y, vec3 rho_y) {
  return vplkit_reflected_radiance_unit_normal(light_pos, intensity, y, vplkit_unit_or_zero(n_y), rho_y);
}

#endif  // VPLKIT_VPL_VPL_GLSL
