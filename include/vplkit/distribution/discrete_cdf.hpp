// SPDX-License-Identifier: MIT
#pragma once
// Discrete distribution sampled by inverse transform: a normalised CDF searched with a guide
// table (the cutpoint method of Chen & Asau 1974; Fishman & Moore 1984). Monotone in u, so it
// keeps the stratification of stratified or low-discrepancy u (the alias table does not).
//
// Stored arrays (uploadable to a GPU as they are):
//   cdf   : n + 1 values of T, cdf[0] = 0, cdf[n] = 1 exactly, non-decreasing; a zero weight
//           (or one below the smallest normal T) gives exactly equal neighbours cdf[i] ==
//           cdf[i + 1]. Every value is 0 or at least discrete_cdf_min_value<T>() (2^-103 for
//           float), so every pmf is 0 or normal (weights.hpp, the normal-range contract). An
//           empty distribution (all weights 0, or n = 0) stores n + 1 zeros, so cdf[n] == 0
//           marks it on the GPU too.
//   guide : m + 1 uint32, m = discrete_guide_size(n) a power of two;
//           guide[j] = the largest i in [0, n - 1] with cdf[i] <= j / m.
// Sampling returns the largest i with cdf[i] <= u. That bin has cdf[i + 1] > u >= cdf[i], so
// its width is positive: a zero weight is never returned, whatever u is.
#include <vplkit/core/prefetch.hpp>
#include <vplkit/distribution/discrete_sample.hpp>
#include <vplkit/distribution/weights.hpp>

#include <cstddef>
#include <cstdint>
#include <iterator>
#include <type_traits>
#include <utility>
#include <vector>

namespace vplkit {

// Guide table size for n weights: the smallest power of two >= n (at least 1). A power of two
// makes the bucket of u, floor(u * m), exact in T arithmetic (u * 2^k only shifts the exponent),
// which is what lets the guided search return exactly the index of a plain binary search. With
// m >= n a bucket holds on average at most one CDF step. Memory: 4 (m + 1) bytes, at most
// twice the CDF's.
inline std::size_t discrete_guide_size(std::size_t n) noexcept {
  std::size_t m = 1;
  while (m < n) m <<= 1;
  return m;
}

// Largest i in [lo, hi] with cdf[i] <= u, given cdf[lo] <= u and cdf non-decreasing.
// Branch-free halving: the comparison compiles to a conditional move, ceil(log2(hi - lo + 1))
// steps, and the loop reads the same way in GLSL.
template <class T>
inline std::size_t discrete_cdf_search(const T* cdf, std::size_t lo, std::size_t hi,
                                       T u) noexcept {
  std::size_t len = hi - lo + 1;
  while (len > 1) {
    const std::size_t half = len / 2;
    lo = cdf[lo + half] <= u ? lo + half : lo;
    len -= half;
  }
  return lo;
}

// Guided inverse transform on the stored arrays; u must already be clamped to [0, 1) and the
// distribution non-empty. u in [j/m, (j+1)/m) means cdf[guide[j]] <= j/m <= u, and no i above
// guide[j+1] has cdf[i] <= u < (j+1)/m: the answer lies in [guide[j], guide[j+1]].
// With m >= n most buckets hold at most 3 candidates (the counts are about Poisson(n / m)):
// two branch-free steps settle those, so the one branch left is well predicted; longer buckets
// (many tiny weights packed below one 1/m step) fall back to the halving search. The steps may
// look one past hi: cdf[hi + 1] exists (hi <= n - 1) and is > u (hi is the largest i with
// cdf[i] <= (j + 1) / m > u, and cdf[n] = 1 > u), so such a step never moves.
template <class T>
inline std::size_t discrete_cdf_sample_guided(const T* cdf, const std::uint32_t* guide,
                                              std::size_t m, T u) noexcept {
  // Exact: m is a power of two. Signed conversions: one instruction each on x86-64.
  const std::size_t j = std::size_t(std::int64_t(u * T(std::int64_t(m))));
  std::size_t lo = guide[j];
  const std::size_t hi = guide[j + 1];
  if (hi - lo > 3) return discrete_cdf_search(cdf, lo, hi, u);
  // Adding the comparison (0 or 1) keeps GCC from turning these selects into branches.
  const std::size_t c = lo + 2 < hi + 1 ? lo + 2 : hi + 1;
  lo += (c - lo) * std::size_t(cdf[c] <= u);
  lo += std::size_t(cdf[lo + 1] <= u);
  return lo;
}

template <class T>
class discrete_cdf {
  static_assert(std::is_same<T, float>::value || std::is_same<T, double>::value,
                "discrete_cdf<T> is defined for float and double");

public:
  using value_type = T;

