// SPDX-License-Identifier: MIT
#pragma once
// Discrete distribution sampled by descending a binary tree of partial sums, one fresh 24-bit
// random number per level: the sampler whose draws do not move when the weights move by their
// last bits (docs/math.md, "Image parity at large DPRSMs"). A flat CDF's stored value i collects
// the rounding differences of every weight before it; here a weight difference moves only the
// shares on its own path, each by about the same relative amount.
//
// Tree (an implicit heap): L = share_tree_leaf_count(n) leaves, the smallest power of two >= n;
// node 1 is the root, node k has children 2k and 2k + 1, leaf i is node L + i. Stored arrays
// (uploadable to a GPU as they are; share_tree_build.comp writes the same bits):
//   sums   : 2L floats; sums[L + i] = weight i (0 below the smallest normal float, and for the
//            padding leaves i >= n), sums[k] = fl(sums[2k] + sums[2k + 1]) (one float add, in
//            this order), sums[0] = 0. sums[1] is the total.
//   shares : L uint32; inner node k in [1, L) stores its left share on the 2^24 grid of the
//            RNG's numbers, q = ceil(sums[2k] / sums[k] * 2^24) computed exactly from the bits of
//            the two floats (share_tree_share: integer arithmetic only), then: 0 when the left sum
//            is 0, 2^24 when the right sum is 0, otherwise clamped to [1, 2^24 - 1] so that
//            both sides stay drawable however tiny one is against the other. shares[0] = 0.
// Why this layout: the build is a bottom-up reduction in log2(L) levels, and level l is the
// contiguous range [2^l, 2^(l+1)): on a GPU adjacent invocations read adjacent child pairs and
// write adjacent parents (coalesced), and no index arithmetic beyond shifts is needed. Sampling
// reads one share per level; the top levels are the first few cache lines, shared by every
// invocation and kept in cache. Padding to a power of two gives every leaf the same depth, so
// every draw consumes the same count of numbers (depth()), whatever index it lands on.
//
// Sampling: at node k take a fresh 24-bit number b (the RNG's top 24 bits, rng_next_u32 >> 8),
// go left when b < q[k]. Then pmf(i) = prod (q or 2^24 - q) 2^-24 along i's path is exactly the
// probability of drawing i, given independent uniform numbers; the returned float is that
// product rounded once per level (at most depth() float roundings, ~depth() 2^-24 relative),
// and it is bit for bit what pmf(i) returns, on the CPU and in share_tree.glsl. A zero weight has
// a factor 0 on its path and is never drawn; every positive weight has a positive probability.
// No invert(): a draw is depth() numbers, not one u, so there is no monotone map to hand back.
//
// The normal-range contract (weights.hpp): weights below FLT_MIN count as 0, a negative, NaN or
// infinite weight throws (sanitized() zeroes it), -0 and negative denormals are valid zeros.
// Every node sum is 0 or a sum of normal floats (a normal float), so FTZ/DAZ cannot change a sum,
// and the shares are integer functions of the sums: the arrays are the same bits with IEEE
// arithmetic, under FTZ|DAZ, and from share_tree_build.comp on any GPU that rounds float addition
// correctly (GLSL's `precise` +), with no ulp residual from division (there is none). The product
// in pmf uses probability_product: 0 or a normal float on every device.
// Float only: the tree's sums must be float to be reproduced by the GPU build bit for bit.
#include <vplkit/core/error.hpp>
#include <vplkit/distribution/discrete_sample.hpp>
#include <vplkit/distribution/weights.hpp>

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <iterator>
#include <limits>
#include <string>
#include <type_traits>
#include <vector>

