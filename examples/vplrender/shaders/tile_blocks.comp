// SPDX-License-Identifier: MIT
// --candidate-source tiles on the GPU: the frame's texel blocks, the pack's
// builders/tile_blocks.glsl (vplkit::make_tile_blocks's per-block function), one invocation per
// block of B x B texels: the block's proxy VPL (the l-weighted mean position and unit normal and
// the total flux; tile_weights.comp weighs it) and each of its texels' share l_t / L of the block's
// flux luminance (0 without a VPL; estimate_tiles.glsl draws within a block from them). The host
// (render/gpu/gpu_tiles.cpp) prepends "#version 430".
layout(local_size_x = 64) in;

#include "vplkit/builders/tile_blocks.glsl"

struct vr_surfel {
  vec4 position;
  vec4 normal;
  vec4 albedo;
};
layout(std430, binding = 0) readonly buffer VrDprsm { vr_surfel vr_dprsm[]; };
layout(std430, binding = 1) writeonly buffer VrShares { float vr_shares[]; };   // 2 R^2: per texel
layout(std430, binding = 2) writeonly buffer VrProxies { vec4 vr_proxies[]; };  // 3 per block

uniform int u_dprsm_res;
uniform vec3 u_light_pos;
uniform vec3 u_light_int;
uniform vec3 u_frame_pos;
uniform vec3 u_axis_x;
uniform vec3 u_axis_y;
uniform vec3 u_axis_z;
uniform int u_block;  // B

vec3 vplkit_load_dprsm_position(int texel) { return vr_dprsm[texel].position.xyz; }
vec3 vplkit_load_dprsm_normal(int texel) { return vr_dprsm[texel].normal.xyz; }
vec3 vplkit_load_dprsm_albedo(int texel) { return vr_dprsm[texel].albedo.xyz; }

void main() {
  vplkit_dprsm_view view = vplkit_dprsm_view(
      u_dprsm_res, vplkit_point_light(u_light_pos, u_light_int,
                                      vplkit_light_frame(u_frame_pos, u_axis_x, u_axis_y, u_axis_z)));
  vplkit_tile_block_grid g = vplkit_make_tile_block_grid(u_dprsm_res, u_block);
  // Groups spread over x and y past GL_MAX_COMPUTE_WORK_GROUP_COUNT (vplkit::gl::dispatch_linear).
  int b = int(gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x);
  if (b >= vplkit_tile_block_grid_count(g)) return;
  vplkit_tile_block_proxy p = vplkit_tile_block_proxy_of(view, g, b);
  int face = vplkit_tile_block_grid_face_of_block(g, b);
  ivec4 r = vplkit_tile_block_grid_rect(g, b);
  for (int y = r.y; y < r.w; ++y)
    for (int x = r.x; x < r.z; ++x) {
      int t = vplkit_texel_index(face, x, y, u_dprsm_res);
      vr_shares[t] = p.flux_luminance > 0.0 ? vplkit_tile_texel_share(vplkit_flux_weight_texel(view, t), p.flux_luminance) : 0.0;
    }
  vr_proxies[3 * b] = vec4(p.proxy.position, 0.0);
  vr_proxies[3 * b + 1] = vec4(p.proxy.normal, 0.0);
  vr_proxies[3 * b + 2] = vec4(p.proxy.flux, 0.0);
}
