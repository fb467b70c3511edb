// SPDX-License-Identifier: MIT
#pragma once
// Patch-sampled VPLs (docs/math.md section 11): instead of a VPL at the texel centre y_t that
// stands for the whole texel (the midpoint rule, vpl_mode::point), a point y drawn uniformly over
// the texel's uv square and carried along its light ray onto the texel's plane (through y_t,
// normal n_t), with the flux of that point's own solid angle, rho_t I_s J(uv) (2/R)^2. Averaged over
// the jitter this is exactly the integral over the texel's patch, so VPL sampling converges to the
// same continuous one-bounce integral as gathering, and MIS mixes two strategies of one estimand.
//
// A texel's domain is the set of directions it owns (texel_owner_from_uv): the part of its uv
// square inside its face's unit disk and, for a rim texel, the band parts of invalid neighbours
// it owns. A rim texel's point is drawn over the 2 x 2 texels on its outer side (texel_patch_block),
// which hold them all, and kept only where the texel owns it: so its patch is exactly the set of
// directions the lookup files under it, and no direction belongs to two patches. A plane point
// counts only where the DPRSM's own lit test (dprsm_plane_lit, that of dprsm_lookup) would count a
// surface point there; every plane point is at the plane, so that rejects only where the test falls
// back to the centre's depth (grazing) and the point lies beyond it. Everything else is rejected
// (flux 0): points outside the disk (r2 > 1, the other face's domain) or owned by another texel
// (a rim texel's block), light rays parallel to the
// plane or meeting it behind the light, texels without flux (invalid, empty, facing away from the
// light, zero normal), non-finite distances. Never NaN or Inf for a validated view.
// Assumes n_t is the texel's GEOMETRIC normal: the plane then holds the triangle the texel sees,
// and inside that triangle y is the surface point the light sees in that direction.
//
// Edge texels (docs/math.md section 11, "Hidden plane points"): where a texel straddles a crease or
// a silhouette, its plane extended over the whole texel runs behind the neighbouring surface (a
// floor's plane under the wall it meets, a column's plane behind the floor it stands on). Such a
// point is seen by no receiver the neighbour faces, so the patch would lose that flux: 7 % of
// sponza's one-bounce light at R = 128. A plane point that a neighbour's plane hides (the texels
// across the nearest edges and corner of the point's uv, dprsm_patch_point_hidden) therefore moves
// to the texel centre y_t with its flux unchanged (at_centre): the midpoint rule for that part of
// the texel, energy kept. The split is a function of uv alone, so MIS can tell a gathering hit in
// that part (mis_estimator.hpp gives it to gathering alone).
#include <vplkit/core/prefetch.hpp>
#include <vplkit/core/unit_or_zero.hpp>
#include <vplkit/core/vector.hpp>
#include <vplkit/paraboloid/paraboloid.hpp>
#include <vplkit/paraboloid/texel_grid.hpp>
#include <vplkit/vpl/dprsm_lookup.hpp>
#include <vplkit/vpl/dprsm_plane.hpp>
#include <vplkit/vpl/dprsm_view.hpp>
#include <vplkit/vpl/vpl.hpp>

#include <cmath>
#include <limits>

