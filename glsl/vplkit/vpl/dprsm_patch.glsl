// SPDX-License-Identifier: MIT
// vplkit GLSL pack: patch-sampled VPLs (docs/math.md section 11); mirrors
// include/vplkit/vpl/dprsm_patch.hpp (T = float) line for line. A point y drawn uniformly over a
// texel's uv square (a rim texel's: the 2 x 2 texels on its outer side), carried along its light
// ray onto the texel's plane (through y_t, normal n_t), with the flux of its own solid angle
// rho_t I_s J(uv) (2/R)^2 nx ny: unbiased for the texel's part of the continuous one-bounce
// integral. Rejected (flux 0): uv outside the face's disk or not owned by the texel
// (vplkit_texel_owner_from_uv), rays parallel to the plane or meeting it behind the light, texels
// without flux, points that the lit test of vplkit_dprsm_lookup (vplkit_dprsm_plane_lit) rejects.
// Assumes n_t is the texel's geometric normal. A plane point hidden by a neighbour's plane (an edge
// texel's plane run past a crease or behind a silhouette) moves to the texel centre with its flux
// (at_centre; the C++ header says why).
//
// ACCESSORS used (declared in dprsm_view.glsl, defined by the including shader): position, normal
// and albedo; the plane record too with VPLKIT_DPRSM_PLANE_ACCESSOR (then a neighbour costs one
// vec4 load instead of three and a normalisation).
#ifndef VPLKIT_VPL_DPRSM_PATCH_GLSL
#define VPLKIT_VPL_DPRSM_PATCH_GLSL

#include "vplkit/core/constants.glsl"
#include "vplkit/core/unit_or_zero.glsl"
#include "vplkit/paraboloid/paraboloid.glsl"
#include "vplkit/paraboloid/texel_grid.glsl"
#include "vplkit/vpl/dprsm_lookup.glsl"
#include "vplkit/vpl/dprsm_plane.glsl"
#include "vplkit/vpl/dprsm_view.glsl"
#include "vplkit/vpl/vpl.glsl"

// C++ enum class vpl_mode { point, patch }.
const int vplkit_vpl_point = 0;
const int vplkit_vpl_patch = 1;

// One jittered point of a texel's patch.
struct vplkit_dprsm_patch_sample {
  vplkit_vpl point;    // y (y_t when at_centre), n_t and rho_t I_s Omega(uv); flux 0 and y_t when rejected
  vec2 uv;             // the jittered point in the face's uv square
  float solid_angle;   // Omega(uv) = J(uv) (2/R)^2 nx ny (the block's), 0 when rejected
  float distance;      // d1 = |y - c|
  float cos_alpha;     // between n_t and y -> c
  bool at_centre;      // the plane point was hidden by a neighbour: y = y_t
};

// Relative margin of the hidden test (two plane intersections of one ray, compared by distance).
const float vplkit_dprsm_patch_hidden_margin = 1e-3;

// Is the point c + d1 w of texel t's plane (w in t's part of the map at uv) behind the plane of a
// neighbour on uv's side of t's centre? Neighbours without a surface, invalid, facing away or met
// at grazing incidence hide nothing.
bool vplkit_dprsm_patch_point_hidden(vplkit_dprsm_view view, int t, vec2 uv, vec3 w, float d1) {
  int R = view.resolution;
  ivec2 xy = vplkit_texel_coords(t, R);
  vec2 centre = vplkit_texel_center_uv(xy.x, xy.y, R);
  int dx = uv.x < centre.x ? -1 : 1, dy = uv.y < centre.y ? -1 : 1;
  ivec2 near[3] = ivec2[3](ivec2(xy.x + dx, xy.y), ivec2(xy.x, xy.y + dy), ivec2(xy.x + dx, xy.y + dy));
  int face = vplkit_texel_face(t, R);
  for (int k = 0; k < 3; ++k) {
    ivec2 q = near[k];
    if (q.x < 0 || q.y < 0 || q.x >= R || q.y >= R) continue;
    // The neighbour's plane record (dprsm_plane.glsl): w > 0 exactly when it is valid, saw a
    // surface and faces the light; one vec4 load with VPLKIT_DPRSM_PLANE_ACCESSOR.
    vec4 p = vplkit_dprsm_view_plane_at(view, vplkit_texel_index(face, q.x, q.y, R));
    if (!vplkit_dprsm_plane_can_hide(p)) continue;
    float h_u = p.w;
    float cos_u = -dot(p.xyz, w);
    if (!(cos_u > vplkit_dprsm_plane_min_cos)) continue;
    precise float lhs = d1 * cos_u;
    precise float rhs = h_u * (1.0 + vplkit_dprsm_patch_hidden_margin);
    if (lhs > rhs) return true;  // d1 > d_u (1 + margin)
  }
  return false;
}