namespace vplkit {

// The grid of the shares and of the level numbers: 2^24, the RNG's float resolution.
inline constexpr std::uint32_t share_tree_one = 1u << 24;

// Leaves for n weights: the smallest power of two >= n (at least 1).
inline std::size_t share_tree_leaf_count(std::size_t n) noexcept {
  std::size_t m = 1;
  while (m < n) m <<= 1;
  return m;
}

// Levels (numbers consumed per draw): log2(leaf_count).
inline unsigned share_tree_depth(std::size_t leaves) noexcept {
  unsigned d = 0;
  while ((std::size_t(1) << d) < leaves) ++d;
  return d;
}

// The quantised left share of a node with children sums `left` and `right` (each 0 or a normal,
// finite float; sum = fl(left + right) as stored): 0 when left == 0, 2^24 when right == 0,
// otherwise ceil(left / sum * 2^24) clamped to [1, 2^24 - 1]. Exact: with left = ml 2^el and
// sum = ms 2^es (ml, ms the 24-bit significands) the quotient is ml 2^(24 + el - es) / ms, a
// long division in 32-bit integers (8 bits per step, remainders < 2^24 so r << 8 fits). A
// float division could differ between devices (GLSL allows 2.5 ulp) and flip the ceiling
// where the quotient is near a grid point; integer arithmetic cannot. share_tree.glsl's
// vplkit_share_tree_share is this function, step for step.
inline std::uint32_t share_tree_share(float left, float right) noexcept {
  if (!(left > 0.0f)) return 0u;
  if (!(right > 0.0f)) return share_tree_one;
  const float sum = left + right;  // >= left: addition of a positive value rounds monotonically
  std::uint32_t lb, sb;
  std::memcpy(&lb, &left, 4);
  std::memcpy(&sb, &sum, 4);
  const int k0 = 24 + int(lb >> 23) - int(sb >> 23);  // 24 + el - es, <= 24
  std::uint32_t q = 1u;  // k0 < 0: the quotient is below 1/2 (ml / ms < 2), its ceiling 1
  if (k0 >= 0) {
    const std::uint32_t ml = (lb & 0x7fffffu) | 0x800000u, ms = (sb & 0x7fffffu) | 0x800000u;
    std::uint32_t quotient = ml / ms, r = ml % ms;
    for (int k = k0; k > 0; k -= 8) {
      const int c = k < 8 ? k : 8;
      r <<= unsigned(c);
      quotient = (quotient << unsigned(c)) + r / ms;
      r %= ms;
    }
    q = quotient + (r != 0u ? 1u : 0u);
  }
  return q < share_tree_one - 1u ? q : share_tree_one - 1u;
}

template <class T>
class share_tree {
  static_assert(std::is_same<T, float>::value,
                "share_tree<T> is defined for float (the GPU build reproduces its float sums)");

public:
  using value_type = T;

  // Empty distribution: size 0, sample() returns {0, 0}.
  share_tree() : sums_(2, 0.0f), shares_(1, 0u) {}

  // Throws invalid_input naming the first negative, NaN or infinite weight, when the float sum of
  // the weights overflows (the tree's sums are floats: scale the weights down), or when
  // n > 2^31 (2L node indices must fit 32 bits).
  share_tree(const T* weights, std::size_t n) { build(weights, n); }

  template <class Range,
            class = std::enable_if_t<detail::is_contiguous_range_of<Range, T>::value>>
  explicit share_tree(const Range& weights)
      : share_tree(static_cast<const T*>(std::data(weights)), std::size(weights)) {}

  // Rebuilds from new weights. Same validation; on any exception the object is unchanged (the
  // arrays are built aside and swapped in).
  void assign(const T* weights, std::size_t n) { build(weights, n); }

  // Zeroes negative / NaN / infinite weights instead of throwing, and counts them.
  static sanitized_distribution<share_tree> sanitized(const T* weights, std::size_t n) {
    std::size_t zeroed = 0;
    const std::vector<T> w = detail::sanitized_weights("share_tree", weights, n, &zeroed);
    return {share_tree(w.data(), w.size()), zeroed};
  }
  template <class Range,
            class = std::enable_if_t<detail::is_contiguous_range_of<Range, T>::value>>
  static sanitized_distribution<share_tree> sanitized(const Range& weights) {
    return sanitized(static_cast<const T*>(std::data(weights)), std::size(weights));
  }

  std::size_t size() const noexcept { return n_; }
  std::size_t leaf_count() const noexcept { return leaves_; }
  // Numbers one draw consumes: log2(leaf_count()), 0 for n <= 1.
  unsigned depth() const noexcept { return depth_; }
  // The root's sum: the float pairwise sum of the weights (finite for every accepted input).
  T total() const noexcept { return sums_[1]; }
  bool empty() const noexcept { return !(total() > 0.0f); }

