// SPDX-License-Identifier: MIT
// --candidate-source tiles on the GPU: each tile's block weights, render/cpu/tiled_candidates.hpp's
// tile_block_weight statement for statement. One invocation per (block, tile), tile on z: W_i(b) =
// the mean over tile i's gather points (its stratified subset, pixels[offsets[i] .. offsets[i +
// 1]), entries -1 or background skipped and not counted) of luminance(vpl_contribution(g, proxy_b,
// dmin)), written to weights[i * blocks + b] for cdf_build.comp; 0 for a block without flux. The
// host (render/gpu/gpu_tiles.cpp) prepends "#version 430".
layout(local_size_x = 64) in;

#include "vplkit/core/gather_point.glsl"
#include "vplkit/vpl/luminance.glsl"
#include "vplkit/vpl/vpl.glsl"

layout(std430, binding = 0) readonly buffer VrGbuffer { vec4 vr_gbuffer[]; };   // 3 per pixel
layout(std430, binding = 1) readonly buffer VrSubset { int vr_subset[]; };
layout(std430, binding = 2) readonly buffer VrOffsets { uint vr_offsets[]; };  // tiles + 1
layout(std430, binding = 3) readonly buffer VrProxies { vec4 vr_proxies[]; };  // 3 per block
layout(std430, binding = 4) writeonly buffer VrWeights { float vr_weights[]; };

uniform int u_blocks;
uniform int u_tiles;
uniform int u_pixel_count;
uniform float u_dmin;

void main() {
  int b = int(gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x);
  int tile = int(gl_GlobalInvocationID.z);
  if (b >= u_blocks || tile >= u_tiles) return;
  vplkit_vpl v = vplkit_vpl(vr_proxies[3 * b].xyz, vr_proxies[3 * b + 1].xyz, vr_proxies[3 * b + 2].xyz);
  uint first = vr_offsets[tile], end = vr_offsets[tile + 1];
  float sum = 0.0;
  int used = 0;
  if (vplkit_vpl_has_flux(v))
    for (uint k = first; k < end; ++k) {
      int p = vr_subset[k];
      if (p < 0 || p >= u_pixel_count) continue;
      // Local copies: NVIDIA's compiler refuses a buffer member as a function argument (C1317).
      vec4 gp = vr_gbuffer[3 * p], gn = vr_gbuffer[3 * p + 1], ga = vr_gbuffer[3 * p + 2];
      vplkit_gather_point g = vplkit_unpack_gather_point(gp, gn, ga);
      if (!vplkit_gather_point_valid(g)) continue;
      sum += vplkit_luminance(vplkit_vpl_contribution(g, v, u_dmin));
      ++used;
    }
  vr_weights[uint(tile) * uint(u_blocks) + uint(b)] = used > 0 ? sum * (1.0 / float(used)) : 0.0;
}
