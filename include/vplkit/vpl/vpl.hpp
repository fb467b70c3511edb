// SPDX-License-Identifier: MIT
#pragma once
// VPL model (docs/math.md sections 2 and 5): flux of a DPRSM texel, contribution of a VPL to a
// gather point, radiance reflected by a directly lit diffuse point. No visibility here: callers
// multiply by V.
//
// Robustness contract (every function below): never NaN or Inf for finite inputs, and 0 (not NaN)
// when a position or normal has a NaN coordinate.
//  - Normals may have any length; they are normalised with unit_or_zero, and a zero normal
//    gives a zero result (an unoriented point neither emits nor receives).
//  - Two points closer than vpl_coincidence_tolerance (16 eps times their largest coordinate)
//    are the same point as far as their float coordinates can tell: the direction between them
//    is rounding noise, so the result is 0 (this covers x == y with dmin = 0).
//  - Squared distances are raised to at least vpl_distance_sq_floor = sqrt(smallest normal)
//    (2^-63 in float, 2^-511 in double), so 1 / (pi d^2) <= 2.9e18 in float: the result is
//    finite whenever |flux| * albedo (resp. |I| * albedo) stays below ~1e19 (float).
//  - The normal-range contract (docs/math.md, "GPU arithmetic model"): a result, cosine or
//    flux below the smallest normal T is 0, as a GPU that flushes denormals computes it, so a
//    flux, a zero/non-zero decision or a patch area is the same on every device.
#include <vplkit/core/gather_point.hpp>
#include <vplkit/core/normal_range.hpp>
#include <vplkit/core/unit_or_zero.hpp>
#include <vplkit/core/vector.hpp>

#include <cmath>
#include <limits>

