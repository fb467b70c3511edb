// SPDX-License-Identifier: MIT
#pragma once
// --candidate-source tiles (ris-mis): per image tile a candidate distribution near the tile's
// integrand at the cost of a few texel blocks per tile, not of every texel per tile. The GPU
// backend builds the same on the GPU (render/gpu/gpu_tiles.hpp, tile_blocks.comp, tile_weights.comp,
// estimate_tiles.glsl).
//
// The DPRSM's faces are cut into blocks of B x B texels. Per block, once per frame: the texels that
// carry a VPL, each one's share l_t / L_b of the block's flux luminance, and a proxy VPL (the
// flux-weighted mean position and unit normal, the block's total flux). Per tile i: the block
// weights W_i(b) = mean over the tile's gather points g of luminance(vpl_contribution(g, proxy_b)),
// and a discrete CDF over them. The learned pmf of texel t in block b is P_i(b) l_t / L_b, exact
// (the within-block draw follows the shares); it is mixed with the flux build's fallback (uniform
// over the texels with a VPL) by --eps, so every texel with a VPL keeps a positive pmf and ris-mis
// stays unbiased however far the proxy is from a texel (docs/results.md, RIS, "Candidate sources":
// B = 4-8 loses nothing against per-texel weights). The cost is O(tiles x blocks x points + texels)
// where the local CDFs cost O(regions x texels x points).
#include "render/cpu/parallel.hpp"

#include <vplkit/core/gather_point.hpp>
#include <vplkit/core/unit_or_zero.hpp>
#include <vplkit/distribution/defensive_mixture.hpp>
#include <vplkit/distribution/discrete_cdf.hpp>
#include <vplkit/distribution/discrete_sample.hpp>
#include <vplkit/distribution/mixture_split.hpp>
#include <vplkit/paraboloid/texel_grid.hpp>
#include <vplkit/vpl/dprsm_view.hpp>
#include <vplkit/vpl/luminance.hpp>
#include <vplkit/vpl/vpl.hpp>

#include <algorithm>
#include <cstddef>
#include <vector>

namespace vplrender {

// The frame's texel blocks (shared by every tile). The GPU backend's tile_blocks.comp writes the
// same shares and proxies (render/gpu/gpu_tiles.hpp), and estimate_tiles.glsl draws a texel of a
// block as texel_in_block does: the same comparisons in the same order.
struct tile_blocks {
  int block = 8;       // B: texels per block side
  int resolution = 0;  // R of the DPRSM's faces
  int per_side = 0;    // blocks per face side, ceil(R / B)
  std::vector<float> share;          // per texel: l_t / L_b (0 without a VPL)
  std::vector<int> begin;            // per block: its first entry in texels (size blocks + 1)
  std::vector<int> texels;           // the texels of positive share, block by block, row-major in a block
  std::vector<float> cumulative;     // per entry of texels: the running sum of the shares in its block
  std::vector<vplkit::vpl<float>> proxy;  // per block; flux 0 for a block without a VPL

  int count() const { return static_cast<int>(proxy.size()); }
  int block_of(int t) const {
    const vplkit::ivec2 xy = vplkit::texel_coords(t, resolution);
    return (vplkit::texel_face(t, resolution) * per_side + xy.y / block) * per_side + xy.x / block;
  }
  // The texel of block b at the fraction d / w of its flux: the first texel whose running share
  // times w exceeds d (the last one if none does). The remapped u of the block's CDF is (u - lo) /
  // (hi - lo); comparing d = u - lo with w = hi - lo times the running share instead needs no
  // division, which GLSL does not round correctly. w = 0 (never for a block the CDF picks) takes
  // the first texel.
  int texel_in_block(std::size_t b, float d, float w) const {
    if (!(w > 0.0f)) {
      d = 0.0f;
      w = 1.0f;
    }
    int k = begin[b];
    const int last = begin[b + 1] - 1;
    while (k < last && !(d < w * cumulative[static_cast<std::size_t>(k)])) ++k;
    return texels[static_cast<std::size_t>(k)];
  }
};

// flux: the flux weights of the view (luminance of each texel's VPL flux, 0 without one).
inline tile_blocks make_tile_blocks(const vplkit::dprsm_view<float>& view, const std::vector<float>& flux,
                                    int block) {
  tile_blocks tb;
  tb.block = std::max(1, block);
  tb.resolution = view.resolution;
  tb.per_side = (tb.resolution + tb.block - 1) / tb.block;
  const int n_blocks = 2 * tb.per_side * tb.per_side;
  tb.share.assign(flux.size(), 0.0f);
  tb.begin.assign(static_cast<std::size_t>(n_blocks) + 1, 0);
  tb.proxy.assign(static_cast<std::size_t>(n_blocks), vplkit::vpl<float>{});
  for (int b = 0; b < n_blocks; ++b) {
    const int face = b / (tb.per_side * tb.per_side), in_face = b % (tb.per_side * tb.per_side);
    const int x0 = (in_face % tb.per_side) * tb.block, y0 = (in_face / tb.per_side) * tb.block;
    const int x1 = std::min(x0 + tb.block, tb.resolution), y1 = std::min(y0 + tb.block, tb.resolution);
    tb.begin[static_cast<std::size_t>(b)] = static_cast<int>(tb.texels.size());
    float L = 0.0f;
    glm::vec3 P(0.0f), N(0.0f), F(0.0f);
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) {
        const int t = vplkit::texel_index(face, x, y, tb.resolution);
        const float l = flux[static_cast<std::size_t>(t)];
        if (!(l > 0.0f)) continue;
        const vplkit::vpl<float> v = view.vpl_at(t);
        L += l;
        P += l * v.position;
        N += l * vplkit::unit_or_zero(v.normal);
        F += v.flux;
      }
    if (!(L > 0.0f)) continue;
    float c = 0.0f;
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) {
        const int t = vplkit::texel_index(face, x, y, tb.resolution);
        const float l = flux[static_cast<std::size_t>(t)];
        const float s = l > 0.0f ? l / L : 0.0f;
        if (!(s > 0.0f)) continue;
        tb.share[static_cast<std::size_t>(t)] = s;
        c += s;
        tb.texels.push_back(t);
        tb.cumulative.push_back(c);
      }
    tb.proxy[static_cast<std::size_t>(b)] = vplkit::vpl<float>{P / L, vplkit::unit_or_zero(N), F};
  }
  tb.begin[static_cast<std::size_t>(n_blocks)] = static_cast<int>(tb.texels.size());
  return tb;
}

