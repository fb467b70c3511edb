// SPDX-License-Identifier: MIT
// vplkit GLSL pack: dense indices of the occupied voxels (mirrors
// include/vplkit/visibility/voxel_rank.hpp): rank[w] = occupied voxels in words 0 .. w-1, so an
// occupied voxel with flat index i is number r = rank[i >> 5] + bitCount(words[i >> 5] &
// ((1u << (i & 31)) - 1u)) in flat-index order. prefix_sum.comp computes rank (bit-count mode).
//
// ACCESSORS (the including shader defines them):
//   uint vplkit_load_voxel_word(uint word_index);   // voxel_grid.glsl
//   uint vplkit_load_voxel_rank(uint word_index);   // rank[word_index]
#ifndef VPLKIT_VISIBILITY_VOXEL_RANK_GLSL
#define VPLKIT_VISIBILITY_VOXEL_RANK_GLSL

#include "vplkit/visibility/voxel_grid.glsl"

uint vplkit_load_voxel_rank(uint word_index);

// Dense index of voxel v among the occupied voxels, or -1 when v is free or outside the grid.
int vplkit_voxel_occupied_index(vplkit_voxel_grid g, ivec3 v) {
  if (!vplkit_voxel_in_grid(g.resolution, v)) return -1;
  uint i = vplkit_voxel_flat_index(g.resolution, v);
  uint word = vplkit_load_voxel_word(i >> 5u);
  uint bit = i & 31u;
  if (((word >> bit) & 1u) == 0u) return -1;
  return int(vplkit_load_voxel_rank(i >> 5u)) + bitCount(word & ((1u << bit) - 1u));
}

#endif  // VPLKIT_VISIBILITY_VOXEL_RANK_GLSL