  // Empty distribution: size 0, sample() returns {0, 0}.
  discrete_cdf() : cdf_(1, T(0)), guide_(2, 0u) {}

  // Throws invalid_input naming the first negative, NaN or infinite weight, when the double sum
  // overflows (double weights only), or when n > 2^32 - 1.
  discrete_cdf(const T* weights, std::size_t n) { build(weights, n); }

  // Any contiguous range of T: std::vector, std::array, a C array, a span.
  template <class Range,
            class = std::enable_if_t<detail::is_contiguous_range_of<Range, T>::value>>
  explicit discrete_cdf(const Range& weights)
      : discrete_cdf(static_cast<const T*>(std::data(weights)), std::size(weights)) {}

  // Rebuilds in place, reusing the storage (no allocation unless n grows): the way to rebuild a
  // CDF every frame. Same validation; on any exception the object is unchanged.
  void assign(const T* weights, std::size_t n) { build(weights, n); }
  template <class Range,
            class = std::enable_if_t<detail::is_contiguous_range_of<Range, T>::value>>
  void assign(const Range& weights) {
    build(static_cast<const T*>(std::data(weights)), std::size(weights));
  }

  // Zeroes negative / NaN / infinite weights instead of throwing, and counts them.
  static sanitized_distribution<discrete_cdf> sanitized(const T* weights, std::size_t n) {
    std::size_t zeroed = 0;
    const std::vector<T> w = detail::sanitized_weights("discrete_cdf", weights, n, &zeroed);
    return {discrete_cdf(w.data(), w.size()), zeroed};
  }
  template <class Range,
            class = std::enable_if_t<detail::is_contiguous_range_of<Range, T>::value>>
  static sanitized_distribution<discrete_cdf> sanitized(const Range& weights) {
    return sanitized(static_cast<const T*>(std::data(weights)), std::size(weights));
  }

  std::size_t size() const noexcept { return n_; }
  // Sum of the weights, accumulated in double and rounded once to T: +Inf for float weights that
  // sum past FLT_MAX (accepted: the CDF is normalised by the double sum()).
  T total() const noexcept { return total_; }
  // The same sum before that rounding: finite for every accepted input.
  double sum() const noexcept { return sum_; }
  bool empty() const noexcept { return total_ == T(0); }

  // Probability that sample() returns i: the width of bin i of the stored CDF, i.e. exactly
  // the fraction of [0, 1) that maps to i, up to the one rounding of this subtraction (correctly
  // rounded on every device). 0 for i >= size() and for an empty distribution; otherwise 0 or a
  // normal T. A positive weight too small to move
  // its CDF value (w_i / total below half an ulp of cdf[i + 1], e.g. 1e-30 beside 2; or a weight
  // below the smallest normal T; or a prefix sum below discrete_cdf_min_value of the total) gets a
  // bin of width 0: pmf 0, and sample() never returns it.
  T pmf(std::size_t i) const noexcept { return i < n_ ? cdf_[i + 1] - cdf_[i] : T(0); }

  // Inverse transform with the guide table. u NaN or < 0 is taken as 0, u >= 1 as the largest
  // T below 1. Returns the largest i with cdf[i] <= u and pmf(i); {0, 0} when empty().
  discrete_sample<T> sample(T u) const noexcept {
    if (empty()) return {0, T(0)};
    u = discrete_clamp_u(u);
    const std::size_t i = discrete_cdf_sample_guided(cdf_.data(), guide_.data(), m_, u);
    return {i, cdf_[i + 1] - cdf_[i]};
  }

  // Asks for the guide entries that sample(u) reads first (prefetch_read): for a caller that
  // knows several u before it samples them. No effect on any value.
  VPLKIT_PREFETCH_INLINE void prefetch_sample(T u) const noexcept {
    if (empty()) return;
    u = discrete_clamp_u(u);
    prefetch_read(guide_.data() + std::size_t(std::int64_t(u * T(std::int64_t(m_)))));
  }

  // The same index by a plain binary search over the whole CDF (no guide table).
  discrete_sample<T> sample_binary_search(T u) const noexcept {
    if (empty()) return {0, T(0)};
    u = discrete_clamp_u(u);
    const std::size_t i = discrete_cdf_search(cdf_.data(), 0, n_ - 1, u);
    return {i, cdf_[i + 1] - cdf_[i]};
  }

