// SPDX-License-Identifier: MIT
#pragma once
// --sampler share-tree: the defensive mixtures of global, gbg, local and mis with their
// learned part drawn from a vplkit::share_tree (docs/math.md, "Image parity at large DPRSMs"): a
// weight that differs by its last bits between the backends moves only the shares on its own path,
// so the CPU and GPU draws stay the same at large DPRSMs, where the flat CDF's prefix sums collect
// every difference before a bin.
//
// How a draw consumes random numbers (estimate_distributions.glsl's VR_SAMPLER_SHARE_TREE does the
// same, number for number):
//   - the mixture's split takes the estimator's u (vplkit::mixture_split::choose, as for the CDF);
//   - the fallback (uniform over the texels with a VPL) is its discrete CDF at the split's
//     remapped u, as before;
//   - the learned part is share_tree::sample with 24-bit numbers (rng_next_u32 >> 8) from the
//     pixel's TREE STREAM: share_tree_stream(pixel's stream), a key of its own (the pixel key
//     hashed), counter 0 at the pixel's first draw.
// Every draw advances the tree stream by exactly depth() numbers, whichever part it took (the
// fallback and an empty mixture skip them), so draw k's numbers start at k depth(): a GPU render
// split into sample ranges [begin, end) resumes the stream at begin depth() without keeping it.
// The estimator's own stream (u, the patch jitter, the clamp compensation's key) is the one the CDF
// sampler consumes: its library code is unchanged, the tree draws beside it.
#include <vplkit/core/error.hpp>
#include <vplkit/distribution/defensive_mixture.hpp>
#include <vplkit/distribution/discrete_sample.hpp>
#include <vplkit/distribution/mixture_split.hpp>
#include <vplkit/distribution/share_tree.hpp>
#include <vplkit/sampling/rng.hpp>

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace vplrender {

// The tree stream's key salt; estimate_params.h's VR_SHARE_TREE_STREAM_SALT (checked there).
inline constexpr std::uint32_t share_tree_stream_salt = 0x5E72EEu;

// The tree stream of a pixel whose estimator stream is `pixel` (only its key is used).
inline vplkit::counter_rng share_tree_stream(const vplkit::counter_rng& pixel) {
  return vplkit::counter_rng{vplkit::rng_key(pixel.key, share_tree_stream_salt), 0u};
}

// Mixture d: its learned part as a share tree, the split and fallback of the joint CDF mixture d
// (the same eps and the same emptiness: a tree's total is positive exactly when the CDF's is, both
// counting weights below FLT_MIN as 0; checked).
struct share_tree_mixture {
  vplkit::share_tree<float> learned;
  const vplkit::defensive_mixture<float>* joint = nullptr;
};

// D mixtures from the builders' D weight arrays of n each (region-major). Rejected weights count as 0
// (as share_tree_build.comp); a float total past FLT_MAX throws vplkit::invalid_input.
inline std::vector<share_tree_mixture> build_share_tree_mixtures(const std::vector<float>& weights,
                                                                 const std::vector<vplkit::defensive_mixture<float>>& joint) {
  const std::size_t D = joint.size();
  if (D == 0 || weights.size() % D != 0)
    throw std::logic_error("build_share_tree_mixtures: " + std::to_string(weights.size()) + " weights for " +
                           std::to_string(D) + " mixtures");
  const std::size_t n = weights.size() / D;
  std::vector<share_tree_mixture> out(D);
  for (std::size_t d = 0; d < D; ++d) {
    out[d].learned = vplkit::share_tree<float>::sanitized(weights.data() + d * n, n).distribution;
    out[d].joint = &joint[d];
    if (out[d].learned.empty() != joint[d].learned().empty())
      throw std::logic_error("build_share_tree_mixtures: mixture " + std::to_string(d) +
                             ": the share tree and the CDF disagree on emptiness");
  }
  return out;
}

// Mixture m drawn with the tree numbers of `stream` (a pixel's tree stream, advanced by every
// draw): the estimators' Distribution interface (sample(u) -> {index, pmf}, pmf(i)).
struct share_tree_mixture_draw {
  const share_tree_mixture* m = nullptr;
  vplkit::counter_rng* stream = nullptr;

  float pmf(std::size_t i) const noexcept {
    return m->joint->split().pmf(m->learned.pmf(i), m->joint->fallback().pmf(i));
  }

  vplkit::discrete_sample<float> sample(float u) const {
    if (m->joint->empty()) {
      stream->counter += m->learned.depth();
      return {0, 0.0f};
    }
    const vplkit::mixture_choice<float> c = m->joint->split().choose(u);
    std::size_t i = 0;
    if (c.component == vplkit::mixture_fallback) {
      i = m->joint->fallback().sample(c.u).index;
      stream->counter += m->learned.depth();
    } else {
      i = m->learned.sample([this] { return vplkit::rng_next_u32(*stream) >> 8u; }).index;
    }
    return {i, pmf(i)};
  }
};

}  // namespace vplrender
