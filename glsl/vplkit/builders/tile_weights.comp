// SPDX-License-Identifier: MIT
// vplkit kernel: the tiles' block weights (docs/math.md 13.5), one invocation per (block, tile),
// tile on z: the GPU side of vplkit::tile_block_weight over each tile's points. Runs
// vplkit_tile_block_weight (builders/tile_weights.glsl) with block b's proxy (tile_blocks.comp's
// proxies) over tile i's points pixels[offsets[i] .. offsets[i + 1]) (entries -1, outside the
// image or background are skipped and not counted) and writes weights[i * blocks + b]
// (tile-major: one cdf_build.comp distribution per tile). Interface: tile_weights_params.h,
// shared with the C++ host; the G-buffer is vec4 triplets (gather_subset.comp's layout). Dispatch
// ceil(blocks / LOCAL_SIZE) groups spread over x and y and the tiles on z (the host's
// vplkit::gl::dispatch_linear); under llvmpipe's loop budget (docs/glsl.md) keep each tile's points
// below ~65000. Precision: docs/glsl/builders.md.
#include "vplkit/builders/tile_weights.glsl"
#include "vplkit/builders/tile_weights_params.h"

layout(local_size_x = VPLKIT_TILE_WEIGHTS_LOCAL_SIZE, local_size_y = 1, local_size_z = 1) in;

layout(std430, binding = VPLKIT_TILE_WEIGHTS_BINDING_GBUFFER) readonly buffer vplkit_tile_weights_gbuffer_buffer {
  vec4 vplkit_tile_weights_gbuffer[];
};
layout(std430, binding = VPLKIT_TILE_WEIGHTS_BINDING_SUBSET) readonly buffer vplkit_tile_weights_subset_buffer {
  int vplkit_tile_weights_subset[];
};
layout(std430, binding = VPLKIT_TILE_WEIGHTS_BINDING_OFFSETS) readonly buffer vplkit_tile_weights_offsets_buffer {
  uint vplkit_tile_weights_offsets[];
};
layout(std430, binding = VPLKIT_TILE_WEIGHTS_BINDING_PROXIES) readonly buffer vplkit_tile_weights_proxies_buffer {
  vec4 vplkit_tile_weights_proxies[];
};
layout(std430, binding = VPLKIT_TILE_WEIGHTS_BINDING_WEIGHTS) writeonly buffer vplkit_tile_weights_out_buffer {
  float vplkit_tile_weights_out[];
};
layout(std140, binding = VPLKIT_TILE_WEIGHTS_BINDING_PARAMS) uniform vplkit_tile_weights_uniforms {
  vplkit_tile_weights_params vplkit_tile_weights;
};

uint vplkit_tile_weights_first;  // this invocation's tile: offsets[tile]

vplkit_gather_point vplkit_load_subset_gather_point(int i) {
  int p = vplkit_tile_weights_subset[vplkit_tile_weights_first + uint(i)];
  if (p < 0 || p >= vplkit_tile_weights.pixel_count) return vplkit_unpack_gather_point(vec4(0.0), vec4(0.0), vec4(0.0));
  // Local copies: NVIDIA's compiler refuses a buffer member as a function argument (C1317).
  vec4 gp = vplkit_tile_weights_gbuffer[3 * p], gn = vplkit_tile_weights_gbuffer[3 * p + 1],
       ga = vplkit_tile_weights_gbuffer[3 * p + 2];
  return vplkit_unpack_gather_point(gp, gn, ga);
}

void main() {
  int b = int(gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x);
  int tile = int(gl_GlobalInvocationID.z);
  if (b >= vplkit_tile_weights.blocks || tile >= vplkit_tile_weights.tiles) return;
  vplkit_tile_weights_first = vplkit_tile_weights_offsets[tile];
  int count = int(vplkit_tile_weights_offsets[tile + 1] - vplkit_tile_weights_first);
  vec4 p = vplkit_tile_weights_proxies[3 * b], n = vplkit_tile_weights_proxies[3 * b + 1],
       f = vplkit_tile_weights_proxies[3 * b + 2];
  vplkit_tile_weights_out[uint(tile) * uint(vplkit_tile_weights.blocks) + uint(b)] =
      vplkit_tile_block_weight(vplkit_vpl(p.xyz, n.xyz, f.xyz), count, vplkit_tile_weights.dmin);
}
