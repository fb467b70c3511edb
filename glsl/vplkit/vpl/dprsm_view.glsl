// SPDX-License-Identifier: MIT
// vplkit GLSL pack: read access to a Dual Paraboloid Reflective Shadow Map, mirroring
// include/vplkit/vpl/dprsm_view.hpp (T = float). Texels are indexed as in texel_grid.glsl
// (index = face * R * R + y * R + x, 2 R^2 in all); a texel that saw no geometry has albedo 0.
//
// ACCESSORS — the including shader defines these (it chooses buffers, images and bindings):
//   vec3 vplkit_load_dprsm_position(int texel);  // world-space y_t
//   vec3 vplkit_load_dprsm_normal(int texel);    // n_t, any length
//   vec3 vplkit_load_dprsm_albedo(int texel);    // rho_t, 0 where the texel saw nothing
// A shader only has to define the accessors that the functions it calls use:
//   vplkit_dprsm_view_vpl_at and vplkit_dprsm_lookup (dprsm_lookup.glsl): all three; everything
//   else: none. (In std430 an array of vec3 has a 16-byte stride: store vec4.)
// Optional, with VPLKIT_DPRSM_PLANE_ACCESSOR defined before this file is first included:
//   vec4 vplkit_load_dprsm_plane(int texel);     // the texel's plane record (dprsm_plane.glsl),
//                                                // built for this light by dprsm_planes.comp
// vplkit_dprsm_view_plane_at then reads it (one 16-byte load) instead of computing the record from
// the three accessors and a normalisation (the default, the same value); the patch-sampled VPLs
// (dprsm_patch.glsl) read a neighbour's plane through it.
//
// The C++ view's pointers become the accessors; what is left is a small struct passed by value:
//   dprsm_view<float>{resolution, ..., light}  <-> vplkit_dprsm_view{resolution, light}
//   view.vpl_at(i)                             <-> vplkit_dprsm_view_vpl_at(view, i)  (etc.)
//   view.planes (null or not)                  <-> VPLKIT_DPRSM_PLANE_ACCESSOR (undefined or defined)
//   point_light<float>{position, intensity, frame} <-> vplkit_point_light
//   make_point_light(p, I, axis)               <-> vplkit_make_point_light(p, I, axis)
// validate() / validate_light() are host-side (they throw); upload only validated views.
#ifndef VPLKIT_VPL_DPRSM_VIEW_GLSL
#define VPLKIT_VPL_DPRSM_VIEW_GLSL

#include "vplkit/paraboloid/light_frame.glsl"
#include "vplkit/paraboloid/paraboloid.glsl"
#include "vplkit/paraboloid/texel_grid.glsl"
#include "vplkit/vpl/dprsm_plane.glsl"
#include "vplkit/vpl/vpl.glsl"

vec3 vplkit_load_dprsm_position(int texel);
vec3 vplkit_load_dprsm_normal(int texel);
vec3 vplkit_load_dprsm_albedo(int texel);
#ifdef VPLKIT_DPRSM_PLANE_ACCESSOR
vec4 vplkit_load_dprsm_plane(int texel);
#endif

struct vplkit_point_light {
  vec3 position;             // c (world); must equal frame.position
  vec3 intensity;            // I_s, RGB W/sr
  vplkit_light_frame frame;  // light space of the DPRSM
};

// A point light whose DPRSM front paraboloid looks along front_axis (the C++ default is +z).
vplkit_point_light vplkit_make_point_light(vec3 position, vec3 intensity, vec3 front_axis) {
  return vplkit_point_light(position, intensity, vplkit_make_light_frame(position, front_axis));
}

struct vplkit_dprsm_view {
  int resolution;  // R: each face is R x R
  vplkit_point_light light;
};

int vplkit_dprsm_view_texel_count(vplkit_dprsm_view view) {
  return vplkit_texel_count(view.resolution);
}

// Inside the unit disk of its face (texel_is_valid); only these carry VPLs.
bool vplkit_dprsm_view_texel_valid(vplkit_dprsm_view view, int index) {
  ivec2 xy = vplkit_texel_coords(index, view.resolution);
  return vplkit_texel_is_valid(xy.x, xy.y, view.resolution);
}

float vplkit_dprsm_view_solid_angle(vplkit_dprsm_view view, int index) {
  ivec2 xy = vplkit_texel_coords(index, view.resolution);
  return vplkit_texel_solid_angle(xy.x, xy.y, view.resolution);
}

// The VPL of texel `index` (0 <= index < texel count; not checked). flux = vpl_flux(albedo, I_s,
// solid angle), and 0 when the texel is invalid (solid angle 0), saw nothing (albedo 0), or shows a
// surface facing away from the light (vplkit_vpl_cos_alpha(c, y, n) = 0): such a point receives no
// direct light, so it reflects none (consistent with vplkit_reflected_radiance).
vplkit_vpl vplkit_dprsm_view_vpl_at(vplkit_dprsm_view view, int index) {
  vplkit_vpl v;
  v.position = vplkit_load_dprsm_position(index);
  v.normal = vplkit_load_dprsm_normal(index);
  v.flux = vplkit_vpl_flux(vplkit_load_dprsm_albedo(index), view.light.intensity,
                           vplkit_dprsm_view_solid_angle(view, index));
  if (!(vplkit_vpl_cos_alpha(view.light.position, v.position, v.normal) > 0.0)) v.flux = vec3(0.0);
  return v;
}

// The plane record of texel `index` (0 <= index < texel count; not checked): the accessor's with
// VPLKIT_DPRSM_PLANE_ACCESSOR, else vplkit_dprsm_plane_of computed from the three accessors.
vec4 vplkit_dprsm_view_plane_at(vplkit_dprsm_view view, int index) {
#ifdef VPLKIT_DPRSM_PLANE_ACCESSOR
  return vplkit_load_dprsm_plane(index);
#else
  return vplkit_dprsm_plane_of(view.light.position, vplkit_dprsm_view_texel_valid(view, index),
                               vplkit_load_dprsm_position(index), vplkit_load_dprsm_normal(index),
                               vplkit_load_dprsm_albedo(index));
#endif
}

// Texel through which the light sees world direction `dir` (any length): the valid texel that
// owns its uv (vplkit_texel_owner_from_uv), so no direction is filed under a texel without a VPL.
int vplkit_dprsm_view_texel_of_direction(vplkit_dprsm_view view, vec3 dir) {
  vplkit_paraboloid_point p =
      vplkit_paraboloid_from_direction(vplkit_light_frame_to_light(view.light.frame, dir));
  ivec2 xy = vplkit_texel_owner_from_uv(p.uv, view.resolution);
  return vplkit_texel_index(p.face, xy.x, xy.y, view.resolution);
}

// Texel through which the light sees world point p (the GBG projection; the caller still compares
// p with the texel's position to decide whether this texel saw p).
int vplkit_dprsm_view_texel_of_point(vplkit_dprsm_view view, vec3 p) {
  return vplkit_dprsm_view_texel_of_direction(view, p - view.light.position);
}

#endif  // VPLKIT_VPL_DPRSM_VIEW_GLSL
