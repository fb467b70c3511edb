// SPDX-License-Identifier: MIT
// vplrender: the G-buffer's four targets (raster/gl_raster.cpp): world position, unit geometric
// normal, albedo, unit shading normal; alpha 1 marks a written pixel. The host prepends
// "#version 430 core".
//
// Depth = distance to the eye / u_far, written per fragment (as the DPRSM pass does). The
// projection's own depth, with znear = 1e-5 zfar, resolves only about 1e-5 z^2 / znear in float:
// millimetres in the Cornell box, so where a closed box's top face lies just behind its front face
// (the camera a little below the top) the back face won the test along the front face's top row.
// Linear depth resolves 2^-24 u_far everywhere.
#include "material.glsl"

uniform vec3 u_eye;
uniform float u_far;
in vec3 v_position;
in vec3 v_normal;
in vec2 v_uv;
flat in vec4 v_plane;
layout(location = 0) out vec4 o_position;
layout(location = 1) out vec4 o_normal;
layout(location = 2) out vec4 o_albedo;
layout(location = 3) out vec4 o_shading_normal;
void main() {
  // Geometric normal: the triangle's plane, turned to the camera's side of it (two-sided). The
  // side is decided by the plane equation at the eye, exact for the whole triangle; an
  // interpolated normal against the interpolated position can pick the wrong side.
  vec3 ng = v_plane.xyz;
  if (dot(ng, u_eye) - v_plane.w < 0.0) ng = -ng;
  // Shading normal: the interpolated vertex normal, on the geometric normal's side.
  vec3 ns = v_normal;
  float len = length(ns);
  ns = len > 0.0 ? ns / len : ng;
  if (dot(ns, ng) < 0.0) ns = -ns;
  // A flat triangle's vertex normal and its plane's normal differ by rounding only: one vector
  // for both then (the shading one, as before), so flat scenes keep their G-buffer bit for bit.
  if (dot(ns, ng) >= 1.0 - 1e-6) ng = ns;
  if (dot(ng, ng) == 0.0) ng = ns;  // a degenerate triangle has no plane
  gl_FragDepth = clamp(length(v_position - u_eye) / u_far, 0.0, 1.0);
  o_position = vec4(v_position, 1.0);
  o_normal = vec4(ng, 1.0);
  o_albedo = vec4(vr_material_albedo(v_uv), 1.0);
  o_shading_normal = vec4(ns, 1.0);
}
