// SPDX-License-Identifier: MIT
// vplrender: one face of the DPRSM (raster/gl_raster.cpp, once per face); dprsm.frag writes the
// targets. The host prepends "#version 430 core".
//
// Paraboloid projection in the vertex shader, homogeneous form: with d the unit light-space
// direction and z' = d.z on the front face, -d.z on the back face, clip = (d.x, d.y, 0, 1 + z')
// divides to uv = d.xy / (1 + z') = vplkit_paraboloid_from_direction's uv on that face. The other
// hemisphere is cut by gl_ClipDistance[0] = z' + m >= 0, so a triangle straddling the rim is
// clipped just past it (w ~ 1 there, finite everywhere it is kept; the back pole, where w = 0, is
// always clipped). The margin m = 4/R (two rim texels in angle) exists because the clipped edge is
// a straight chord in uv between two points of the circle: clipping exactly at z' = 0 left the
// valid texels between chord and rim empty (measured: 1.7% of the texels at R = 64, all with
// r2 > 0.98). Texels outside the unit disk are cleared after read-back. Depth is written per
// fragment.
#include "raster_inputs.glsl"

uniform vec3 u_light;
uniform vec3 u_axis_x;
uniform vec3 u_axis_y;
uniform vec3 u_axis_z;
uniform int u_face;
uniform float u_rim_margin;
out vec3 v_position;
out vec3 v_normal;
out vec2 v_uv;
flat out vec4 v_plane;
out float gl_ClipDistance[1];
void main() {
  vec3 q = a_position - u_light;
  vec3 l = vec3(dot(q, u_axis_x), dot(q, u_axis_y), dot(q, u_axis_z));
  float len = length(l);
  vec3 d = len > 0.0 ? l / len : vec3(0.0, 0.0, 1.0);
  float z = u_face == 0 ? d.z : -d.z;
  gl_ClipDistance[0] = z + u_rim_margin;
  gl_Position = vec4(d.x, d.y, 0.0, 1.0 + z);
  v_position = a_position;
  v_normal = a_normal;
  v_uv = a_uv;
  v_plane = a_plane;
}
