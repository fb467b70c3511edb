// SPDX-License-Identifier: MIT
#pragma once
// Walker's alias method, built with Vose's (1991) numerically stable O(n) algorithm in double.
// O(1) sampling: pick bucket j uniformly, keep j with probability threshold[j], else take
// alias[j]. Not monotone in u (neighbouring u land in unrelated buckets and the fraction decides
// between two unrelated indices), so it destroys the structure of stratified / low-discrepancy
// u; discrete_cdf keeps it. Prefer discrete_cdf there, and the alias table for independent u
// with large n where its single memory access wins.
//
// Stored array (uploadable to a GPU as it is): n bins {threshold, pmf, alias}; for T = float the
// bin is 12 bytes, std430-compatible with `struct { float threshold; float pmf; uint alias; }`.
//   threshold in [0, 1]: keep the bucket itself when the fraction f < threshold. A zero weight
//   has threshold exactly 0 (f < 0 never holds) and an alias whose weight is > 0, so it is never
//   returned, whatever u is. A full bucket has threshold 1 (f < 1 always holds).
//   pmf = w_i / total (rounded once to T): the pmf of the index i, not of the bucket. A positive
//   weight whose pmf is below the smallest normal T (w_i / total < 2^-126 for float, or a weight
//   that is itself below it) is built like a zero weight: threshold 0, never returned (its
//   threshold n w_i / total could survive as a denormal and hand out index i with pmf 0, an
//   infinite 1 / pmf, or read as 0 on a GPU). discrete_cdf drops it too. Every threshold and
//   pmf is 0 or a normal T (the normal-range contract of weights.hpp): a threshold below the
//   smallest normal T is stored as 0, which moves less than min() / n of probability to the
//   bucket's alias.
// An empty table (all weights 0, or n = 0) stores n bins {0, 0, 0}.
#include <vplkit/core/normal_range.hpp>
#include <vplkit/distribution/discrete_sample.hpp>
#include <vplkit/distribution/weights.hpp>

#include <cstddef>
#include <cstdint>
#include <iterator>
#include <type_traits>
#include <vector>

namespace vplkit {

template <class T>
struct alias_bin {
  T threshold;
  T pmf;
  std::uint32_t alias;
};
static_assert(sizeof(alias_bin<float>) == 12, "alias_bin<float> must match the std430 layout");

// Bucket j in [0, n - 1] and the kept-or-aliased decision, on the stored bins; f in [0, 1).
// Written as arithmetic on the comparison because f < threshold is a coin flip for a branch
// predictor and GCC turns the equivalent ternary into a branch.
template <class T>
inline std::size_t alias_table_pick(const alias_bin<T>* bins, std::size_t j, T f) noexcept {
  const std::size_t a = bins[j].alias;
  return a + (j - a) * std::size_t(f < bins[j].threshold);
}

// Bucket floor(x) of x = u * n, clamped to n - 1 (u * n may round up to n when n is not a
// power of two). Signed conversion: one instruction on x86-64.
template <class T>
inline std::size_t alias_table_bucket(T x, std::size_t n) noexcept {
  const std::size_t j = std::size_t(std::int64_t(x));
  return j < n ? j : n - 1;
}

template <class T>
class alias_table {
  static_assert(std::is_same<T, float>::value || std::is_same<T, double>::value,
                "alias_table<T> is defined for float and double");

public:
  using value_type = T;
  using bin = alias_bin<T>;

  alias_table() = default;

  // Same validation as discrete_cdf: invalid_input names the first negative, NaN or infinite
  // weight; also thrown when the double sum overflows (double weights only) or n > 2^32 - 1.
  alias_table(const T* weights, std::size_t n) { build(weights, n); }

  template <class Range,
            class = std::enable_if_t<detail::is_contiguous_range_of<Range, T>::value>>
  explicit alias_table(const Range& weights)
      : alias_table(static_cast<const T*>(std::data(weights)), std::size(weights)) {}

  // Rebuilds in place, reusing the bins' storage. On any exception the object is unchanged.
  void assign(const T* weights, std::size_t n) { build(weights, n); }
  template <class Range,
            class = std::enable_if_t<detail::is_contiguous_range_of<Range, T>::value>>
  void assign(const Range& weights) {
    build(static_cast<const T*>(std::data(weights)), std::size(weights));
  }

  static sanitized_distribution<alias_table> sanitized(const T* weights, std::size_t n) {
    std::size_t zeroed = 0;
    const std::vector<T> w = detail::sanitized_weights("alias_table", weights, n, &zeroed);
    return {alias_table(w.data(), w.size()), zeroed};
  }
  template <class Range,
            class = std::enable_if_t<detail::is_contiguous_range_of<Range, T>::value>>
  static sanitized_distribution<alias_table> sanitized(const Range& weights) {
    return sanitized(static_cast<const T*>(std::data(weights)), std::size(weights));
  }

  std::size_t size() const noexcept { return bins_.size(); }
  // The double sum of the weights rounded to T: +Inf for float weights that sum past FLT_MAX
  // (accepted: every pmf is computed from the double sum()).
  T total() const noexcept { return total_; }
  double sum() const noexcept { return sum_; }
  bool empty() const noexcept { return total_ == T(0); }

  // w_i / total, computed in double and rounded once to T; 0 for i >= size(). 0 also for a
  // positive weight whose quotient rounds to 0 in T: such an index is never returned.
  T pmf(std::size_t i) const noexcept { return i < bins_.size() ? bins_[i].pmf : T(0); }

