// SPDX-License-Identifier: MIT
#pragma once
// --candidate-source tiles (ris-mis) on the CPU backend: one library tiled_distribution per image
// tile (vplkit/builders/tiled_distribution.hpp, docs/math.md 13.5) over the frame's texel blocks
// (vplkit/builders/tile_blocks.hpp), each tile's blocks weighed by its gather points. The GPU
// backend builds the same on the GPU (render/gpu/gpu_tiles.hpp, the pack's tile_blocks.comp and
// tile_weights.comp, estimate_tiles.glsl). The cost is O(tiles x blocks x points + texels) where
// the local CDFs cost O(regions x texels x points).
#include "render/cpu/parallel.hpp"

#include <vplkit/builders/tile_blocks.hpp>
#include <vplkit/builders/tiled_distribution.hpp>
#include <vplkit/core/gather_point.hpp>
#include <vplkit/distribution/discrete_cdf.hpp>

#include <cstddef>
#include <vector>

namespace vplrender {

using tile_blocks = vplkit::tile_blocks<float>;
using tiled_distribution = vplkit::tiled_distribution<float>;

// One distribution per tile from the tiles' gather points, over the workers (the library's
// tile_block_weight per block, then its tiled_distribution). The distributions point at tb and
// fallback: both must outlive them and stay where they are. eps in [0, 1] (else
// vplkit::invalid_input).
inline std::vector<tiled_distribution> make_tiled_distributions(
    const tile_blocks& tb, const std::vector<std::vector<vplkit::gather_point<float>>>& tile_points, float dmin,
    const vplkit::discrete_cdf<float>& fallback, float eps, int threads) {
  const int n_tiles = static_cast<int>(tile_points.size());
  const std::size_t n_blocks = static_cast<std::size_t>(tb.count());
  std::vector<std::vector<float>> weights(static_cast<std::size_t>(n_tiles));
  parallel_items(n_tiles, threads, "", {}, [&](int i, int) {
    const std::vector<vplkit::gather_point<float>>& pts = tile_points[static_cast<std::size_t>(i)];
    std::vector<float>& w = weights[static_cast<std::size_t>(i)];
    w.assign(n_blocks, 0.0f);
    for (std::size_t b = 0; b < n_blocks; ++b) w[b] = vplkit::tile_block_weight(pts.data(), pts.size(), tb.proxy[b], dmin);
  });
  // The CDFs after the workers: a bad eps throws, which must not leave a worker.
  std::vector<tiled_distribution> out;
  out.reserve(weights.size());
  for (const std::vector<float>& w : weights) out.emplace_back(tb, w.data(), w.size(), fallback, eps);
  return out;
}

}  // namespace vplrender
