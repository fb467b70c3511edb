// SPDX-License-Identifier: MIT
#pragma once
// Keeping values in the normal range of T, so that the CPU templates and the GLSL pack
// (glsl/vplkit/core/normal_range.glsl) agree on every conforming GPU (docs/math.md, "GPU
// arithmetic model"). A GPU may flush any denormal input or result to 0 (GLSL 4.60 section 4.7.1,
// Vulkan "Precision and Operation of SPIR-V Instructions"), may evaluate a / b as a * (1 / b),
// whose 1 / b is itself a denormal for |b| > 2^126, and guarantees division only for |b| in
// [2^-126, 2^126]. So the library
//  - counts a value below the smallest normal T as 0 wherever a decision or a result depends on
//    it (flush_denormal: the same answer with IEEE arithmetic and with flush-to-zero /
//    denormals-are-zero, x86 MXCSR FTZ|DAZ or -ffast-math);
//  - scales by exact powers of two (binary_exponent, exp2i, scale_by_exp2) before it divides or
//    squares a quantity of unknown magnitude, so that every division has a divisor in [1, 2) or
//    another range the specifications cover.
#include <vplkit/core/vector.hpp>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <type_traits>
#include <utility>

namespace vplkit {

// +0 when |x| is below the smallest normal T (a denormal or a zero), else x (NaN and +-Inf
// included). Written as two comparisons with a normal constant: a denormal compares like 0 under
// denormals-are-zero and below min() under IEEE, so both give 0.
template <class T>
inline T flush_denormal(T x) noexcept {
  constexpr T lo = std::numeric_limits<T>::min();
  return (x < lo && x > -lo) ? T(0) : x;
}

namespace detail {
// std::sqrt and std::abs, or those of a float-like T found by argument-dependent lookup: the
// templates that take them this way also run with a test's GPU model of float arithmetic
// (tests/support/gpu_model_float.hpp), whose sqrt is not correctly rounded.
template <class T>
inline T sqrt_of(T x) {
  using std::sqrt;
  return sqrt(x);
}
template <class T>
inline T abs_of(T x) {
  using std::abs;
  return abs(x);
}
// 1 / sqrt(x), or a float-like T's own inversesqrt (found by argument-dependent lookup): the
// form the GLSL pack computes with (normalize, vplkit_unit_or_zero), so that a model of GLSL's
// inversesqrt sees the operation the GPU performs.
template <class T, class = void>
struct has_own_inversesqrt : std::false_type {};
template <class T>
struct has_own_inversesqrt<T, std::void_t<decltype(inversesqrt(std::declval<T>()))>> : std::true_type {};
template <class T>
inline T inversesqrt_of(T x) {
  if constexpr (has_own_inversesqrt<T>::value) {
    return inversesqrt(x);
  } else {
    return T(1) / sqrt_of(x);
  }
}
}  // namespace detail

// flush_denormal on each component.
template <class T>
inline vec3<T> flush_denormal(vec3<T> v) noexcept {
  return vec3<T>(flush_denormal(v.x), flush_denormal(v.y), flush_denormal(v.z));
}

namespace detail {
template <class T>
struct float_layout;
template <>
struct float_layout<float> {
  using bits = std::uint32_t;
  static constexpr int mantissa_bits = 23;
  static constexpr int bias = 127;
};
template <>
struct float_layout<double> {
  using bits = std::uint64_t;
  static constexpr int mantissa_bits = 52;
  static constexpr int bias = 1023;
};
}  // namespace detail

// floor(log2(x)) for a normal, finite, positive x (read from the exponent bits: exact, no libm).
template <class T>
inline int binary_exponent(T x) noexcept {
  using L = detail::float_layout<T>;
  typename L::bits b;
  std::memcpy(&b, &x, sizeof b);
  return int((b >> L::mantissa_bits) & typename L::bits(2 * L::bias + 1)) - L::bias;
}

// 2^k as T, exact, for k in [min_exponent - 1, max_exponent - 1] ([-126, 127] for float): the
// normal powers of two.
template <class T>
inline T exp2i(int k) noexcept {
  using L = detail::float_layout<T>;
  const typename L::bits b = typename L::bits(k + L::bias) << L::mantissa_bits;
  T x;
  std::memcpy(&x, &b, sizeof x);
  return x;
}

// The largest |k| that scale_by_exp2 takes: 378 for float (three factors of at most 2^126), 3066
// for double. Beyond it every normal x overflows or underflows anyway, and k is clamped.
template <class T>
inline constexpr int scale_by_exp2_max = 3 * (std::numeric_limits<T>::max_exponent - 2);

// x * 2^k as three multiplications by normal powers of two (a GPU may flush a single denormal
// factor 2^k), k clamped to +-scale_by_exp2_max<T>: exact whenever the result is a normal T (each
// partial product lies between x and the result); a result beyond the largest T overflows to
// +-Inf (correctly rounded products), one below the smallest normal T is 0 (flush_denormal: what
// a flushing GPU gives, on every device).
//
// Host shortcut (float and double, whose products are correctly rounded; not a test's GPU model of
// float): for k with 2^k a normal T, the single product x * 2^k. Its bits are the three products':
// where the result is normal or overflows, the partial products are exact and the last one rounds
// as the single product does; where it falls below the smallest normal T by more than its last
// factor, both flush to 0; and near the smallest normal the partial product before the last factor
// (2^k3, k3 <= -1 there) is at least twice the smallest normal, so exact again.
template <class T>
inline T scale_by_exp2(T x, int k) noexcept {
  if constexpr (std::is_same<T, float>::value || std::is_same<T, double>::value) {
    if (k >= std::numeric_limits<T>::min_exponent - 1 && k <= std::numeric_limits<T>::max_exponent - 1)
      return flush_denormal(x * exp2i<T>(k));
  }
  constexpr int kmax = scale_by_exp2_max<T>;
  k = k < -kmax ? -kmax : k > kmax ? kmax : k;
  const int k1 = k / 3;
  const int k2 = (k - k1) / 2;
  const int k3 = k - k1 - k2;
  const T y = x * exp2i<T>(k1);
  const T z = y * exp2i<T>(k2);
  return flush_denormal(z * exp2i<T>(k3));
}

// A positive normal finite x as m * 2^e with m in [1, 2) (exact): the mantissa and exponent that
// let a quotient of values of any magnitude be formed with a divisor in [1, 4).
template <class T>
struct binary_split {
  T mantissa;
  int exponent;
};
template <class T>
inline binary_split<T> split_binary(T x) noexcept {
  const int e = binary_exponent(x);
  return {scale_by_exp2(x, -e), e};
}

}  // namespace vplkit