  // One u for both decisions: x = u * n, bucket floor(x), fraction x - floor(x). The fraction
  // keeps only the bits of u below the bucket bits: with u on a 2^-24 grid (the float RNG
  // convention) it has 24 - log2(n) bits, so for n = 2^20 each threshold is effectively rounded
  // to a multiple of 1/16 and the realised pmf deviates from pmf(). Use sample(u1, u2) with two
  // independent numbers unless n is small. u is clamped as in discrete_cdf.
  discrete_sample<T> sample(T u) const noexcept {
    if (empty()) return {0, T(0)};
    const std::size_t n = bins_.size();
    const T x = discrete_clamp_u(u) * T(std::int64_t(n));
    const std::size_t j = alias_table_bucket(x, n);
    // x - j is exact (the fractional part of a float is a float); the clamp catches x = n.
    const T f = discrete_clamp_u(x - T(std::int64_t(j)));
    const std::size_t i = alias_table_pick(bins_.data(), j, f);
    return {i, bins_[i].pmf};
  }

  // u1 picks the bucket, u2 decides between the bucket and its alias: full precision.
  discrete_sample<T> sample(T u1, T u2) const noexcept {
    if (empty()) return {0, T(0)};
    const std::size_t n = bins_.size();
    const std::size_t j = alias_table_bucket(discrete_clamp_u(u1) * T(std::int64_t(n)), n);
    const std::size_t i = alias_table_pick(bins_.data(), j, discrete_clamp_u(u2));
    return {i, bins_[i].pmf};
  }

  const std::vector<bin>& bins() const noexcept { return bins_; }

private:
  void build(const T* w, std::size_t n) {
    detail::check_size("alias_table", w, n);
    const detail::lane_partition lanes(n);
    const double total = detail::checked_lane_sums("alias_table", w, lanes).total();
    // Every allocation happens before the first change of a member: on any exception the
    // object is unchanged (strong guarantee).
    bins_.reserve(n);
    std::vector<double> q(total == 0.0 ? 0 : n);
    std::vector<std::uint32_t> work(total == 0.0 ? 0 : n);
    sum_ = total;
    total_ = T(total);
    bins_.assign(n, bin{T(0), T(0), 0u});
    if (total == 0.0) return;

    // pmf_i = w_i / total and the scaled probabilities q_i = n * pmf_i (mean 1), in double.
    // T = double divides, so pmf is the correctly rounded quotient (and a denormal total, which
    // has no finite reciprocal, is no special case). T = float multiplies by 1/total: within
    // 1.5 double ulps, far below the float rounding of pmf.
    const double inv = 1.0 / total;  // finite for float: a float total is >= 2^-149
    const bool divide = std::is_same<T, double>::value;
    const double dn = double(n);
    // Worklist: small indices (q < 1) grow from the front, large ones from the back; the slots
    // between the two are free, which lets both pushes below be branch-free (q < 1 is a coin
    // flip the branch predictor cannot learn).
    std::size_t small_end = 0, large_begin = n;
    std::uint32_t any_positive = 0;  // an index with pmf > 0 (the largest weight has pmf >= 1/n)
    for (std::size_t i = 0; i < n; ++i) {
      const double p = divide ? double(detail::weight_value(w[i])) / total
                              : double(detail::weight_value(w[i])) * inv;
      bins_[i].pmf = flush_denormal(T(p));
      q[i] = bins_[i].pmf > T(0) ? p * dn : 0.0;
      const bool is_small = q[i] < 1.0;
      work[small_end] = std::uint32_t(i);
      work[large_begin - 1] = std::uint32_t(i);
      small_end += is_small ? 1 : 0;
      large_begin -= is_small ? 0 : 1;
      any_positive = bins_[i].pmf > T(0) ? std::uint32_t(i) : any_positive;
    }
    // Vose: pair a small bucket with a large index; the large one donates 1 - q_s and joins the
    // small list when it falls below 1. The excess is (q_l - 1) + q_s, exact while q_l <= 2
    // (Sterbenz), rather than (q_l + q_s) - 1. Only indices with q >= 1 (so pmf >= 1/n) ever
    // become aliases; a zero weight keeps threshold exactly q = 0, and so does an index whose pmf
    // was flushed (its q was set to 0 above: its alias gains nothing, the leftovers absorb the
    // missing q below n 2^-126).
    std::size_t small_begin = 0;
    while (small_begin < small_end && large_begin < n) {
      const std::uint32_t s = work[small_begin++];
      const std::uint32_t l = work[large_begin];
      bins_[s].threshold = bins_[s].pmf > T(0) ? flush_denormal(T(q[s])) : T(0);
      bins_[s].alias = l;
      q[l] = (q[l] - 1.0) + q[s];
      const bool demote = q[l] < 1.0;
      // Writing l at small_end is harmless when it is not demoted: that slot is free, or it is
      // large_begin itself, which holds l.
      large_begin += demote ? 1 : 0;
      work[small_end] = l;
      small_end += demote ? 1 : 0;
    }
    // Leftovers carry q = 1 up to rounding: they keep themselves. A zero weight (or pmf) left
    // over (only possible through rounding) must still never be returned: threshold 0, alias to
    // an index with pmf > 0.
    for (std::size_t k = large_begin; k < n; ++k) {
      bins_[work[k]].threshold = T(1);
      bins_[work[k]].alias = work[k];
    }
    for (std::size_t k = small_begin; k < small_end; ++k) {
      const std::uint32_t s = work[k];
      const bool zero = !(bins_[s].pmf > T(0));
      bins_[s].threshold = zero ? T(0) : T(1);
      bins_[s].alias = zero ? any_positive : s;
    }
  }

  T total_ = T(0);
  double sum_ = 0.0;
  std::vector<bin> bins_;
};

}  // namespace vplkit