// One tile's distribution over the texels: a defensive mixture (vplkit::mixture_split, --eps) of
// the learned part, a block from the tile's CDF and then a texel of the block by its share (pmf
// P(block) share), and the flux build's fallback. sample() and pmf() as the library's
// distributions (vplkit::defensive_mixture): the index and the pmf of the whole mixture.
struct tiled_distribution {
  const tile_blocks* blocks = nullptr;
  const vplkit::discrete_cdf<float>* fallback = nullptr;  // uniform over the texels with a VPL
  vplkit::discrete_cdf<float> block_cdf;
  vplkit::mixture_split<float> split;  // eps, 1 where the tile's blocks weigh nothing, 0 without a fallback

  bool fallback_empty() const { return fallback == nullptr || fallback->empty(); }
  bool empty() const { return block_cdf.empty() && fallback_empty(); }

  float pmf(std::size_t i) const {
    const float learned = block_cdf.empty() || i >= blocks->share.size()
                              ? 0.0f
                              : block_cdf.pmf(static_cast<std::size_t>(blocks->block_of(static_cast<int>(i)))) *
                                    blocks->share[i];
    return split.pmf(learned, fallback_empty() ? 0.0f : fallback->pmf(i));
  }

  vplkit::discrete_sample<float> sample(float u) const {
    if (empty()) return {0, 0.0f};
    const vplkit::mixture_choice<float> c = split.choose(u);
    std::size_t i = 0;
    if (c.component == vplkit::mixture_fallback) {
      i = fallback->sample(c.u).index;
    } else {
      const std::size_t b = block_cdf.sample(c.u).index;
      const float lo = block_cdf.cdf()[b], hi = block_cdf.cdf()[b + 1];
      i = static_cast<std::size_t>(blocks->texel_in_block(b, c.u - lo, hi - lo));
    }
    return {i, pmf(i)};
  }
};

// Tile i's block weights W_i(b): the mean over its valid gather points of the proxy's unshadowed
// contribution's luminance, summed in the points' order and multiplied by 1 / |points| (as
// tile_weights.comp and the library's global weights); 0 for a block without flux.
inline float tile_block_weight(const std::vector<vplkit::gather_point<float>>& pts, const vplkit::vpl<float>& v,
                               float dmin) {
  if (pts.empty() || !vplkit::vpl_has_flux(v)) return 0.0f;
  float sum = 0.0f;
  for (const vplkit::gather_point<float>& g : pts) sum += vplkit::luminance(vplkit::vpl_contribution(g, v, dmin));
  return sum * (1.0f / static_cast<float>(pts.size()));
}

// One distribution per tile from the tiles' gather points (valid ones), over the workers. The
// distributions point at tb and fallback: both must outlive them and stay where they are. eps in
// [0, 1] (else vplkit::invalid_input, from mixture_split).
inline std::vector<tiled_distribution> make_tiled_distributions(
    const tile_blocks& tb, const std::vector<std::vector<vplkit::gather_point<float>>>& tile_points, float dmin,
    const vplkit::discrete_cdf<float>& fallback, float eps, int threads) {
  const int n_tiles = static_cast<int>(tile_points.size());
  const std::size_t n_blocks = static_cast<std::size_t>(tb.count());
  std::vector<tiled_distribution> out(static_cast<std::size_t>(n_tiles));
  parallel_items(n_tiles, threads, "", {}, [&](int i, int) {
    const std::vector<vplkit::gather_point<float>>& pts = tile_points[static_cast<std::size_t>(i)];
    std::vector<float> w(n_blocks, 0.0f);
    for (std::size_t b = 0; b < n_blocks; ++b) w[b] = tile_block_weight(pts, tb.proxy[b], dmin);
    tiled_distribution& d = out[static_cast<std::size_t>(i)];
    d.blocks = &tb;
    d.fallback = &fallback;
    d.block_cdf = vplkit::discrete_cdf<float>(w.data(), w.size());
  });
  // After the workers: mixture_split throws on a bad eps, which must not leave a worker.
  for (tiled_distribution& d : out) d.split = vplkit::mixture_split<float>(eps, d.block_cdf.empty(), fallback.empty());
  return out;
}

}  // namespace vplrender
