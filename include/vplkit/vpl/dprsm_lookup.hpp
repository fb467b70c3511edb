// SPDX-License-Identifier: MIT
#pragma once
// Is a surface point lit by the light, and through which DPRSM texel? The shadow-map test of the
// gathering estimator, the GBG builder and the direct light (docs/math.md section 4): y is lit
// when it does not lie behind the surface the light saw through the texel y projects into. That
// surface is taken as the texel's plane (through y_t, normal n_t), not as the centre's depth: a
// fixed depth window around |y_t - c| both lights shadowed points just behind a lit surface
// (contact shadows) and shadows lit points in front of it (a wall at a floor/wall crease).
#include <vplkit/core/gather_point.hpp>
#include <vplkit/core/normal_range.hpp>
#include <vplkit/core/unit_or_zero.hpp>
#include <vplkit/core/vector.hpp>
#include <vplkit/vpl/dprsm_view.hpp>
#include <vplkit/vpl/vpl.hpp>

#include <cmath>
#include <limits>

namespace vplkit {

struct dprsm_lookup_result {
  int texel = -1;         // flat texel index y projects into (-1 when y coincides with the light)
  bool lit = false;       // texel valid, saw a surface, and y is not behind that surface
  bool in_front = false;  // lit, and in front of that surface beyond the tolerance: the light saw
                          // another surface behind y in y's direction (dprsm_plane_side::in_front)
};

// Where a point lies against the surface a texel saw, within the lit test's tolerance.
enum class dprsm_plane_side {
  behind,   // shadowed by it
  on,       // on it: the texel's normal and albedo describe the point's surface
  in_front  // in front of it: lit (nothing the texel saw is in the way), but on another surface
};

// Below this cosine between the light ray and the texel's plane the plane test falls back to the
// centre's depth. The plane point's distance h / cos moves by h * delta / cos^2 when the normal is
// off by delta (float rounding, a plane that is not quite the triangle's); below 1e-3 (the ray
// within 0.06 degrees of the plane) that is no longer a statement about the surface.
template <class T>
constexpr T dprsm_plane_min_cos() {
  return T(1e-3);
}

// The lit test's own slack at distance d from the light, added to the caller's tolerance: half a
// texel's widest footprint (4 d / R at the paraboloid's pole), for surfaces that are not quite
// the texel's plane within one texel (a stored interpolated normal on a smoothed mesh, the next
// triangle across an edge), and 1e-4 d for the rounding of positions and of the plane product.
// A wider window lights more contact shadows, a narrower one darkens the far faces across convex
// edges: half the footprint had the smallest worst case of three widths (docs/results.md 7).
template <class T>
inline T dprsm_lookup_slack(T d, int resolution) {
  return d * (T(2) / T(resolution) + T(1e-4));
}

// Where is y, at distance d_y from the light c, against the plane (y_t, n_t) of the texel it
// projects into, within tolerance + dprsm_lookup_slack(d_y) along the light ray? Behind it is
// shadowed, as a shadow map: a point in front of the surface the light saw in that direction cannot
// be shadowed by it. Where the light ray meets the plane at d_p = h / cos(alpha) ahead of the
// light, d_y <= d_p + tol is tested as n . (y - y_t) >= -tol cos(alpha) (the two sides times
// cos > 0), and in front as n . (y - y_t) > tol cos(alpha): no division, and n . (y - y_t) measured
// directly instead of h - d_y cos, which cancels for points on the plane. Where it does not
// (cos(alpha) <= dprsm_plane_min_cos: grazing, parallel, or the plane's horizon crosses the texel;
// h <= 0: the plane faces away or holds the light; a zero normal), the centre's depth stands in:
// |d_y - |y_t - c|| <= tol is on it. NaN or negative tolerance, or a distance that is not positive
// or beyond 2^126 (float; 2^1022 in double): behind (an infinite d_y would make the slack infinite,
// and a GPU may divide by a d_y above 2^126 through its reciprocal, which it flushes to 0).
// dprsm_plane_side_of_unit takes the plane as n = unit_or_zero(n_t) and h = n . (c - y_t), the values
// of the texel's plane record (dprsm_plane.hpp: normal and |height| where height != 0): the same
// answer, without the normalisation, for callers that hold the record.
template <class T>
inline dprsm_plane_side dprsm_plane_side_of_unit(vec3<T> c, vec3<T> y_t, vec3<T> n, T h, vec3<T> y, T d_y,
                                                 T tolerance, int resolution) {
  if (!(tolerance >= T(0)) || !(d_y > T(0)) || !(d_y <= exp2i<T>(std::numeric_limits<T>::max_exponent - 2)))
    return dprsm_plane_side::behind;
  const T tol = tolerance + dprsm_lookup_slack(d_y, resolution);
  const T cos_a = -glm::dot(n, (y - c) / d_y);
  if (h > T(0) && cos_a > dprsm_plane_min_cos<T>()) {
    const T s = glm::dot(n, y - y_t), band = tol * cos_a;
    if (!(s >= -band)) return dprsm_plane_side::behind;
    return s > band ? dprsm_plane_side::in_front : dprsm_plane_side::on;
  }
  const T d_t = glm::length(y_t - c);
  if (!(d_y <= d_t + tol)) return dprsm_plane_side::behind;
  return d_y < d_t - tol ? dprsm_plane_side::in_front : dprsm_plane_side::on;
}

template <class T>
inline dprsm_plane_side dprsm_plane_side_of(vec3<T> c, vec3<T> y_t, vec3<T> n_t, vec3<T> y, T d_y, T tolerance,
                                            int resolution) {
  const vec3<T> n = unit_or_zero(n_t);
  return dprsm_plane_side_of_unit(c, y_t, n, glm::dot(n, c - y_t), y, d_y, tolerance, resolution);
}

// The lit test: y not behind the texel's plane (dprsm_plane_side_of).
template <class T>
inline bool dprsm_plane_lit(vec3<T> c, vec3<T> y_t, vec3<T> n_t, vec3<T> y, T d_y, T tolerance, int resolution) {
  return dprsm_plane_side_of(c, y_t, n_t, y, d_y, tolerance, resolution) != dprsm_plane_side::behind;
}

// dprsm_plane_lit from the plane's n and h (dprsm_plane_side_of_unit).
template <class T>
inline bool dprsm_plane_lit_unit(vec3<T> c, vec3<T> y_t, vec3<T> n, T h, vec3<T> y, T d_y, T tolerance,
                                 int resolution) {
  return dprsm_plane_side_of_unit(c, y_t, n, h, y, d_y, tolerance, resolution) != dprsm_plane_side::behind;
}

// Where the light ray towards y meets texel t's plane (y_t, n_t): the surface point the light saw
// in y's direction. y itself where the plane cannot say (the lit test's fallback cases).
template <class T>
inline vec3<T> dprsm_plane_point_towards(vec3<T> c, vec3<T> y_t, vec3<T> n_t, vec3<T> y) {
  const vec3<T> w = unit_or_zero(y - c);
  const vec3<T> n = unit_or_zero(n_t);
  const T h = glm::dot(n, c - y_t);
  const T cos_a = -glm::dot(n, w);
  if (!(h > T(0)) || !(cos_a > dprsm_plane_min_cos<T>())) return y;
  return c + (h / cos_a) * w;
}

// Did texel t (any int) see a surface: a valid texel with a nonzero albedo?
template <class T>
inline bool dprsm_texel_saw_surface(const dprsm_view<T>& view, int t) {
  if (t < 0 || t >= view.texel_count() || !view.texel_valid(t)) return false;
  const vec3<T> rho = view.albedo[t];
  return rho.x > T(0) || rho.y > T(0) || rho.z > T(0);
}

// tolerance: world-space error of y's position along the light ray (0 for exact hits; about a
// voxel diagonal or two for the paper's voxel ray marching); the lit test adds its own slack.
template <class T>
inline dprsm_lookup_result dprsm_lookup(const dprsm_view<T>& view, vec3<T> y, T tolerance) {
  dprsm_lookup_result r;
  const vec3<T> to_y = y - view.light.position;
  // Scale-first (scaled_length): glm::length's square would be a denormal below 2^-63 (float),
  // which a GPU flushes (docs/math.md, "GPU arithmetic model").
  const T d_y = scaled_length(to_y);
  if (!(d_y > T(0))) return r;
  r.texel = view.texel_of_direction(to_y);
  if (!dprsm_texel_saw_surface(view, r.texel)) return r;
  const dprsm_plane_side side = dprsm_plane_side_of(view.light.position, view.position[r.texel],
                                                    view.normal[r.texel], y, d_y, tolerance, view.resolution);
  r.lit = side != dprsm_plane_side::behind;
  r.in_front = side == dprsm_plane_side::in_front;
  return r;
}

// L_o towards x of a hit the lookup lk found lit (lk.texel = t): the light's reflection with t's
// albedo, 0 seen from the unlit side (one-sided emission), and
// - a hit whose tracer knows its surface (ray_hit_has_normal: exact rays, triangle voxels) is
//   shaded as that surface: its lit side the one facing the light (the exact method's convention),
//   the cosine from its shading normal (or its geometric one). Shaded as itself, each texel's cone
//   reflects rho_t I Omega_t, as its VPL (docs/math.md section 4.1). The texel's normal describes
//   only the surface at the texel's centre: a column's foot in a floor texel's cone, a wall a few
//   centimetres above a floor, a grazing face curving away within one texel would reflect the
//   floor's (or the centre's) cos(alpha) over an area per solid angle of the light that is
//   1 / cos(alpha_y) larger, the texel's flux counted cos(alpha_t) / cos(alpha_y) times (+1.4 %
//   of sponza's one-bounce light). Nothing asks x to face n_t as well: the far face of a convex
//   edge, within the test's slack behind the near face's plane, is seen from behind that plane
//   and is lit (asking it darkened 1.5 % of sponza's light); only a gather point inside a closed
//   solid sees the inner side of a face the plane test lit within its slack. On smoothed meshes
//   pass the shading normal: the geometric one lights what the shading normal turns away from the
//   light (+2.2 % on sponza's arches).
// - else (the voxel-entry tracer) with t's normal; a hit known only within depth_tolerance > 0
//   (up to a voxel diagonal off its surface, often in front of it) is evaluated where the light
//   saw the texel's surface in its direction (dprsm_plane_point_towards): at the point itself the
//   1/d1^2 of a light near a wall is far larger than the surface's (fireflies).
// Shared by the gathering estimator and the GBG builder's gathering accumulator, so that they agree.
template <class T>
inline vec3<T> dprsm_hit_radiance(const dprsm_view<T>& view, const dprsm_lookup_result& lk, vec3<T> x,
                                  const ray_hit<T>& hit, T depth_tolerance) {
  const int t = lk.texel;
  const vec3<T> c = view.light.position;
  const vec3<T> y = hit.position;
  if (ray_hit_has_normal(hit)) {
    const vec3<T> n_g = ray_hit_normal_towards(hit, c);
    if (!(glm::dot(unit_or_zero(n_g), unit_or_zero(x - y)) > T(0))) return vec3<T>(T(0));  // unlit side
    return reflected_radiance(c, view.light.intensity, y, ray_hit_shading_normal(hit, n_g), view.albedo[t]);
  }
  const vec3<T> n_t = view.normal[t];
  if (!(glm::dot(unit_or_zero(n_t), unit_or_zero(x - y)) > T(0))) return vec3<T>(T(0));  // from behind
  const vec3<T> at = depth_tolerance > T(0) ? dprsm_plane_point_towards(c, view.position[t], n_t, y) : y;
  return reflected_radiance(c, view.light.intensity, at, n_t, view.albedo[t]);
}

}  // namespace vplkit
