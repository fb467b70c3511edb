// SPDX-License-Identifier: MIT
// The rasteriser's float render targets (raster/gl_raster.cpp) copied into the surfel layout every
// GPU kernel reads (raster/gpu_scene_buffers.hpp: three vec4 per surfel) on the GPU: the same bytes
// as the host's read-back followed by upload_surfels, without the round trip. One invocation per
// texel of the target; the host prepends "#version 430".
//  - u_kind 0, the G-buffer: row y of the image (0 = top) is GL's row height - 1 - y; the fourth
//    target (the shading normal) goes into the three w.
//  - u_kind 1, one face of the DPRSM: GL's rows as they are (face * R^2 + y R + x, y along v);
//    texels outside the face's unit disk stay empty (vplkit_texel_is_valid), w = 0.
// A target contributes a texel only where its alpha is > 0 (a fragment was written there), else 0:
// the read-back's rule.
layout(local_size_x = 64) in;

#include "vplkit/paraboloid/texel_grid.glsl"

layout(binding = 0) uniform sampler2D u_target_position;
layout(binding = 1) uniform sampler2D u_target_normal;
layout(binding = 2) uniform sampler2D u_target_albedo;
layout(binding = 3) uniform sampler2D u_target_shading_normal;  // G-buffer only

layout(std430, binding = 0) writeonly buffer VrSurfels { vec4 vr_surfels[]; };

uniform int u_width;   // of the target (R for a DPRSM face)
uniform int u_height;
uniform int u_kind;    // 0: G-buffer, 1: a DPRSM face
uniform uint u_first;  // the surfel of texel (0, 0): 0, or face * R^2

vec3 vr_written(sampler2D target, ivec2 texel) {
  vec4 v = texelFetch(target, texel, 0);
  return v.w > 0.0 ? v.xyz : vec3(0.0);
}

void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= uint(u_width) * uint(u_height)) return;
  int x = int(i % uint(u_width));
  int y = int(i / uint(u_width));
  ivec2 texel = ivec2(x, u_kind == 0 ? u_height - 1 - y : y);
  vec3 p = vr_written(u_target_position, texel);
  vec3 n = vr_written(u_target_normal, texel);
  vec3 a = vr_written(u_target_albedo, texel);
  vec3 ns = vec3(0.0);
  if (u_kind == 0) {
    ns = vr_written(u_target_shading_normal, texel);
  } else if (!vplkit_texel_is_valid(x, y, u_width)) {
    p = vec3(0.0);
    n = vec3(0.0);
    a = vec3(0.0);
  }
  uint s = 3u * (u_first + i);
  vr_surfels[s] = vec4(p, ns.x);
  vr_surfels[s + 1u] = vec4(n, ns.y);
  vr_surfels[s + 2u] = vec4(a, ns.z);
}
