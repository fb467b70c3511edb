// SPDX-License-Identifier: MIT
// vplkit GLSL pack: sampling a share tree, one fresh 24-bit number per level; mirrors the sampling
// side of include/vplkit/distribution/share_tree.hpp (float). The arrays come from the C++
// share_tree<float> (upload shares(); sums() only for the total) or from the kernel
// share_tree_build.comp, in the same layout: shares[0 .. L - 1] of an implicit heap of
// L = vplkit_share_tree_leaf_count(n) leaves, node 1 the root. Draws and pmfs are the C++ ones bit
// for bit for the same stream: integer comparisons, exact factors, and the products through
// vplkit_probability_product (`precise`, 0 or a normal float). ACCESSOR
// vplkit_load_share_tree_share(tree, node), `tree` being the descriptor's id; HOOK
// vplkit_share_tree_next_bits(tree): the next number in [0, 2^24) of the draw in progress (the
// C++ sample's next24 functor; with the project's RNG, vplkit_rng_next_u32(rng) >> 8u on the
// invocation's stream kept in a global, as C++ sample([&] { return rng_next_u32(rng) >> 8u; })).
// A hook and not an inout vplkit_counter_rng parameter: the distribution layer does not include
// the sampling layer (docs/architecture.md), and the caller chooses the stream.
#ifndef VPLKIT_DISTRIBUTION_SHARE_TREE_GLSL
#define VPLKIT_DISTRIBUTION_SHARE_TREE_GLSL

#include "vplkit/distribution/discrete_sample.glsl"
#include "vplkit/distribution/share_tree_share.glsl"
#include "vplkit/distribution/weights.glsl"

uint vplkit_load_share_tree_share(uint tree, uint node);
uint vplkit_share_tree_next_bits(uint tree);

// What the C++ share_tree<float> object knows besides its shares, passed by value:
//   id     : handed to the accessor;
//   size   : n (C++ size());
//   leaves : L (C++ leaf_count(); vplkit_share_tree_leaf_count(n));
//   total  : the root sum (C++ total(), sums[1]); the tree is empty unless 0 < total <= FLT_MAX
//            (a GPU build whose float sum overflowed writes +Inf there: sampled as empty).
struct vplkit_share_tree {
  uint id;
  uint size;
  uint leaves;
  float total;
};

bool vplkit_share_tree_empty(vplkit_share_tree t) {
  return !(t.total > 0.0 && t.total <= vplkit_FLT_MAX);
}

// The factor of going left (q 2^-24) or right ((2^24 - q) 2^-24) at `node`: exact.
float vplkit_share_tree_factor(vplkit_share_tree t, uint node, bool right) {
  uint q = vplkit_load_share_tree_share(t.id, node);
  return float(right ? vplkit_share_tree_one - q : q) * (1.0 / 16777216.0);
}

// C++ pmf(i): the product of the factors along i's path, root first.
float vplkit_share_tree_pmf(vplkit_share_tree t, uint index) {
  if (index >= t.size || vplkit_share_tree_empty(t)) return 0.0;
  float p = 1.0;
  uint k = 1u;
  for (uint half_leaves = t.leaves >> 1u; half_leaves > 0u; half_leaves >>= 1u) {
    bool right = (index & half_leaves) != 0u;
    p = vplkit_probability_product(p, vplkit_share_tree_factor(t, k, right));
    k = 2u * k + (right ? 1u : 0u);
  }
  return p;
}

// C++ sample(next24): one vplkit_share_tree_next_bits(t.id) per level (log2(leaves) of them,
// also when empty) against the node's share; {0, 0} when empty.
vplkit_discrete_sample vplkit_share_tree_sample(vplkit_share_tree t) {
  float p = 1.0;
  uint k = 1u;
  while (k < t.leaves) {
    uint b = vplkit_share_tree_next_bits(t.id);
    bool right = !(b < vplkit_load_share_tree_share(t.id, k));
    p = vplkit_probability_product(p, vplkit_share_tree_factor(t, k, right));
    k = 2u * k + (right ? 1u : 0u);
  }
  if (vplkit_share_tree_empty(t)) return vplkit_discrete_sample(0u, 0.0);
  return vplkit_discrete_sample(k - t.leaves, p);
}

#endif  // VPLKIT_DISTRIBUTION_SHARE_TREE_GLSL
