// SPDX-License-Identifier: MIT
#pragma once
// Shared by discrete_cdf and alias_table: weight validation, the sanitizing copy, the accurate
// running sum, and the clamp of a random number u into [0, 1).
//
// The normal-range contract (docs/math.md, "GPU arithmetic model"): a GPU may flush denormals,
// so every distribution counts a weight below the smallest normal T (FLT_MIN for float) as 0,
// stores no CDF value, threshold or pmf between 0 and the smallest normal T, and reads a u below
// it as 0. Each such test compares with a normal constant, which gives the same answer with IEEE
// arithmetic, with flush-to-zero / denormals-are-zero (x86 MXCSR FTZ|DAZ, -ffast-math) and on a
// GPU that flushes: zero weights are never picked and pmf(sample) == pmf(index) on every device.
#include <vplkit/core/error.hpp>
#include <vplkit/core/normal_range.hpp>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <limits>
#include <sstream>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace vplkit {

// What the `sanitized` factories return: the distribution built after every negative, NaN or
// infinite weight was replaced by 0, and how many weights were replaced.
template <class Distribution>
struct sanitized_distribution {
  Distribution distribution;
  std::size_t zeroed;
};

// Indices are stored as 32-bit unsigned integers (guide table, alias indices) so that the GPU
// can read the same arrays; a distribution therefore holds at most 2^32 - 1 weights.
inline constexpr std::size_t discrete_max_size = std::size_t(0xffffffffu);

// The largest T below 1: where u >= 1 is clamped, so that u * n < n and cdf[n] = 1 > u.
template <class T> inline constexpr T discrete_u_max();
template <> inline constexpr float discrete_u_max<float>() { return 0x1.fffffep-1f; }
template <> inline constexpr double discrete_u_max<double>() { return 0x1.fffffffffffffp-1; }

// u NaN, negative or below the smallest normal T -> 0 (written as !(u >= min) so that NaN takes
// this branch; GLSL's clamp leaves NaN undefined; a denormal u reads as 0 on a GPU that flushes,
// so it does everywhere), u >= 1 -> the largest T below 1. Every sampler applies this first.
template <class T>
inline T discrete_clamp_u(T u) noexcept {
  if (!(u >= std::numeric_limits<T>::min())) return T(0);
  return u < discrete_u_max<T>() ? u : discrete_u_max<T>();
}

// The smallest non-zero value a stored CDF holds: min() / epsilon() (2^-103 for float, 2^-970
// for double); a normalised prefix sum below it is stored as 0. Any two distinct stored values
// then differ by at least min() (their difference is a multiple of the smaller one's ulp, which
// is >= min()), so every pmf = cdf[i + 1] - cdf[i] is 0 or a normal T: the subtraction and every
// comparison with it give the same result on a GPU that flushes denormals. A weight whose share
// of the total is below this never moves the CDF (pmf 0, never sampled): far below the float
// resolution of any realistic distribution (2^-103 ~ 1e-31).
template <class T>
inline constexpr T discrete_cdf_min_value() noexcept {
  return std::numeric_limits<T>::min() / std::numeric_limits<T>::epsilon();
}

namespace detail {

// Any contiguous range of T: std::vector, std::array, a C array, a span (data() and size()).
template <class R, class T, class = void>
struct is_contiguous_range_of : std::false_type {};
template <class R, class T>
struct is_contiguous_range_of<
    R, T,
    std::void_t<decltype(std::data(std::declval<const R&>())),
                decltype(std::size(std::declval<const R&>()))>>
    : std::is_convertible<decltype(std::data(std::declval<const R&>())), const T*> {};

// True for negative, NaN and +-Inf; -0 and the negative denormals are valid (zero) weights: a
// denormal counts as 0 whatever its sign, and reads as -0 under denormals-are-zero, so rejecting
// it would depend on the floating-point mode.
template <class T>
inline bool is_bad_weight(T w) noexcept {
  return !(w > -std::numeric_limits<T>::min() && w <= std::numeric_limits<T>::max());
}

// The value a valid weight contributes: w, or 0 below the smallest normal T (see the top).
template <class T>
inline T weight_value(T w) noexcept {
  return w >= std::numeric_limits<T>::min() ? w : T(0);
}

template <class T>
[[noreturn]] inline void throw_bad_weight(const char* who, std::size_t i, T w) {
  std::ostringstream s;
  s.precision(std::numeric_limits<T>::max_digits10);
  s << who << ": weight[" << i << "] = " << w << " is "
    << (std::isnan(w) ? "NaN" : std::isinf(w) ? "infinite" : "negative")
    << "; weights must be finite and >= 0 (the sanitized() factory zeroes such weights)";
  throw invalid_input(s.str());
}

template <class T>
inline void check_size(const char* who, const T* w, std::size_t n) {
  static_assert(std::is_same<T, float>::value || std::is_same<T, double>::value,
                "vplkit distributions are defined for float and double");
  if (n > 0 && w == nullptr) {
    throw invalid_input(std::string(who) + ": null weight pointer with n = " + std::to_string(n));
  }
  if (n > discrete_max_size) {
    throw invalid_input(std::string(who) + ": " + std::to_string(n) +
                        " weights; at most 2^32 - 1 are supported (32-bit indices)");
  }
}

// Throws for the first bad weight. Called only after a cheap pass found one (or the sum
// overflowed), so the common path pays for no per-weight branch.
template <class T>
inline void find_and_throw_bad_weight(const char* who, const T* w, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i) {
    if (is_bad_weight(w[i])) throw_bad_weight(who, i, w[i]);
  }
}

