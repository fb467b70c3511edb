// SPDX-License-Identifier: MIT
// vplrender's estimate kernels with --candidate-source tiles (VR_RIS_TILES; ris-mis): tile d's
// candidate distribution, render/cpu/tiled_candidates.hpp's tiled_distribution. Mixture record d
// (estimate_params.h's vr_mixture_record, written by render/gpu/gpu_tiles.cpp) is the tile's
// defensive mixture: its learned part the CDF over the DPRSM's texel blocks (id VR_TILE_SLOT + d,
// in the tile buffer at VR_RIS_BINDING_TILES), its fallback the flux build's (in the CDF data, as
// every mixture's). A learned draw picks a block from the CDF, then a texel of the block by the
// shares tile_blocks.comp wrote; the learned pmf of texel t is P(block of t) share_t. Included by
// estimate_distributions.glsl, which routes vplkit_load_cdf / _guide for ids >= VR_TILE_SLOT here
// and makes these the estimators' hooks.
//
// Layout of the tile buffer (uints, offsets in vr_params.ris): tile d's CDF at d (Nb + 1), Nb =
// 2 P^2 blocks, P = ceil(R / B); its guide at tile_guide_base + d (m + 1), m =
// vplkit_discrete_guide_size(Nb); the shares at tile_share_base + t.
#ifndef VPLRENDER_ESTIMATE_TILES_GLSL
#define VPLRENDER_ESTIMATE_TILES_GLSL

#include "estimate_ris_params.h"
#include "vplkit/distribution/defensive_mixture.glsl"
#include "vplkit/paraboloid/texel_grid.glsl"

layout(std430, binding = VR_RIS_BINDING_TILES) restrict readonly buffer VrTiles { uint vr_tiles[]; };

int vr_tile_per_side() { return (vr_params.resolution + vr_params.ris.tile_block - 1) / vr_params.ris.tile_block; }
uint vr_tile_blocks() {
  uint p = uint(vr_tile_per_side());
  return 2u * p * p;
}
float vr_tile_load_cdf(uint tile, uint i) { return uintBitsToFloat(vr_tiles[tile * (vr_tile_blocks() + 1u) + i]); }
uint vr_tile_load_guide(uint tile, uint j) {
  return vr_tiles[vr_params.ris.tile_guide_base + tile * (vplkit_discrete_guide_size(vr_tile_blocks()) + 1u) + j];
}
float vr_tile_share(uint t) { return uintBitsToFloat(vr_tiles[vr_params.ris.tile_share_base + t]); }

// C++ tile_blocks::block_of.
uint vr_tile_block_of(uint t) {
  int R = vr_params.resolution, B = vr_params.ris.tile_block, P = vr_tile_per_side();
  ivec2 xy = vplkit_texel_coords(int(t), R);
  return uint((vplkit_texel_face(int(t), R) * P + xy.y / B) * P + xy.x / B);
}

// C++ tile_blocks::texel_in_block: the first texel of block b (row-major, positive share) whose
// running share times w exceeds d, else the block's last such texel. precise: w c is compared
// as the C++ rounds it, not fused into the comparison's subtraction.
uint vr_tile_texel_in_block(uint b, float d, float w) {
  if (!(w > 0.0)) {
    d = 0.0;
    w = 1.0;
  }
  int R = vr_params.resolution, B = vr_params.ris.tile_block, P = vr_tile_per_side();
  int face = int(b) / (P * P), in_face = int(b) % (P * P);
  int x0 = (in_face % P) * B, y0 = (in_face / P) * B;
  int x1 = min(x0 + B, R), y1 = min(y0 + B, R);
  float c = 0.0;
  uint last = 0u;
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) {
      uint t = uint(vplkit_texel_index(face, x, y, R));
      float s = vr_tile_share(t);
      if (!(s > 0.0)) continue;
      c += s;
      precise float bound = w * c;
      if (d < bound) return t;
      last = t;
    }
  return last;
}

// C++ tiled_distribution::pmf.
float vr_tiled_pmf(vplkit_defensive_mixture m, uint i) {
  float learned = vplkit_discrete_cdf_empty(m.learned) || i >= uint(vplkit_texel_count(vr_params.resolution))
                      ? 0.0
                      : vplkit_discrete_cdf_pmf(m.learned, vr_tile_block_of(i)) * vr_tile_share(i);
  return vplkit_mixture_split_pmf(vplkit_defensive_mixture_split(m), learned, vplkit_discrete_cdf_pmf(m.fallback, i));
}

// C++ tiled_distribution::sample.
vplkit_discrete_sample vr_tiled_sample(vplkit_defensive_mixture m, float u) {
  if (vplkit_defensive_mixture_empty(m)) return vplkit_discrete_sample(0u, 0.0);
  vplkit_mixture_choice c = vplkit_mixture_split_choose(vplkit_defensive_mixture_split(m), u);
  uint i;
  if (c.component == VPLKIT_MIXTURE_FALLBACK) {
    i = vplkit_discrete_cdf_sample(m.fallback, c.u).index;
  } else {
    uint b = vplkit_discrete_cdf_sample(m.learned, c.u).index;
    float lo = vplkit_load_cdf(m.learned.id, b), hi = vplkit_load_cdf(m.learned.id, b + 1u);
    i = vr_tile_texel_in_block(b, c.u - lo, hi - lo);
  }
  return vplkit_discrete_sample(i, vr_tiled_pmf(m, i));
}

#endif  // VPLRENDER_ESTIMATE_TILES_GLSL
