// SPDX-License-Identifier: MIT
// vplkit GLSL pack: a tile's weight of one texel block (docs/math.md 13.5); mirrors
// include/vplkit/builders/tile_blocks.hpp's tile_block_weight (T = float): the mean over the
// tile's gather points of the block proxy's unshadowed contribution's luminance. A weights kernel
// runs it once per (block, tile) and writes tile-major weights for cdf_build.comp.
//
// ACCESSORS (the including shader defines them):
//   vplkit_gather_point vplkit_load_subset_gather_point(int i);
//     entry i (0 <= i < count) of the tile's points, in their order, as for
//     builders/global_weights.glsl: entries failing vplkit_gather_point_valid are skipped and not
//     counted.
//
// Arithmetic, as in the C++: the sum runs in float over the points in order, then is multiplied
// by 1.0 / float(used) (a GLSL division: within 2.5 ulp, the same factor for every block of a tile,
// so the tile's CDF does not move).
#ifndef VPLKIT_BUILDERS_TILE_WEIGHTS_GLSL
#define VPLKIT_BUILDERS_TILE_WEIGHTS_GLSL

#include "vplkit/core/gather_point.glsl"
#include "vplkit/vpl/luminance.glsl"
#include "vplkit/vpl/vpl.glsl"

vplkit_gather_point vplkit_load_subset_gather_point(int i);

// C++ tile_block_weight: 0 for a proxy without flux or without a valid point.
float vplkit_tile_block_weight(vplkit_vpl proxy, int count, float dmin) {
  if (!vplkit_vpl_has_flux(proxy)) return 0.0;
  float sum = 0.0;
  int used = 0;
  for (int i = 0; i < count; ++i) {
    vplkit_gather_point g = vplkit_load_subset_gather_point(i);
    if (!vplkit_gather_point_valid(g)) continue;
    sum += vplkit_luminance(vplkit_vpl_contribution(g, proxy, dmin));
    ++used;
  }
  return used > 0 ? sum * (1.0 / float(used)) : 0.0;
}

#endif  // VPLKIT_BUILDERS_TILE_WEIGHTS_GLSL