// The running sum every distribution uses, written so that a second pass over the same weights
// reproduces every partial sum bit for bit (the normaliser must be exactly the last partial sum,
// so that cdf[n] == 1 and a zero-weight tail gets exactly equal CDF values).
//  - float weights: summed in double. A float has 24 significant bits and a double 53, so each
//    partial sum is within (n - 1) * 2^-53 relative of exact: below half a float ulp for
//    n < 2^28, and the sum never stalls (a float running sum stops growing once it reaches
//    2^24 times the weight: the tail of 2^24+ equal weights would get pmf 0).
//  - double weights: Neumaier's compensated sum (improved Kahan), so the error is about one
//    ulp independent of n. value() is fl(sum + compensation); the caller keeps the running max
//    because that rounding alone does not promise monotonicity.
// A zero weight leaves both members unchanged, so value() is unchanged: zero weights give
// exactly equal neighbours in the CDF.
template <class T> struct running_sum;

template <>
struct running_sum<float> {
  double sum = 0.0;
  void add(float w) noexcept { sum += double(w); }
  double value() const noexcept { return sum; }
};

template <>
struct running_sum<double> {
  double sum = 0.0, compensation = 0.0;
  void add(double w) noexcept {
    const double t = sum + w;
    // Neumaier: the rounding error of sum + w is exact as (big - t) + small.
    compensation += std::fabs(sum) >= std::fabs(w) ? (sum - t) + w : (w - t) + sum;
    sum = t;
  }
  double value() const noexcept { return sum + compensation; }
};

// The weights are summed in kLanes contiguous lanes (lane k covers [begin[k], begin[k+1])),
// interleaved so that the CPU overlaps kLanes independent add chains instead of waiting on one:
// a single running sum is bound by the add latency, ~4x slower to build. Lane k starts from 0,
// its partial sums are offset[k] + (lane running sum), offset[k + 1] = offset[k] + lane_total[k],
// so the last partial sum of a lane is bit for bit the next lane's offset and the last one of
// all is the total; pairwise-like summation is also more accurate than one long chain.
inline constexpr std::size_t kLanes = 4;

struct lane_partition {
  std::size_t begin[kLanes + 1];
  std::size_t common;  // every lane has at least this many weights (the last lane is shortest)
  explicit lane_partition(std::size_t n) noexcept {
    const std::size_t chunk = (n + kLanes - 1) / kLanes;
    for (std::size_t k = 0; k <= kLanes; ++k) begin[k] = k * chunk < n ? k * chunk : n;
    common = begin[kLanes] - begin[kLanes - 1];
  }
};

// Visits every weight lane by lane, each lane in increasing index order (interleaved across
// lanes for the first `common` steps, then each lane's rest); f(lane, index). Two visits run the
// same operations on every lane in the same order: that is what makes the partial sums of the
// CDF pass equal those of the total pass.
template <class F>
inline void for_each_in_lanes(const lane_partition& lanes, F&& f) {
  for (std::size_t t = 0; t < lanes.common; ++t) {
    for (std::size_t k = 0; k < kLanes; ++k) f(k, lanes.begin[k] + t);
  }
  for (std::size_t k = 0; k < kLanes; ++k) {
    for (std::size_t i = lanes.begin[k] + lanes.common; i < lanes.begin[k + 1]; ++i) f(k, i);
  }
}

