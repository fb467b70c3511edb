// SPDX-License-Identifier: MIT
#pragma once
// A tile's candidate distribution over the DPRSM's texels (docs/math.md 13.5): a CDF over texel
// blocks (builders/tile_blocks.hpp) whose weights W(b) are the tile's (tile_block_weight), refined
// within each block by the flux shares, in a defensive mixture with a fallback over the texels:
//     p(t) = (1 - eps) P(b(t)) l_t / L_b(t)  +  eps p_fallback(t),   P(b) = W(b) / sum W.
// The pmf is exact, so an estimator that divides by it stays unbiased however far a proxy is from
// its texels, and with eps > 0 and make_vpl_fallback's fallback every texel with a VPL keeps
// p > 0. What it buys: per image tile a distribution near the tile's integrand at the cost of
// 2 R^2 / B^2 weights per tile, where a local CDF (local_weights.hpp) costs 2 R^2.
//
// sample(u): the u split of every defensive mixture (mixture_split: the fallback with u (1/eps),
// else the learned part with u' = (u - eps) (1/(1 - eps))), a block b from the CDF with u', then
// tile_blocks::texel_in_block(b, u' - F(b), F(b + 1) - F(b)). Returns the index and the mixture's
// pmf; {0, 0} when both parts are empty. The GLSL mirror is builders/tiled_distribution.glsl.
#include <vplkit/builders/tile_blocks.hpp>
#include <vplkit/core/error.hpp>
#include <vplkit/distribution/discrete_cdf.hpp>
#include <vplkit/distribution/discrete_sample.hpp>
#include <vplkit/distribution/mixture_split.hpp>

#include <cstddef>
#include <string>

namespace vplkit {

template <class T>
class tiled_distribution {
public:
  using value_type = T;

  // Empty: sample() returns {0, 0}.
  tiled_distribution() = default;

  // block_weights: one per block of `blocks` (n == blocks.count(), finite and >= 0, else
  // invalid_input, as discrete_cdf); fallback: over the 2 R^2 texels (make_vpl_fallback), or an
  // empty one for none; eps in [0, 1] (else invalid_input). Keeps pointers to blocks and fallback:
  // both must outlive the distribution and stay where they are.
  tiled_distribution(const tile_blocks<T>& blocks, const T* block_weights, std::size_t n,
                     const discrete_cdf<T>& fallback, T eps)
      : blocks_(&blocks), fallback_(&fallback), block_cdf_(block_weights, n) {
    if (n != std::size_t(blocks.count()))
      throw invalid_input("tiled_distribution: " + std::to_string(n) + " block weights for " +
                          std::to_string(blocks.count()) + " blocks");
    if (!fallback.empty() && fallback.size() != blocks.share.size())
      throw invalid_input("tiled_distribution: a fallback over " + std::to_string(fallback.size()) +
                          " texels for a DPRSM of " + std::to_string(blocks.share.size()));
    split_ = mixture_split<T>(eps, block_cdf_.empty(), fallback.empty());
  }

  bool empty() const noexcept { return block_cdf_.empty() && fallback_empty(); }
  // The CDF over the blocks (empty when every block weighs 0: the fallback alone serves) and the
  // split of eps (effective eps 1 then, 0 without a fallback).
  const discrete_cdf<T>& block_cdf() const noexcept { return block_cdf_; }
  const mixture_split<T>& split() const noexcept { return split_; }

  T pmf(std::size_t i) const noexcept {
    const T learned = block_cdf_.empty() || i >= blocks_->share.size()
                          ? T(0)
                          : block_cdf_.pmf(std::size_t(blocks_->block_of(int(i)))) * blocks_->share[i];
    return split_.pmf(learned, fallback_empty() ? T(0) : fallback_->pmf(i));
  }

  discrete_sample<T> sample(T u) const noexcept {
    if (empty()) return {0, T(0)};
    const mixture_choice<T> c = split_.choose(u);
    std::size_t i = 0;
    if (c.component == mixture_fallback) {
      i = fallback_->sample(c.u).index;
    } else {
      const std::size_t b = block_cdf_.sample(c.u).index;
      const T lo = block_cdf_.cdf()[b], hi = block_cdf_.cdf()[b + 1];
      i = std::size_t(blocks_->texel_in_block(b, c.u - lo, hi - lo));
    }
    return {i, pmf(i)};
  }

private:
  bool fallback_empty() const noexcept { return fallback_ == nullptr || fallback_->empty(); }

  const tile_blocks<T>* blocks_ = nullptr;
  const discrete_cdf<T>* fallback_ = nullptr;
  discrete_cdf<T> block_cdf_;
  mixture_split<T> split_;
};

}  // namespace vplkit
