// SPDX-License-Identifier: MIT
// vplrender: the DPRSM's three targets for one face (raster/gl_raster.cpp): world position, unit
// normal (turned to the light), albedo; alpha 1 marks a written texel. The host prepends
// "#version 430 core".
//
// Per fragment (= texel centre, gl_FragCoord.xy = (x + 0.5, y + 0.5)): the texel's exact light
// ray (vplkit_paraboloid_to_direction) meets the triangle's plane; that point, not the
// interpolated one, is stored, so inside a triangle the map equals a ray cast exactly up to float
// rounding. Attributes (normal, texcoord) are interpolated across the (small, tessellated)
// triangle. Depth = distance to the light / u_far.
#include "vplkit/paraboloid/paraboloid.glsl"
#include "material.glsl"

uniform vec3 u_light;
uniform vec3 u_axis_x;
uniform vec3 u_axis_y;
uniform vec3 u_axis_z;
uniform int u_face;
uniform float u_resolution;
uniform float u_far;
in vec3 v_position;
in vec3 v_normal;
in vec2 v_uv;
flat in vec4 v_plane;
layout(location = 0) out vec4 o_position;
layout(location = 1) out vec4 o_normal;
layout(location = 2) out vec4 o_albedo;
void main() {
  vec2 uv = gl_FragCoord.xy / u_resolution * 2.0 - 1.0;
  vec3 dl = vplkit_paraboloid_to_direction(u_face, uv);
  vec3 dir = u_axis_x * dl.x + u_axis_y * dl.y + u_axis_z * dl.z;
  vec3 p = v_position;
  float denom = dot(v_plane.xyz, dir);
  if (abs(denom) > 1e-6) {
    float t = (v_plane.w - dot(v_plane.xyz, u_light)) / denom;
    // The texel's ray meets the plane behind the light: this triangle cannot be what the texel
    // sees (a triangle whose interpolation wrapped across the face, see raster/tessellate.hpp).
    if (!(t > 0.0)) discard;
    p = u_light + t * dir;
  }
  vec3 n = v_normal;
  float len = length(n);
  n = len > 0.0 ? n / len : v_plane.xyz;
  if (dot(n, u_light - p) < 0.0) n = -n;  // two-sided: the lit side reflects
  gl_FragDepth = clamp(length(p - u_light) / u_far, 0.0, 1.0);
  o_position = vec4(p, 1.0);
  o_normal = vec4(n, 1.0);
  o_albedo = vec4(vr_material_albedo(v_uv), 1.0);
}
