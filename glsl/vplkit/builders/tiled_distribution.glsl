// SPDX-License-Identifier: MIT
// vplkit GLSL pack: a tile's candidate distribution over the DPRSM's texels (docs/math.md 13.5);
// mirrors include/vplkit/builders/tiled_distribution.hpp (T = float). The distribution is a
// vplkit_defensive_mixture whose learned part is the tile's CDF over the blocks (cdf_build.comp
// over the tile's vplkit_tile_block_weight values) and whose fallback is over the 2 R^2 texels
// (make_vpl_fallback's), with the C++ split's scalars; the grid names the blocks. The learned
// pmf of texel t is P(block of t) share_t, so vplkit_tiled_distribution_sample returns the C++
// index and pmf: the u split of mixture_split.glsl, the block from its CDF, and the texel within
// the block by comparison, without a division.
//
// ACCESSORS (the including shader defines them):
//   float vplkit_load_tile_share(int texel);
//     texel's share of its block's flux (vplkit_tile_texel_share as the block kernel wrote it; 0
//     without a VPL).
//   those of distribution/discrete_cdf.glsl (vplkit_load_cdf, vplkit_load_guide) for both CDFs,
//   told apart by their descriptors' ids.
#ifndef VPLKIT_BUILDERS_TILED_DISTRIBUTION_GLSL
#define VPLKIT_BUILDERS_TILED_DISTRIBUTION_GLSL

#include "vplkit/builders/tile_blocks.glsl"
#include "vplkit/distribution/defensive_mixture.glsl"
#include "vplkit/paraboloid/texel_grid.glsl"

float vplkit_load_tile_share(int texel);

// C++ tile_blocks::texel_in_block: the first texel of block b (row-major, positive share) whose
// running share c has d < w c, else the block's last such texel; w <= 0 or NaN takes the first.
// precise: w c is rounded before the comparison, as in the C++, not fused with anything.
int vplkit_tile_texel_in_block(vplkit_tile_block_grid g, int b, float d, float w) {
  if (!(w > 0.0)) {
    d = 0.0;
    w = 1.0;
  }
  int face = vplkit_tile_block_grid_face_of_block(g, b);
  ivec4 r = vplkit_tile_block_grid_rect(g, b);
  float c = 0.0;
  int last = vplkit_texel_index(face, r.x, r.y, g.resolution);  // a block without a VPL: its first texel
  for (int y = r.y; y < r.w; ++y)
    for (int x = r.x; x < r.z; ++x) {
      int t = vplkit_texel_index(face, x, y, g.resolution);
      float s = vplkit_load_tile_share(t);
      if (!(s > 0.0)) continue;
      c += s;
      precise float bound = w * c;
      if (d < bound) return t;
      last = t;
    }
  return last;
}

// C++ tiled_distribution::pmf.
float vplkit_tiled_distribution_pmf(vplkit_defensive_mixture m, vplkit_tile_block_grid g, uint i) {
  float learned = vplkit_discrete_cdf_empty(m.learned) || i >= uint(vplkit_texel_count(g.resolution))
                      ? 0.0
                      : vplkit_discrete_cdf_pmf(m.learned, uint(vplkit_tile_block_grid_block_of(g, int(i)))) *
                            vplkit_load_tile_share(int(i));
  return vplkit_mixture_split_pmf(vplkit_defensive_mixture_split(m), learned, vplkit_discrete_cdf_pmf(m.fallback, i));
}

// C++ tiled_distribution::sample: the index and the mixture's pmf; {0, 0} when both parts are empty.
vplkit_discrete_sample vplkit_tiled_distribution_sample(vplkit_defensive_mixture m, vplkit_tile_block_grid g, float u) {
  if (vplkit_defensive_mixture_empty(m)) return vplkit_discrete_sample(0u, 0.0);
  vplkit_mixture_choice c = vplkit_mixture_split_choose(vplkit_defensive_mixture_split(m), u);
  uint i;
  if (c.component == VPLKIT_MIXTURE_FALLBACK) {
    i = vplkit_discrete_cdf_sample(m.fallback, c.u).index;
  } else {
    uint b = vplkit_discrete_cdf_sample(m.learned, c.u).index;
    float lo = vplkit_load_cdf(m.learned.id, b), hi = vplkit_load_cdf(m.learned.id, b + 1u);
    i = uint(vplkit_tile_texel_in_block(g, int(b), c.u - lo, hi - lo));
  }
  return vplkit_discrete_sample(i, vplkit_tiled_distribution_pmf(m, g, i));
}

#endif  // VPLKIT_BUILDERS_TILED_DISTRIBUTION_GLSL
