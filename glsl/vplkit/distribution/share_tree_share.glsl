// SPDX-License-Identifier: MIT
// vplkit GLSL pack: the share tree's grid, leaf count and quantised share, the part of
// include/vplkit/distribution/share_tree.hpp that both the sampler (share_tree.glsl) and the
// build kernel (share_tree_build.comp) use; a file of its own so that the build kernel need not
// define the sampler's accessor and hook (docs/glsl.md, "Accessors and Mesa's linker").
#ifndef VPLKIT_DISTRIBUTION_SHARE_TREE_SHARE_GLSL
#define VPLKIT_DISTRIBUTION_SHARE_TREE_SHARE_GLSL

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

#endif  // VPLKIT_DISTRIBUTION_SHARE_TREE_SHARE_GLSL