  // Probability that sample() returns i: the product of the factors q 2^-24 (left) or
  // (2^24 - q) 2^-24 (right) along i's path from the root, multiplied in that order with
  // probability_product (0 or a normal float). Bit for bit the pmf sample() returns with i.
  // 0 for i >= size() and for an empty distribution.
  T pmf(std::size_t i) const noexcept {
    if (i >= n_ || empty()) return 0.0f;
    float p = 1.0f;
    std::size_t k = 1;
    for (unsigned l = depth_; l-- > 0;) {
      const bool right = ((i >> l) & 1u) != 0;
      p = detail::probability_product(p, factor(k, right));
      k = 2 * k + (right ? 1 : 0);
    }
    return p;
  }

  // One draw from numbers given by `next24()`: called exactly depth() times, root first, each
  // call returning a uniform integer in [0, 2^24) (more bits are an error: only the low 24 are
  // meaningful, values >= 2^24 always go right). A functor rather than one u: each level needs a
  // fresh number (deriving them from one 24-bit u leaves ~2^24 / n values per bin, so the
  // probability of a bin would be a count, not the product pmf() returns); a functor keeps the
  // order of consumption explicit and lets the caller pass its own stream without this layer
  // depending on the sampling layer. With the project's RNG (sampling/rng.hpp), the numbers the
  // GPU draws too: sample([&] { return rng_next_u32(rng) >> 8u; }) (the 24 bits
  // uint_to_unit_float keeps); share_tree.glsl's hook vplkit_share_tree_next_bits is this functor. An empty distribution still consumes depth() numbers and returns {0, 0}: a
  // stream advances by the same count on every path and device.
  template <class NextBits>
  discrete_sample<T> sample(NextBits&& next24) const {
    float p = 1.0f;
    std::size_t k = 1;
    for (unsigned l = 0; l < depth_; ++l) {
      const std::uint32_t b = std::uint32_t(next24());
      const bool right = !(b < shares_[k]);
      p = detail::probability_product(p, factor(k, right));
      k = 2 * k + (right ? 1 : 0);
    }
    if (empty()) return {0, 0.0f};
    return {k - leaves_, p};
  }

  // For upload: 2 leaf_count() sums and leaf_count() shares (see the top of this file).
  const std::vector<float>& sums() const noexcept { return sums_; }
  const std::vector<std::uint32_t>& shares() const noexcept { return shares_; }

private:
  // Exact: q and 2^24 - q are below 2^25, and the scale is a power of two.
  float factor(std::size_t k, bool right) const noexcept {
    const std::uint32_t q = shares_[k];
    return float(right ? share_tree_one - q : q) * (1.0f / 16777216.0f);
  }

  void build(const T* w, std::size_t n) {
    detail::check_size("share_tree", w, n);
    if (n > (std::size_t(1) << 31)) {
      throw invalid_input("share_tree: " + std::to_string(n) +
                          " weights; at most 2^31 are supported (2 x leaves node indices in 32 bits)");
    }
    for (std::size_t i = 0; i < n; ++i) {
      if (detail::is_bad_weight(w[i])) detail::throw_bad_weight("share_tree", i, w[i]);
    }
    const std::size_t leaves = share_tree_leaf_count(n);
    std::vector<float> sums(2 * leaves, 0.0f);
    std::vector<std::uint32_t> shares(leaves, 0u);
    for (std::size_t i = 0; i < n; ++i) sums[leaves + i] = detail::weight_value(w[i]);
    for (std::size_t k = leaves - 1; k >= 1; --k) {
      const float left = sums[2 * k], right = sums[2 * k + 1];
      sums[k] = left + right;
      shares[k] = share_tree_share(left, right);
    }
    if (!(sums[1] <= std::numeric_limits<float>::max())) {
      throw invalid_input("share_tree: the weights' float sum overflows (the tree's sums are "
                          "floats, as in the GPU build); scale the weights down");
    }
    sums_.swap(sums);
    shares_.swap(shares);
    n_ = n;
    leaves_ = leaves;
    depth_ = share_tree_depth(leaves);
  }

  std::size_t n_ = 0;
  std::size_t leaves_ = 1;
  unsigned depth_ = 0;
  std::vector<float> sums_;
  std::vector<std::uint32_t> shares_;
};

}  // namespace vplkit
