// SPDX-License-Identifier: MIT
#pragma once
// Dense indices of the occupied voxels of a voxel_grid: rank[w] = the number of occupied voxels in
// words 0 .. w-1 (one uint32 per occupancy word), so an occupied voxel with flat index i is the
// r-th occupied voxel in flat-index order, r = rank[i >> 5] + bitCount(words[i >> 5] & ((1u <<
// (i & 31)) - 1u)). Per-occupied-voxel data (the triangle voxel grid's lists) is indexed by r.
// The GPU computes rank with glsl/vplkit/visibility/prefix_sum.comp (bit-count mode).
#include <vplkit/core/vector.hpp>
#include <vplkit/visibility/voxel_grid.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace vplkit {

// Number of set bits (bitCount in GLSL): the branch-free SWAR count (C++17 has no std::popcount),
// on the hot path of every triangle voxel query.
inline int voxel_bit_count(std::uint32_t w) {
  w = w - ((w >> 1) & 0x55555555u);
  w = (w & 0x33333333u) + ((w >> 2) & 0x33333333u);
  return int((((w + (w >> 4)) & 0x0F0F0F0Fu) * 0x01010101u) >> 24);
}

// rank[w] = occupied voxels in words 0 .. w-1 (the exclusive prefix sum of the words' bit counts).
inline std::vector<std::uint32_t> voxel_occupancy_rank(const std::uint32_t* words, std::size_t word_count) {
  std::vector<std::uint32_t> rank(word_count);
  std::uint32_t sum = 0;
  for (std::size_t i = 0; i < word_count; ++i) {
    rank[i] = sum;
    sum += std::uint32_t(voxel_bit_count(words[i]));
  }
  return rank;
}

// Dense index of voxel v among the occupied voxels, or -1 when v is free or outside the grid.
template <class T>
inline std::int64_t voxel_occupied_index(const voxel_grid_view<T>& g, const std::uint32_t* rank, ivec3 v) {
  if (!voxel_in_grid(g.resolution, v)) return -1;
  const std::int64_t i = voxel_flat_index(g.resolution, v);
  const std::uint32_t word = g.words[std::size_t(i >> 5)];
  const std::uint32_t bit = std::uint32_t(i & 31);
  if (((word >> bit) & 1u) == 0u) return -1;
  return std::int64_t(rank[std::size_t(i >> 5)]) + voxel_bit_count(word & ((std::uint32_t(1) << bit) - 1u));
}

}  // namespace vplkit