// Does the light direction towards the surface point y fall where texel t's patch moves its points
// to the centre (vplkit_dprsm_patch_vpl, at_centre)? Decided from y's direction alone (MIS, the
// clamp compensation).
// t must be a valid texel (texel_of_direction gives one): the plane comes from its record.
bool vplkit_dprsm_patch_direction_at_centre(vplkit_dprsm_view view, int t, vec3 y) {
  vec3 c = view.light.position;
  vec3 w = vplkit_unit_or_zero(y - c);
  vec4 plane = vplkit_dprsm_view_plane_at(view, t);
  vec3 n = plane.xyz;
  float h = abs(plane.w);
  float cos_a = -dot(n, w);
  if (!(h > 0.0) || !(cos_a > 0.0)) return false;
  vplkit_paraboloid_point q = vplkit_paraboloid_from_direction(vplkit_light_frame_to_light(view.light.frame, w));
  return vplkit_dprsm_patch_point_hidden(view, t, q.uv, w, h / cos_a);
}

// The point of texel t (0 <= t < texel count, not checked) that xi in [0, 1]^2 selects;
// depth_tolerance that of vplkit_dprsm_lookup (+inf: the whole patch).
vplkit_dprsm_patch_sample vplkit_dprsm_patch_vpl(vplkit_dprsm_view view, int t, vec2 xi, float depth_tolerance) {
  int R = view.resolution;
  ivec2 xy = vplkit_texel_coords(t, R);
  vec3 c = view.light.position;
  vec3 y_t = vplkit_load_dprsm_position(t);
  vec3 n_t = vplkit_load_dprsm_normal(t);
  vplkit_texel_block block = vplkit_texel_patch_block(xy.x, xy.y, R);
  vplkit_dprsm_patch_sample s = vplkit_dprsm_patch_sample(vplkit_vpl(y_t, n_t, vec3(0.0)),
                                                          vplkit_texel_block_point_uv(block, R, xi), 0.0, 0.0, 0.0, false);
  if (!vplkit_texel_is_valid(xy.x, xy.y, R)) return s;
  if (!(dot(s.uv, s.uv) <= 1.0)) return s;  // beyond the rim: the other face's directions
  if (block.nx * block.ny != 1 && vplkit_texel_owner_from_uv(s.uv, R) != xy) return s;  // owned by another texel
  if (!(vplkit_vpl_cos_alpha(c, y_t, n_t) > 0.0)) return s;  // as vpl_at: the texel's surface is unlit
  vec3 w = vplkit_light_frame_to_world(view.light.frame,
                                       vplkit_paraboloid_to_direction(vplkit_texel_face(t, R), s.uv));
  // The plane's height over the light is the same at every point; along w it lies at h / cos(alpha).
  // n and h from the texel's plane record (|w|: a texel without albedo keeps its plane).
  vec4 plane = vplkit_dprsm_view_plane_at(view, t);
  vec3 n = plane.xyz;
  float h = abs(plane.w);
  float cos_a = -dot(n, w);
  if (!(h > 0.0) || !(cos_a > 0.0)) return s;
  float d1 = h / cos_a;
  if (!(d1 <= vplkit_FLT_MAX)) return s;
  vec3 y = c + d1 * w;
  if (!vplkit_dprsm_plane_lit(c, y_t, n_t, y, d1, depth_tolerance, R)) return s;
  s.solid_angle = vplkit_texel_block_point_solid_angle(s.uv, block, R);
  s.point.flux = vplkit_vpl_flux(vplkit_load_dprsm_albedo(t), view.light.intensity, s.solid_angle);
  if (vplkit_dprsm_patch_point_hidden(view, t, s.uv, w, d1)) {  // the centre carries this point's flux
    s.at_centre = true;
    s.distance = length(y_t - c);
    s.cos_alpha = vplkit_vpl_cos_alpha(c, y_t, n_t);
    return s;
  }
  s.distance = d1;
  s.cos_alpha = cos_a;
  s.point.position = y;
  return s;
}

#endif  // VPLKIT_VPL_DPRSM_PATCH_GLSL
