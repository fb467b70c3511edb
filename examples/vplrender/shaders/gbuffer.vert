// SPDX-License-Identifier: MIT
// vplrender: the camera's G-buffer pass (raster/gl_raster.cpp), the scene as it is through the
// camera's view-projection; gbuffer.frag writes the targets. The host prepends "#version 430 core".
#include "raster_inputs.glsl"

uniform mat4 u_view_projection;
out vec3 v_position;
out vec3 v_normal;
out vec2 v_uv;
flat out vec4 v_plane;
void main() {
  v_position = a_position;
  v_normal = a_normal;
  v_uv = a_uv;
  v_plane = a_plane;
  gl_Position = u_view_projection * vec4(a_position, 1.0);
}