  // For upload: n + 1 CDF values, and guide_size() + 1 guide entries.
  const std::vector<T>& cdf() const noexcept { return cdf_; }
  const std::vector<std::uint32_t>& guide() const noexcept { return guide_; }
  std::size_t guide_size() const noexcept { return m_; }

private:
  void build(const T* w, std::size_t n) {
    detail::check_size("discrete_cdf", w, n);
    const detail::lane_partition lanes(n);
    const detail::lane_sums<T> sums = detail::checked_lane_sums("discrete_cdf", w, lanes);
    // Validated. reserve() is the last thing that can throw and changes no size, so a rejected
    // input or a failed allocation leaves the object as it was (strong guarantee).
    const std::size_t m = discrete_guide_size(n);
    cdf_.reserve(n + 1);
    guide_.reserve(m + 1);
    const double total = sums.total();
    n_ = n;
    sum_ = total;
    total_ = T(total);  // > 0 whenever total > 0: a sum of T values is >= the smallest of them
    m_ = m;
    cdf_.resize(n + 1);
    guide_.assign(m_ + 1, 0u);
    cdf_[0] = T(0);
    if (total == 0.0) {
      for (T& c : cdf_) c = T(0);
      return;
    }

    // Second pass: the same lane sums bit for bit (see detail::for_each_in_lanes), so the last
    // partial sum equals `total` and every partial sum that reached it maps to exactly 1.
    // The guide is counted on the way: guide[j] must end as the number of i in [1, n - 1] with
    // cdf[i] <= j / m, i.e. with ceil(cdf[i] * m) <= j (cdf[i] * m is exact: a power-of-two
    // scale). Histogram of ceil(cdf[i] * m) over i in [1, n], inclusive prefix sum, and
    // guide[m] set to n - 1 (it counted cdf[n] = 1 too); no data-dependent branch anywhere.
    const double md = double(m_);
    T* c = cdf_.data();
    std::uint32_t* g = guide_.data();
    // A value below discrete_cdf_min_value is stored as 0 (weights.hpp): every pmf is then 0 or
    // normal. The test is monotone in the value, so the CDF stays non-decreasing.
    auto store = [&](std::size_t i, T ci) {
      ci = ci >= discrete_cdf_min_value<T>() ? ci : T(0);
      c[i + 1] = ci;
      ++g[detail::ceil_to_size(double(ci) * md)];
    };
    detail::running_sum<T> acc[detail::kLanes];
    if constexpr (std::is_same<T, float>::value) {
      // Partial sums of floats in double are monotone as they are. Multiplying by 1/total
      // instead of dividing keeps the division off the loop: within 1.5 double ulps of the
      // quotient, far below the float rounding that follows, and monotone. A partial sum equal
      // to the total gives 1 - 2^-53, 1 or 1 + 2^-52: min() and the rounding to float make
      // every one of them exactly 1.
      const double inv = 1.0 / total;  // finite: a float total is >= 2^-149
      detail::for_each_in_lanes(lanes, [&](std::size_t k, std::size_t i) {
        acc[k].add(detail::weight_value(w[i]));  // as checked_lane_sums added it
        const double q = (sums.offset[k] + acc[k].value()) * inv;
        store(i, T(q < 1.0 ? q : 1.0));
      });
    } else {
      // Double: the correctly rounded prefix / total, with the running max guarding the
      // monotonicity that fl(sum + compensation) does not promise by itself.
      double lane_max[detail::kLanes] = {};
      detail::for_each_in_lanes(lanes, [&](std::size_t k, std::size_t i) {
        acc[k].add(detail::weight_value(w[i]));  // as checked_lane_sums added it
        const double v = acc[k].value();
        lane_max[k] = v > lane_max[k] ? v : lane_max[k];
        const double p = sums.offset[k] + lane_max[k];
        store(i, p >= total ? T(1) : T(p / total));
      });
    }
    c[n] = T(1);
    for (std::size_t j = 1; j <= m_; ++j) g[j] += g[j - 1];
    g[m_] = std::uint32_t(n - 1);
  }

  std::size_t n_ = 0;
  T total_ = T(0);
  double sum_ = 0.0;
  std::size_t m_ = 1;
  std::vector<T> cdf_;
  std::vector<std::uint32_t> guide_;
};

}  // namespace vplkit