// Lane totals (the running max of each lane's running sum: see running_sum) and their offsets;
// validates the weights on the way. Throws invalid_input naming the first negative / NaN /
// infinite weight, or when the double total overflows. That never happens for float weights
// (fewer than 2^32 of them, each at most FLT_MAX, sum to far less than DBL_MAX): a float total
// above FLT_MAX is accepted, every pmf is a well-defined double quotient rounded to float, and
// only total() (the sum rounded to T) reads +Inf.
template <class T>
struct lane_sums {
  double offset[kLanes + 1];  // offset[kLanes] is the total
  double total() const noexcept { return offset[kLanes]; }
};

template <class T>
inline lane_sums<T> checked_lane_sums(const char* who, const T* w, const lane_partition& lanes) {
  running_sum<T> acc[kLanes];
  double lane_max[kLanes] = {};
  bool valid[kLanes];
  for (std::size_t k = 0; k < kLanes; ++k) valid[k] = true;
  for_each_in_lanes(lanes, [&](std::size_t k, std::size_t i) {
    // Both comparisons always evaluated (an int &, not &&): no branch in the lane loop.
    valid[k] &= (static_cast<int>(w[i] > -std::numeric_limits<T>::min()) &
                 static_cast<int>(w[i] <= std::numeric_limits<T>::max())) != 0;
    acc[k].add(weight_value(w[i]));  // no branch: a select
    const double v = acc[k].value();
    lane_max[k] = v > lane_max[k] ? v : lane_max[k];
  });
  lane_sums<T> out;
  out.offset[0] = 0.0;
  bool all_valid = true, finite = true;
  for (std::size_t k = 0; k < kLanes; ++k) {
    out.offset[k + 1] = out.offset[k] + lane_max[k];
    all_valid &= valid[k];
    // A double lane that overflowed has an infinite sum (and a NaN value(), which the running
    // max skips): check each lane's own sum, not only the offsets.
    finite &= std::isfinite(acc[k].value());
  }
  if (!all_valid) find_and_throw_bad_weight(who, w, lanes.begin[kLanes]);
  if (!finite || !std::isfinite(out.total())) {
    throw invalid_input(std::string(who) +
                        ": the weights sum to more than the largest finite double; scale them down");
  }
  return out;
}

// Smallest integer >= x for 0 <= x < 2^62, without std::ceil (which needs SSE4.1 to be one
// instruction on x86-64; the baseline target calls libm).
inline std::size_t ceil_to_size(double x) noexcept {
  const std::int64_t k = std::int64_t(x);  // signed: one instruction, unsigned needs a branch
  return std::size_t(k + (double(k) < x ? 1 : 0));
}

// a * b for probabilities a, b >= 0, but the smallest normal T instead of a product below it
// when both are > 0: a product that underflows would turn a valid sample into a division by zero
// (and a denormal one reads as 0 on a GPU). Factors below the smallest normal T count as 0. The
// result is 0 or a normal T, the same with IEEE arithmetic and with flush-to-zero (a flushed
// product and a denormal one both become min(); so does one that a GPU flushes because its exact
// value is below min() although it rounds to min()). Any other product is left alone (1 * p stays
// p, so eps = 0 reproduces the learned pmf exactly).
template <class T>
inline T probability_product(T a, T b) noexcept {
  a = flush_denormal(a);
  b = flush_denormal(b);
  const T p = a * b;
  return p >= std::numeric_limits<T>::min() ? p
                                            : (a > T(0) && b > T(0)) ? std::numeric_limits<T>::min() : T(0);
}

// 1 / p for the rescaling of a reused u (mixture and roulette), computed in double and rounded
// once to T; 0 for p <= 0 (that branch is never taken), and capped at the largest finite T for
// a denormal p, so that u * scale is never Inf or NaN (the clamp of u then does the rest).
template <class T>
inline T reciprocal_or_zero(T p) noexcept {
  if (!(p > T(0))) return T(0);
  const double r = 1.0 / double(p);
  return r < double(std::numeric_limits<T>::max()) ? T(r) : std::numeric_limits<T>::max();
}

// Copy of the weights with every bad one replaced by 0; *zeroed = how many.
template <class T>
inline std::vector<T> sanitized_weights(const char* who, const T* w, std::size_t n,
                                        std::size_t* zeroed) {
  check_size(who, w, n);
  std::vector<T> out(w, w + n);
  std::size_t count = 0;
  for (T& x : out) {
    if (is_bad_weight(x)) {
      x = T(0);
      ++count;
    }
  }
  *zeroed = count;
  return out;
}

}  // namespace detail
}  // namespace vplkit
