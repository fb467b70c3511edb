// SPDX-License-Identifier: MIT
#pragma once
// --candidate-source tiles (ris-mis, CPU backend): per image tile a candidate distribution near the
// tile's integrand at the cost of a few texel blocks per tile, not of every texel per tile.
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
#include <vplkit/paraboloid/texel_grid.hpp>
#include <vplkit/vpl/dprsm_view.hpp>
#include <vplkit/vpl/luminance.hpp>
#include <vplkit/vpl/vpl.hpp>

#include <algorithm>
#include <cstddef>
#include <vector>

namespace vplrender {

// The frame's texel blocks (shared by every tile).
struct tile_blocks {
  int block = 8;       // B: texels per block side
  int resolution = 0;  // R of the DPRSM's faces
  int per_side = 0;    // blocks per face side, ceil(R / B)
  std::vector<float> share;          // per texel: l_t / L_b (0 without a VPL)
  std::vector<int> begin;            // per block: its first entry in texels (size blocks + 1)
  std::vector<int> texels;           // the texels with a VPL, block by block
  std::vector<float> cumulative;     // per entry of texels: the running sum of the shares in its block
  std::vector<vplkit::vpl<float>> proxy;  // per block; flux 0 for a block without a VPL

  int count() const { return static_cast<int>(proxy.size()); }
  int block_of(int t) const {
    const vplkit::ivec2 xy = vplkit::texel_coords(t, resolution);
    return (vplkit::texel_face(t, resolution) * per_side + xy.y / block) * per_side + xy.x / block;
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
    const std::size_t first = tb.texels.size();
    tb.begin[static_cast<std::size_t>(b)] = static_cast<int>(first);
    float L = 0.0f;
    glm::vec3 P(0.0f), N(0.0f), F(0.0f);
    for (int y = y0; y < std::min(y0 + tb.block, tb.resolution); ++y)
      for (int x = x0; x < std::min(x0 + tb.block, tb.resolution); ++x) {
        const int t = vplkit::texel_index(face, x, y, tb.resolution);
        const float l = flux[static_cast<std::size_t>(t)];
        if (!(l > 0.0f)) continue;
        const vplkit::vpl<float> v = view.vpl_at(t);
        tb.texels.push_back(t);
        L += l;
        P += l * v.position;
        N += l * vplkit::unit_or_zero(v.normal);
        F += v.flux;
      }
    if (!(L > 0.0f)) continue;
    float c = 0.0f;
    for (std::size_t k = first; k < tb.texels.size(); ++k) {
      const std::size_t t = static_cast<std::size_t>(tb.texels[k]);
      tb.share[t] = flux[t] / L;
      c += tb.share[t];
      tb.cumulative.push_back(c);
    }
    tb.proxy[static_cast<std::size_t>(b)] = vplkit::vpl<float>{P / L, vplkit::unit_or_zero(N), F};
  }
  tb.begin[static_cast<std::size_t>(n_blocks)] = static_cast<int>(tb.texels.size());
  return tb;
}

// One tile's distribution over the texels: with probability 1 - eps a block from its CDF, then a
// texel of the block by its share; with probability eps the flux build's fallback. sample() and
// pmf() as the library's distributions (vplkit::defensive_mixture): the index and the pmf of the
// whole mixture.
struct tiled_distribution {
  const tile_blocks* blocks = nullptr;
  const vplkit::discrete_cdf<float>* fallback = nullptr;  // uniform over the texels with a VPL
  vplkit::discrete_cdf<float> block_cdf;
  float eps = 0.0f;

  // The fallback's share of the mixture: eps, 1 where the tile's blocks weigh nothing (every
  // draw then comes from the fallback), 0 without a fallback.
  float fallback_share() const {
    if (fallback == nullptr || fallback->empty()) return 0.0f;
    return block_cdf.empty() ? 1.0f : eps;
  }
  bool empty() const { return block_cdf.empty() && (fallback == nullptr || fallback->empty()); }

  float pmf(std::size_t i) const {
    const float e = fallback_share();
    const float learned = block_cdf.empty() || i >= blocks->share.size()
                              ? 0.0f
                              : block_cdf.pmf(static_cast<std::size_t>(blocks->block_of(static_cast<int>(i)))) *
                                    blocks->share[i];
    const float fb = e > 0.0f ? fallback->pmf(i) : 0.0f;
    return (1.0f - e) * learned + e * fb;
  }

  vplkit::discrete_sample<float> sample(float u) const {
    if (empty()) return {0, 0.0f};
    constexpr float below_one = 0x1.fffffep-1f;
    const float e = fallback_share();
    std::size_t i = 0;
    if (u < e) {
      i = fallback->sample(std::min(u / e, below_one)).index;
    } else {
      const float ul = std::min((u - e) / (1.0f - e), below_one);
      const std::size_t b = block_cdf.sample(ul).index;
      const float lo = block_cdf.cdf()[b], hi = block_cdf.cdf()[b + 1];
      const float u2 = hi > lo ? std::min((ul - lo) / (hi - lo), below_one) : 0.0f;
      int k = blocks->begin[b];
      const int last = blocks->begin[b + 1] - 1;
      while (k < last && !(u2 < blocks->cumulative[static_cast<std::size_t>(k)])) ++k;
      i = static_cast<std::size_t>(blocks->texels[static_cast<std::size_t>(k)]);
    }
    return {i, pmf(i)};
  }
};

// One distribution per tile from the tiles' gather points (valid ones), over the workers. The
// distributions point at tb and fallback: both must outlive them and stay where they are.
inline std::vector<tiled_distribution> make_tiled_distributions(
    const tile_blocks& tb, const std::vector<std::vector<vplkit::gather_point<float>>>& tile_points, float dmin,
    const vplkit::discrete_cdf<float>& fallback, float eps, int threads) {
  const int n_tiles = static_cast<int>(tile_points.size());
  const std::size_t n_blocks = static_cast<std::size_t>(tb.count());
  std::vector<tiled_distribution> out(static_cast<std::size_t>(n_tiles));
  parallel_items(n_tiles, threads, "", {}, [&](int i, int) {
    const std::vector<vplkit::gather_point<float>>& pts = tile_points[static_cast<std::size_t>(i)];
    std::vector<float> w(n_blocks, 0.0f);
    if (!pts.empty())
      for (std::size_t b = 0; b < n_blocks; ++b) {
        const vplkit::vpl<float>& v = tb.proxy[b];
        if (!vplkit::vpl_has_flux(v)) continue;
        float sum = 0.0f;
        for (const vplkit::gather_point<float>& g : pts) sum += vplkit::luminance(vplkit::vpl_contribution(g, v, dmin));
        w[b] = sum / static_cast<float>(pts.size());
      }
    tiled_distribution& d = out[static_cast<std::size_t>(i)];
    d.blocks = &tb;
    d.fallback = &fallback;
    d.eps = eps;
    d.block_cdf = vplkit::discrete_cdf<float>(w.data(), w.size());
  });
  return out;
}

}  // namespace vplrender
