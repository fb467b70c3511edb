// SPDX-License-Identifier: MIT
// --candidate-source tiles on the GPU: each tile's block weights, the pack's
// builders/tile_weights.glsl (vplkit::tile_block_weight), one invocation per (block, tile), tile on
// z: W_i(b) over tile i's gather points (its stratified subset, pixels[offsets[i] .. offsets[i +
// 1]); entries -1 or background skipped and not counted), written to weights[i * blocks + b] for
// cdf_build.comp. The host (render/gpu/gpu_tiles.cpp) prepends "#version 430".
layout(local_size_x = 64) in;

#include "vplkit/builders/tile_weights.glsl"

layout(std430, binding = 0) readonly buffer VrGbuffer { vec4 vr_gbuffer[]; };   // 3 per pixel
layout(std430, binding = 1) readonly buffer VrSubset { int vr_subset[]; };
layout(std430, binding = 2) readonly buffer VrOffsets { uint vr_offsets[]; };  // tiles + 1
layout(std430, binding = 3) readonly buffer VrProxies { vec4 vr_proxies[]; };  // 3 per block
layout(std430, binding = 4) writeonly buffer VrWeights { float vr_weights[]; };

uniform int u_blocks;
uniform int u_tiles;
uniform int u_pixel_count;
uniform float u_dmin;

uint vr_first;  // this invocation's tile: offsets[tile]

vplkit_gather_point vplkit_load_subset_gather_point(int i) {
  int p = vr_subset[vr_first + uint(i)];
  if (p < 0 || p >= u_pixel_count) return vplkit_unpack_gather_point(vec4(0.0), vec4(0.0), vec4(0.0));
  // Local copies: NVIDIA's compiler refuses a buffer member as a function argument (C1317).
  vec4 gp = vr_gbuffer[3 * p], gn = vr_gbuffer[3 * p + 1], ga = vr_gbuffer[3 * p + 2];
  return vplkit_unpack_gather_point(gp, gn, ga);
}

void main() {
  int b = int(gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x);
  int tile = int(gl_GlobalInvocationID.z);
  if (b >= u_blocks || tile >= u_tiles) return;
  vr_first = vr_offsets[tile];
  int count = int(vr_offsets[tile + 1] - vr_first);
  vec4 p = vr_proxies[3 * b], n = vr_proxies[3 * b + 1], f = vr_proxies[3 * b + 2];
  vr_weights[uint(tile) * uint(u_blocks) + uint(b)] = vplkit_tile_block_weight(vplkit_vpl(p.xyz, n.xyz, f.xyz), count, u_dmin);
}
