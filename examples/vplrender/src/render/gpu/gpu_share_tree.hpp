// SPDX-License-Identifier: MIT
#pragma once
// --sampler share-tree on the GPU backend: the learned parts of the D mixtures as share trees, built
// on the GPU from the builders' weights by the pack's distribution/share_tree_build.comp (log2(L) + 1
// dispatches per tree, L = share_tree_leaf_count(n)): the arrays of vplkit::share_tree<float> bit
// for bit from the same weights (parity_share_tree_test). Only the trees' totals come back (4 bytes
// each): the estimate kernels' mixture records carry them (estimate_params.h).
#include "render/stage_timer.hpp"

#include <headless_gl/compute.hpp>

#include <nlohmann/json.hpp>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace vplrender {

struct gpu_share_trees {
  vplkit::gl::buffer shares;  // VR_ESTIMATE_BINDING_COMPONENTS: uint shares[D L], tree d at d L
  std::uint32_t leaves = 0;   // L
  std::vector<float> totals;  // per tree: sums[1] (the float pairwise total)
};

// `weights` holds the D weight arrays of n floats each (region-major), on the GPU. A float total past
// FLT_MAX throws vplkit::invalid_input, as the C++ share_tree build does. Stage "share tree (gpu)"
// goes to `timer`, facts to det["share_tree"].
gpu_share_trees build_share_trees_gpu(const vplkit::gl::buffer& weights, int D, std::size_t n, stage_timer& timer,
                                      nlohmann::json& det);

}  // namespace vplrender
