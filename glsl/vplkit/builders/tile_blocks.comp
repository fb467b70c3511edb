// SPDX-License-Identifier: MIT
// vplkit kernel: texel blocks of tiled candidate distributions (docs/math.md 13.5), one invocation
// per block of B x B texels: the GPU side of vplkit::make_tile_blocks. Writes block b's proxy
// (vplkit_tile_block_proxy_of, builders/tile_blocks.glsl) as proxies[3 b .. 3 b + 2] = (position,
// flux luminance L_b), (unit normal, 0), (flux, 0), and every texel t of the block its share
// shares[t] = vplkit_tile_texel_share(l_t, L_b) (0 without a VPL), which
// builders/tiled_distribution.glsl reads. Interface: tile_blocks_params.h, shared with the C++
// host; the DPRSM is vec4 triplets (position, normal, albedo). Dispatch ceil(2 P^2 / LOCAL_SIZE)
// groups spread over x and y (linear group = x + y * gl_NumWorkGroups.x; the host's
// vplkit::gl::dispatch_linear), P = ceil(R / B). Precision: docs/glsl/builders.md.
#include "vplkit/builders/tile_blocks.glsl"
#include "vplkit/builders/tile_blocks_params.h"

layout(local_size_x = VPLKIT_TILE_BLOCKS_LOCAL_SIZE, local_size_y = 1, local_size_z = 1) in;

layout(std430, binding = VPLKIT_TILE_BLOCKS_BINDING_DPRSM) readonly buffer vplkit_tile_blocks_dprsm_buffer {
  vec4 vplkit_tile_blocks_dprsm[];
};
layout(std430, binding = VPLKIT_TILE_BLOCKS_BINDING_SHARES) writeonly buffer vplkit_tile_blocks_shares_buffer {
  float vplkit_tile_blocks_shares[];
};
layout(std430, binding = VPLKIT_TILE_BLOCKS_BINDING_PROXIES) writeonly buffer vplkit_tile_blocks_proxies_buffer {
  vec4 vplkit_tile_blocks_proxies[];
};
layout(std140, binding = VPLKIT_TILE_BLOCKS_BINDING_PARAMS) uniform vplkit_tile_blocks_uniforms {
  vplkit_tile_blocks_params vplkit_tile_blocks;
};

vec3 vplkit_load_dprsm_position(int texel) { return vplkit_tile_blocks_dprsm[3 * texel].xyz; }
vec3 vplkit_load_dprsm_normal(int texel) { return vplkit_tile_blocks_dprsm[3 * texel + 1].xyz; }
vec3 vplkit_load_dprsm_albedo(int texel) { return vplkit_tile_blocks_dprsm[3 * texel + 2].xyz; }

void main() {
  int R = vplkit_tile_blocks.resolution;
  vplkit_tile_block_grid g = vplkit_make_tile_block_grid(R, vplkit_tile_blocks.block);
  int b = int(gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x);
  if (b >= vplkit_tile_block_grid_count(g)) return;
  vplkit_dprsm_view view = vplkit_dprsm_view(R, vplkit_light_params_point_light(vplkit_tile_blocks.light));
  vplkit_tile_block_proxy p = vplkit_tile_block_proxy_of(view, g, b);
  int face = vplkit_tile_block_grid_face_of_block(g, b);
  ivec4 r = vplkit_tile_block_grid_rect(g, b);
  for (int y = r.y; y < r.w; ++y)
    for (int x = r.x; x < r.z; ++x) {
      int t = vplkit_texel_index(face, x, y, R);
      vplkit_tile_blocks_shares[t] =
          p.flux_luminance > 0.0 ? vplkit_tile_texel_share(vplkit_flux_weight_texel(view, t), p.flux_luminance) : 0.0;
    }
  vplkit_tile_blocks_proxies[3 * b] = vec4(p.proxy.position, p.flux_luminance);
  vplkit_tile_blocks_proxies[3 * b + 1] = vec4(p.proxy.normal, 0.0);
  vplkit_tile_blocks_proxies[3 * b + 2] = vec4(p.proxy.flux, 0.0);
}
