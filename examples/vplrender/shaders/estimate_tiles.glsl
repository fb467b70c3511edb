// SPDX-License-Identifier: MIT
// vplrender's estimate kernels with --candidate-source tiles (VR_RIS_TILES; ris-mis): tile d's
// candidate distribution, render/cpu/tiled_candidates.hpp's tiled_distribution. Mixture record d
// (estimate_params.h's vr_mixture_record, written by render/gpu/gpu_tiles.cpp) is the tile's
// defensive mixture: its learned part the CDF over the DPRSM's texel blocks (id VR_TILE_SLOT + d,
// in the tile buffer at VR_RIS_BINDING_TILES), its fallback the flux build's (in the CDF data, as
// every mixture's), drawn by the pack's builders/tiled_distribution.glsl over the shares
// the pack's builders/tile_blocks.comp wrote (vplkit_load_tile_share). Included by
// estimate_distributions.glsl, which routes vplkit_load_cdf / _guide for ids >= VR_TILE_SLOT here
// and makes these the estimators' hooks.
//
// Layout of the tile buffer (uints, offsets in vr_params.ris): tile d's CDF at d (Nb + 1), Nb =
// 2 P^2 blocks, P = ceil(R / B); its guide at tile_guide_base + d (m + 1), m =
// vplkit_discrete_guide_size(Nb); the shares at tile_share_base + t.
#ifndef VPLRENDER_ESTIMATE_TILES_GLSL
#define VPLRENDER_ESTIMATE_TILES_GLSL

#include "estimate_ris_params.h"
#include "vplkit/builders/tiled_distribution.glsl"

layout(std430, binding = VR_RIS_BINDING_TILES) restrict readonly buffer VrTiles { uint vr_tiles[]; };

vplkit_tile_block_grid vr_tile_grid() { return vplkit_make_tile_block_grid(vr_params.resolution, vr_params.ris.tile_block); }
uint vr_tile_blocks() { return uint(vplkit_tile_block_grid_count(vr_tile_grid())); }
float vr_tile_load_cdf(uint tile, uint i) { return uintBitsToFloat(vr_tiles[tile * (vr_tile_blocks() + 1u) + i]); }
uint vr_tile_load_guide(uint tile, uint j) {
  return vr_tiles[vr_params.ris.tile_guide_base + tile * (vplkit_discrete_guide_size(vr_tile_blocks()) + 1u) + j];
}
float vplkit_load_tile_share(int texel) { return uintBitsToFloat(vr_tiles[vr_params.ris.tile_share_base + uint(texel)]); }

float vr_tiled_pmf(vplkit_defensive_mixture m, uint i) { return vplkit_tiled_distribution_pmf(m, vr_tile_grid(), i); }
vplkit_discrete_sample vr_tiled_sample(vplkit_defensive_mixture m, float u) {
  return vplkit_tiled_distribution_sample(m, vr_tile_grid(), u);
}

#endif  // VPLRENDER_ESTIMATE_TILES_GLSL
