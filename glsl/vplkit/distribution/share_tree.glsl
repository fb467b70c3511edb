// SPDX-License-Identifier: MIT
// vplkit GLSL pack: sampling a share tree, one fresh 24-bit number per level; mirrors the sampling
// side of include/vplkit/distribution/share_tree.hpp (float). The arrays come from the C++
// share_tree<float> (upload shares(); sums() only for the total) or from the kernel
// share_tree_build.comp, in the same layout: shares[0 .. L - 1] of an implicit heap of
// L = vplkit_share_tree_leaf_count(n) leaves, node 1 the root. Draws and pmfs are the C++ ones bit
// for bit for the same stream: integer comparisons, exact factors, and the products through
// vplkit_probability_product (`precise`, 0 or a normal float). ACCESSOR
// vplkit_load_share_tree_share(tree, node), `tree` being the descriptor's id.
#ifndef VPLKIT_DISTRIBUTION_SHARE_TREE_GLSL
#define VPLKIT_DISTRIBUTION_SHARE_TREE_GLSL

#include "vplkit/distribution/discrete_sample.glsl"
#include "vplkit/distribution/weights.glsl"
#include "vplkit/sampling/rng.glsl"

uint vplkit_load_share_tree_share(uint tree, uint node);

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

const uint vplkit_share_tree_one = 16777216u;  // 2^24

// Leaves for n weights: the smallest power of two >= n (at least 1); n <= 2^31.
uint vplkit_share_tree_leaf_count(uint n) {
  uint m = 1u;
  while (m < n) m <<= 1u;
  return m;
}

// C++ share_tree_share: the left share of a node on the 2^24 grid, exactly, from the bits of its
// children sums (each 0 or a normal finite float). Integer long division, 8 bits per step.
uint vplkit_share_tree_share(float left, float right) {
  if (!(left > 0.0)) return 0u;
  if (!(right > 0.0)) return vplkit_share_tree_one;
  precise float sum = left + right;
  uint lb = floatBitsToUint(left);
  uint sb = floatBitsToUint(sum);
  int k0 = 24 + int(lb >> 23u) - int(sb >> 23u);
  uint q = 1u;
  if (k0 >= 0) {
    uint ml = (lb & 0x7fffffu) | 0x800000u;
    uint ms = (sb & 0x7fffffu) | 0x800000u;
    uint quotient = ml / ms;
    uint r = ml % ms;
    for (int k = k0; k > 0; k -= 8) {
      int c = min(k, 8);
      r <<= uint(c);
      quotient = (quotient << uint(c)) + r / ms;
      r %= ms;
    }
    q = quotient + (r != 0u ? 1u : 0u);
  }
  return min(q, vplkit_share_tree_one - 1u);
}

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

// C++ sample(counter_rng&): one vplkit_rng_next_u32 per level (log2(leaves) of them, also when
// empty), its top 24 bits against the node's share; {0, 0} when empty.
vplkit_discrete_sample vplkit_share_tree_sample(vplkit_share_tree t, inout vplkit_counter_rng rng) {
  float p = 1.0;
  uint k = 1u;
  while (k < t.leaves) {
    uint b = vplkit_rng_next_u32(rng) >> 8u;
    bool right = !(b < vplkit_load_share_tree_share(t.id, k));
    p = vplkit_probability_product(p, vplkit_share_tree_factor(t, k, right));
    k = 2u * k + (right ? 1u : 0u);
  }
  if (vplkit_share_tree_empty(t)) return vplkit_discrete_sample(0u, 0.0);
  return vplkit_discrete_sample(k - t.leaves, p);
}

#endif  // VPLKIT_DISTRIBUTION_SHARE_TREE_GLSL
