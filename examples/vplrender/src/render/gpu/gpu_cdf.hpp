// SPDX-License-Identifier: MIT
#pragma once
// The defensive mixtures of the GPU backend built on the GPU (vplkit::make_vpl_distribution /
// make_local_vpl_distributions in the layout the estimate kernels sample), from weights that already
// live in a GPU buffer (gpu_builders.cpp, build_gbg_weights_gpu).
//
// The learned CDFs (one per weight array) and the shared fallback (the uniform distribution over
// the texels that carry a VPL; vpl_fallback_weights.comp writes its 0/1 weights) are built in one
// set of dispatches of the pack's distribution/cdf_build.comp (double accumulation): every value
// is the C++ discrete_cdf<float> value or a float neighbour (docs/glsl/distribution.md). Only the
// totals come back to the host (16 bytes per distribution): the mixture scalars (effective eps, the
// two reciprocals) are then computed by the C++ defensive_mixture constructor's own code (the
// estimate kernels get them as estimate_params.h records; the 12-uint records + slot table in
// `meta` are what renderer_gpu_builders_test reads).
#include "render/gpu/gpu_share_tree.hpp"
#include "render/stage_timer.hpp"

#include <headless_gl/compute.hpp>
#include <vplkit/vpl/dprsm_view.hpp>

#include <nlohmann/json.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace vplrender {

struct gpu_mixtures {
  vplkit::gl::buffer data;  // VR_ESTIMATE_BINDING_CDF_DATA (vr_cdf_data): cdf floats (bits) and guides
  vplkit::gl::buffer meta;  // 12 uints per mixture, then the slot table (renderer_gpu_builders_test)
  std::uint32_t slot_base = 0;
  int count = 0;            // D mixtures
  int local_rounds = 0;     // set by the local builder (max(1, vpls / D)), else 0
  // Where distribution k (0..D-1 learned, D the fallback when eps > 0) lives in `data` (uints).
  std::size_t n = 0, m = 0;  // entries (2 R^2) and guide size of every distribution
  std::vector<std::size_t> cdf_offset, guide_offset;
  std::vector<float> totals;  // learned totals (read back), then the fallback's when eps > 0
  std::vector<float> effective_eps, fallback_scale, learned_scale;  // per mixture
  // The D learned weight arrays, read back only for --sampler alias / --face-selection roulette
  // (mixture_components.hpp builds their components on the host).
  std::vector<float> weights;
  // --sampler share-tree: the learned parts as share trees (gpu_share_tree.hpp); else empty.
  gpu_share_trees share_trees;
};

// `dists` discrete CDFs of n entries each (vplkit::discrete_cdf<float>'s values or float
// neighbours), from `weights` (dists arrays of n floats, array-major) by the pack's
// distribution/cdf_build.comp, into one buffer: CDF k at word k (n + 1), its guide table at
// guide_base + k (m + 1), m = vplkit::discrete_guide_size(n), then extra_words words for the caller
// at extra_base (zero; each part starts where an SSBO range binding may). Only the totals come back.
// Throws vplkit::invalid_input when there is nothing to build or the buffer is too small.
struct gpu_cdf_set {
  vplkit::gl::buffer data;
  std::size_t n = 0, m = 0, guide_base = 0, extra_base = 0;
  std::vector<float> totals;      // per CDF (0: empty)
  std::vector<long long> zeroed;  // per CDF: weights taken as 0 (negative, NaN or Inf)
};
gpu_cdf_set build_cdf_set_gpu(const vplkit::gl::buffer& weights, std::size_t dists, std::size_t n,
                              std::size_t extra_words);

// `weights` holds at least (D + 1) n floats, n = view.texel_count(): arrays 0 .. D-1 the builder's
// weights (region-major), array D scratch (the fallback's weights go there). `dprsm` is the DPRSM
// as 3 vec4 per texel (position, normal, albedo). eps in [0, 1] (else vplkit::invalid_input); eps
// = 0 builds no fallback (as make_vpl_distribution). Stage "cdf (gpu)" goes to `timer`, facts to
// det["cdf"].
gpu_mixtures build_mixtures_gpu(const vplkit::gl::buffer& weights, int D, const vplkit::gl::buffer& dprsm,
                                const vplkit::dprsm_view<float>& view, float eps, stage_timer& timer,
                                nlohmann::json& det);

}  // namespace vplrender