namespace vplkit {

template <class T>
struct vpl {
  vec3<T> position;  // y_t
  vec3<T> normal;    // n_t (any length; normalised where used)
  vec3<T> flux;      // Phi_t, RGB watts
};

// A texel carries a VPL where its flux is positive in some channel (albedo and intensity are
// >= 0, so no channel is negative): the one test every builder uses.
// A flux below the smallest normal T counts as none (a GPU may read it as 0).
template <class T>
inline bool vpl_has_flux(const vpl<T>& v) {
  constexpr T lo = std::numeric_limits<T>::min();
  return v.flux.x >= lo || v.flux.y >= lo || v.flux.z >= lo;
}

template <class T>
inline constexpr T vpl_pi = T(3.14159265358979323846);

// Phi_t = rho_t * I_s * Omega_t (RGB). Independent of the distance and of the incidence angle:
// the patch seen through the texel grows as d1^2 / cos(alpha) while its irradiance falls as
// cos(alpha) / d1^2 (docs/math.md section 2; the paper's eq. 1-3 omit Omega_t).
template <class T>
inline vec3<T> vpl_flux(vec3<T> albedo, vec3<T> intensity, T solid_angle) {
  return flush_denormal(albedo * intensity * solid_angle);
}

template <class T>
inline T vpl_distance_sq_floor() {
  // sqrt(min()) exactly: min() = 2^(min_exponent - 1) is an even power of 2 (2^-63 for float).
  return exp2i<T>((std::numeric_limits<T>::min_exponent - 1) / 2);
}

// |a - b|_inf below this means "same point". Scale-relative on purpose: coordinates of size s
// carry rounding of about eps * s, so a smaller separation has no direction.
template <class T>
inline T vpl_coincidence_tolerance(vec3<T> a, vec3<T> b) {
  const T s = glm::max(max_abs_component(a), max_abs_component(b));
  return T(16) * std::numeric_limits<T>::epsilon() * s;
}

// True when a and b cannot be told apart. (NaN coordinates are not detected here; the callers
// below return 0 for them because unit_or_zero turns a NaN direction into 0.)
template <class T>
inline bool vpl_points_coincide(vec3<T> a, vec3<T> b) {
  return max_abs_component(b - a) <= vpl_coincidence_tolerance(a, b);
}

// Does x lie on the plane through y with normal n_y, within the rounding of their coordinates
// (|n_y . (y - x)| <= vpl_coincidence_tolerance(x, y), n_y normalised)? Then x sees that plane
// edge-on: each of its points has cos(theta1) = 0 at x, and a ray leaving x meets it only at
// distance ~0 (where a lifted ray origin crosses it) or grazing it. A zero or NaN normal: true
// (callers ask ray_hit_has_normal first, see vpl_hit_on_own_plane).
template <class T>
inline bool vpl_point_on_plane(vec3<T> x, vec3<T> y, vec3<T> n_y) {
  const T off_plane = detail::abs_of(glm::dot(unit_or_zero(n_y), y - x));
  return !(off_plane > vpl_coincidence_tolerance(x, y));
}

// The crease rule of every gathering strategy (docs/math.md, "The clamp's compensation", "A hit
// on x's own plane sends nothing"): does the ray leaving x hit a surface whose plane passes
// through x (a crease through x, coincident surfaces)? Such a hit sends x nothing: no point of
// that surface other than x itself lies in x's view (cos(theta1) = 0 for the VPL strategy, and
// the ray-casting function, first hit at t > 0, passes it), yet a tracer that lifts its origin
// meets it at distance ~0 and would add its full L_o. Gathering, MIS's gathering strategy, the
// clamp's compensation and the GBG weights skip such hits. A hit without a normal (the paper's
// voxel-entry points) cannot be tested: false.
template <class T>
inline bool vpl_hit_on_own_plane(vec3<T> x, const ray_hit<T>& h) {
  return ray_hit_has_normal(h) && vpl_point_on_plane(x, h.position, h.normal);
}

// Geometry term of VPL t at gather point x, without visibility:
//   G = cos(theta1) cos(theta2) / (pi * max(d2^2, dmin^2)),
// theta1 at the VPL between n_t and x - y_t, theta2 at x between n_x and y_t - x, both clamped
// at 0 (back-facing -> 0). dmin = 0 disables the VPL clamp (the result stays finite, see above).
template <class T>
inline T vpl_geometry_term(vec3<T> x, vec3<T> n_x, vec3<T> y, vec3<T> n_y, T dmin) {
  if (vpl_points_coincide(x, y)) return T(0);
  const vec3<T> w = y - x;
  const vec3<T> wd = unit_or_zero(w);  // x -> y
  const T cos2 = glm::max(T(0), flush_denormal(glm::dot(unit_or_zero(n_x), wd)));
  const T cos1 = glm::max(T(0), flush_denormal(-glm::dot(unit_or_zero(n_y), wd)));
  // Early out also catches NaN coordinates: unit_or_zero maps them to 0, so the cosines are 0
  // and d2sq (possibly NaN) is never divided into.
  const T cos12 = flush_denormal(cos1 * cos2);
  if (!(cos12 > T(0))) return T(0);
  const T d2sq = glm::max(glm::max(glm::dot(w, w), dmin * dmin), vpl_distance_sq_floor<T>());
  // d2sq = Inf (huge separation) gives 0, and so does any d2sq that leaves a denormal.
  return flush_denormal(cos12 / (vpl_pi<T> * d2sq));
}

// L_t(x) = (rho_x / pi) * Phi_t * G (docs/math.md section 2, paper eq. 5 with the patch area
// restored).
template <class T>
inline vec3<T> vpl_contribution(vec3<T> x, vec3<T> n_x, vec3<T> rho_x, const vpl<T>& v, T dmin) {
  const T g = vpl_geometry_term(x, n_x, v.position, v.normal, dmin);
  const T brdf_scale = T(1) / vpl_pi<T>;  // diffuse BRDF rho_x / pi
  return flush_denormal(rho_x * brdf_scale * v.flux * g);
}

// L_t at a gather point with two normals: theta2 against the shading normal, and 0 where y_t lies
// on or below the geometric surface (docs/math.md section 12).
template <class T>
inline vec3<T> vpl_contribution(const gather_point<T>& gp, const vpl<T>& v, T dmin) {
  if (!gather_point_above(gp, unit_or_zero(v.position - gp.position))) return vec3<T>(T(0));
  return vpl_contribution(gp.position, gather_point_shading_normal(gp), gp.albedo, v, dmin);
}

// Smallest cos(alpha) vpl_patch_area divides by: a texel seen at grazing incidence maps to a
// long but finite patch (area <= 1e6 Omega_t d1^2).
template <class T>
inline constexpr T vpl_min_cos_alpha = T(1e-6);

// cos(alpha) at y between n_y and the direction to the light, clamped at 0; 0 when y and the
// light coincide or n_y is zero.
template <class T>
inline T vpl_cos_alpha(vec3<T> light_pos, vec3<T> y, vec3<T> n_y) {
  if (vpl_points_coincide(light_pos, y)) return T(0);
  return glm::max(T(0), flush_denormal(glm::dot(unit_or_zero(n_y), unit_or_zero(light_pos - y))));
}

// Area of the surface patch seen through a texel: A_t = Omega_t d1^2 / cos(alpha), with
// cos(alpha) raised to vpl_min_cos_alpha (also when it is <= 0 or NaN). Needed to turn the VPL pmf
// into a solid-angle pdf at the gather point: p2 = p(t) d2^2 / (A_t cos(theta1)) (docs/math.md
// section 5).
// Evaluated as ((Omega_t / c) d1) d1: an intermediate under- or overflows only where the result
// does (Omega_t / c >= Omega_t; d1 < 1 shrinks, d1 > 1 grows monotonically towards the result),
// and a result below the smallest normal T is 0: the same area, 0 included, on a GPU that flushes
// denormal intermediates (vpl_pdf_solid_angle turns a zero area into an infinite density).
template <class T>
inline T vpl_patch_area(T solid_angle, T d1, T cos_alpha) {
  // written so that a NaN cos_alpha also takes the floor
  const T c = (cos_alpha > vpl_min_cos_alpha<T>) ? cos_alpha : vpl_min_cos_alpha<T>;
  return flush_denormal(((flush_denormal(solid_angle) / c) * d1) * d1);
}

// Radiance leaving a diffuse point y lit by the point light (no visibility):
//   L_o(y) = rho_y I_s cos(alpha) / (pi d1^2),
// cos(alpha) between n_y and c - y clamped at 0. The gathering integrand of docs/math.md section 5
// is f(omega) = (rho_x / pi) L_o(y) cos(theta2). Same robustness rules as vpl_contribution
// (coincident y and c -> 0, d1^2 raised to vpl_distance_sq_floor).
// reflected_radiance_unit_normal takes y's normal already normalised, n_u = unit_or_zero(n_y) (a
// caller that evaluates many points of one texel takes it from the texel's plane record,
// dprsm_plane.hpp, instead of repeating the normalisation): the same bits as reflected_radiance.
template <class T>
inline vec3<T> reflected_radiance_unit_normal(vec3<T> light_pos, vec3<T> intensity, vec3<T> y, vec3<T> n_u,
                                              vec3<T> rho_y) {
  if (vpl_points_coincide(light_pos, y)) return vec3<T>(T(0));
  const vec3<T> w = light_pos - y;
  const T cos_a = glm::max(T(0), flush_denormal(glm::dot(n_u, unit_or_zero(w))));
  if (!(cos_a > T(0))) return vec3<T>(T(0));  // back-facing, zero normal or NaN coordinates
  const T d1sq = glm::max(glm::dot(w, w), vpl_distance_sq_floor<T>());
  return flush_denormal(rho_y * intensity * flush_denormal(cos_a / (vpl_pi<T> * d1sq)));
}

template <class T>
inline vec3<T> reflected_radiance(vec3<T> light_pos, vec3<T> intensity, vec3<T> y, vec3<T> n_y,
                                  vec3<T> rho_y) {
  return reflected_radiance_unit_normal(light_pos, intensity, y, unit_or_zero(n_y), rho_y);
}

}  // namespace vplkit