namespace vplkit {

// What a texel's VPL is.
enum class vpl_mode {
  point,  // the paper's: at y_t with Phi_t = rho_t I_s Omega_t; its estimand is the midpoint rule
  patch   // jittered over the texel's patch: unbiased for the continuous integral
};

// One jittered point of a texel's patch.
template <class T>
struct dprsm_patch_sample {
  vpl<T> point{};           // y (y_t when at_centre), n_t and rho_t I_s Omega(uv); flux 0 and y_t when rejected
  vec2<T> uv{T(0)};         // the jittered point in the face's uv square
  T solid_angle = T(0);     // Omega(uv) = J(uv) (2/R)^2 nx ny (the block's), 0 when rejected
  T distance = T(0);        // d1 = |y - c|
  T cos_alpha = T(0);       // between n_t and y -> c
  bool at_centre = false;   // the plane point was hidden by a neighbour: y = y_t (see above)
};

// Relative margin of the hidden test: two plane intersections of one ray from one light, each
// exact to float rounding, compared by distance.
template <class T>
constexpr T dprsm_patch_hidden_margin() {
  return T(1e-3);
}

// Is the point c + d1 w of texel t's plane (w in t's part of the map at uv) behind the plane of a
// neighbour on uv's side of t's centre? Neighbours that saw nothing, are invalid, face away from the
// light or meet w at grazing incidence (no reliable plane) hide nothing.
template <class T>
inline bool dprsm_patch_point_hidden(const dprsm_view<T>& view, int t, vec2<T> uv, vec3<T> w, T d1) {
  const int R = view.resolution;
  const ivec2 xy = texel_coords(t, R);
  const vec2<T> centre = texel_center_uv<T>(xy.x, xy.y, R);
  const int dx = uv.x < centre.x ? -1 : 1, dy = uv.y < centre.y ? -1 : 1;
  const ivec2 near[3] = {ivec2(xy.x + dx, xy.y), ivec2(xy.x, xy.y + dy), ivec2(xy.x + dx, xy.y + dy)};
  const int face = texel_face(t, R);
  for (const ivec2 q : near) {
    if (q.x < 0 || q.y < 0 || q.x >= R || q.y >= R) continue;
    // The neighbour's plane record (dprsm_plane.hpp): height > 0 exactly when it is valid, saw a
    // surface and faces the light, with n_u and h_u the values computed here before the records.
    const dprsm_plane<T> p = view.plane_at(texel_index(face, q.x, q.y, R));
    if (!dprsm_plane_can_hide(p)) continue;
    const T h_u = p.height;
    const T cos_u = -glm::dot(p.normal, w);
    if (!(cos_u > dprsm_plane_min_cos<T>())) continue;
    if (d1 * cos_u > h_u * (T(1) + dprsm_patch_hidden_margin<T>())) return true;  // d1 > d_u (1 + margin)
  }
  return false;
}

// Does the light direction towards the surface point y fall where texel t's patch moves its points
// to the centre (dprsm_patch_vpl, at_centre)? Decided from y's direction alone, as the jitter
// decides it from uv: the plane point of t in that direction, hidden by a neighbour's plane. For a
// gathering hit y in texel t (MIS, the clamp compensation).
// t must be a valid texel (texel_of_direction gives one): the plane comes from its record.
template <class T>
inline bool dprsm_patch_direction_at_centre(const dprsm_view<T>& view, int t, vec3<T> y) {
  const vec3<T> c = view.light.position;
  const vec3<T> w = unit_or_zero(y - c);
  const dprsm_plane<T> plane = view.plane_at(t);  // n = unit_or_zero(n_t), h = n . (c - y_t) where h > 0
  const vec3<T> n = plane.normal;
  const T h = std::abs(plane.height);
  const T cos_a = -glm::dot(n, w);
  if (!(h > T(0)) || !(cos_a > T(0))) return false;
  const paraboloid_point<T> q = paraboloid_from_direction(view.light.frame.to_light(w));
  return dprsm_patch_point_hidden(view, t, q.uv, w, h / cos_a);
}

// Asks for what dprsm_patch_vpl(view, t, ..) reads of texel t (its position, normal, albedo and
// plane record) and the plane records of the rows above and below (the hidden test's neighbours)
// to be brought into the cache (prefetch_read): for a caller that knows several texels before
// it evaluates them. 0 <= t < texel_count(), not checked. Changes nothing else.
template <class T>
VPLKIT_PREFETCH_INLINE void dprsm_patch_prefetch(const dprsm_view<T>& view, int t) {
  prefetch_read(view.position + t);
  prefetch_read(view.normal + t);
  prefetch_read(view.albedo + t);
  if (view.planes == nullptr) return;
  const int R = view.resolution;
  prefetch_read(view.planes + t);
  if (t >= R) prefetch_read(view.planes + (t - R));
  if (t + R < view.texel_count()) prefetch_read(view.planes + (t + R));
}

// The point of texel t (0 <= t < texel_count(), not checked) that xi in [0, 1]^2 selects.
// depth_tolerance: that of dprsm_lookup (dprsm_plane_lit decides); +inf accepts the whole plane
// patch, NaN or a negative value rejects every point.
template <class T>
inline dprsm_patch_sample<T> dprsm_patch_vpl(const dprsm_view<T>& view, int t, vec2<T> xi, T depth_tolerance) {
  dprsm_patch_sample<T> s;
  const int R = view.resolution;
  const ivec2 xy = texel_coords(t, R);
  const vec3<T> c = view.light.position;
  const vec3<T> y_t = view.position[t];
  const vec3<T> n_t = view.normal[t];
  const texel_block block = texel_patch_block(xy.x, xy.y, R);
  s.uv = texel_block_point_uv(block, R, xi);
  s.point.position = y_t;
  s.point.normal = n_t;
  s.point.flux = vec3<T>(T(0));
  if (!texel_is_valid(xy.x, xy.y, R)) return s;
  if (!(glm::dot(s.uv, s.uv) <= T(1))) return s;  // beyond the rim: the other face's directions
  if (block.nx * block.ny != 1 && texel_owner_from_uv(s.uv, R) != xy) return s;  // owned by another texel
  if (!(vpl_cos_alpha(c, y_t, n_t) > T(0))) return s;  // as vpl_at: the texel's surface is unlit
  const vec3<T> w = view.light.frame.to_world(paraboloid_to_direction(texel_face(t, R), s.uv));
  // Every point of the plane has the same height h = n . (c - y) over it; along w the plane lies
  // at the distance h / cos(alpha). cos(alpha) <= 0: the ray runs parallel to the plane or away
  // from it (it would meet it behind the light). n = unit_or_zero(n_t) and h come from the texel's
  // plane record (|height|: a texel without albedo keeps its plane; no plane: h = 0, rejected).
  const dprsm_plane<T> plane = view.plane_at(t);
  const vec3<T> n = plane.normal;
  const T h = std::abs(plane.height);
  const T cos_a = -glm::dot(n, w);
  if (!(h > T(0)) || !(cos_a > T(0))) return s;
  const T d1 = h / cos_a;
  if (!(d1 <= std::numeric_limits<T>::max())) return s;
  const vec3<T> y = c + d1 * w;
  if (!dprsm_plane_lit_unit(c, y_t, n, h, y, d1, depth_tolerance, R)) return s;  // dprsm_plane_lit, n and h as above
  s.solid_angle = texel_block_point_solid_angle(s.uv, block, R);
  s.point.flux = vpl_flux(view.albedo[t], view.light.intensity, s.solid_angle);
  if (dprsm_patch_point_hidden(view, t, s.uv, w, d1)) {  // the centre carries this point's flux
    s.at_centre = true;
    s.distance = glm::length(y_t - c);
    s.cos_alpha = vpl_cos_alpha(c, y_t, n_t);
    return s;
  }
  s.distance = d1;
  s.cos_alpha = cos_a;
  s.point.position = y;
  return s;
}

}  // namespace vplkit
