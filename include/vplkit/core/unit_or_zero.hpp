// SPDX-License-Identifier: MIT
#pragma once
// Normalisation that cannot produce NaN or Inf, shared by the paraboloid mapping and the VPL
// model (GLSL: vplkit_unit_or_zero).
#include <vplkit/core/normal_range.hpp>
#include <vplkit/core/vector.hpp>

#include <cmath>
#include <limits>
#include <type_traits>

// The shortcut of unit_or_zero is forced inline and its general path kept out of line (for float
// and double the rare branch), so that the estimators' per-candidate calls stay cheap.
#if defined(__GNUC__) || defined(__clang__)
#define VPLKIT_UNIT_OR_ZERO_COLD __attribute__((noinline, cold))
#define VPLKIT_UNIT_OR_ZERO_INLINE inline __attribute__((always_inline))
#else
#define VPLKIT_UNIT_OR_ZERO_COLD
#define VPLKIT_UNIT_OR_ZERO_INLINE inline
#endif

namespace vplkit {

// Largest absolute component (the L-infinity norm). NaN components are skipped by the
// comparisons, so a NaN vector gives 0 and is then treated as the zero vector.
template <class T>
inline T max_abs_component(vec3<T> v) {
  T m = T(0);
  if (detail::abs_of(v.x) > m) m = detail::abs_of(v.x);
  if (detail::abs_of(v.y) > m) m = detail::abs_of(v.y);
  if (detail::abs_of(v.z) > m) m = detail::abs_of(v.z);
  return m;
}

namespace detail {
// unit_or_zero's general path (every T, every magnitude): the power-of-two scaling first.
template <class T>
VPLKIT_UNIT_OR_ZERO_COLD inline vec3<T> unit_or_zero_scaled(vec3<T> v) {
  v = flush_denormal(v);
  const T m = max_abs_component(v);
  if (!(m > T(0)) || !(m <= std::numeric_limits<T>::max())) return vec3<T>(T(0));
  const int e = binary_exponent(m);
  const T scale = exp2i<T>(e < std::numeric_limits<T>::max_exponent - 2 ? -e : 2 - std::numeric_limits<T>::max_exponent);
  const vec3<T> s = flush_denormal(v * scale);
  // len2 is in [1, 48] unless a component of v was NaN. The test uses the looser [0.5, 64] so that
  // it stays a pure NaN check under GPU arithmetic (FMA contraction of the dot product).
  const T len2 = glm::dot(s, s);
  if (!(len2 >= T(0.5)) || !(len2 <= T(64))) return vec3<T>(T(0));
  // s * (1 / sqrt(len2)), the form of the GLSL (s * inversesqrt(len2)): two correctly rounded
  // operations here, inversesqrt and a product on a GPU.
  return flush_denormal(s * detail::inversesqrt_of(len2));
}
}  // namespace detail

// v / |v|, or (0,0,0) when v is zero or has a NaN or infinite component. A component below the
// smallest normal T counts as 0 (a GPU may flush it on input: docs/math.md, "GPU arithmetic
// model"), and so does one of the result. v is first scaled by the power of two that brings its
// largest component into [1, 2) ([2, 4) in the top binade, whose 2^-128 is no normal float): exact,
// so dot(s, s) neither underflows (|v| ~ 1e-30 in float squares to 0) nor overflows (|v| ~ 1e30,
// and FLT_MAX, square to Inf), and nothing divides by a huge |v| (a GPU may divide as
// a * (1 / b), and 1 / b is a denormal for b > 2^126). So any finite v with a normal component
// gives a unit vector, on every device.
//
// Host shortcut (float and double, whose sqrt and division are correctly rounded; not a test's GPU
// model of float): where the largest component lies in [2^-50, 2^60], the power-of-two scaling
// changes no bit of the result, so it is skipped. There the largest square is at least 2^-100, so
// every square that can move the sum (one not below half an ulp of the largest, 2^-124 or more) is
// a normal T with or without the scaling, and the others move it in neither; the scaling by 2^k
// commutes with the correctly rounded squares, sum, square root, reciprocal and product, so
// s * (1 / sqrt(dot(s, s))) = v * (1 / sqrt(dot(v, v))) bit for bit. A NaN component makes
// dot(v, v) NaN, which the range test rejects. (A float component 2^-10 below one of 2^-59 has a
// denormal square that does move the sum: hence 2^-50. Compared over exponents of the whole range
// in tests/hardcases/estimators_ris_mis_batch_hardcases_test.cpp.)
template <class T>
VPLKIT_UNIT_OR_ZERO_INLINE vec3<T> unit_or_zero(vec3<T> v) {
  if constexpr (std::is_same<T, float>::value || std::is_same<T, double>::value) {
    v = flush_denormal(v);
    const T m = max_abs_component(v);
    if (m >= T(0x1p-50) && m <= T(0x1p60)) {
      const T len2 = glm::dot(v, v);  // in [2^-100, 3 * 2^120] unless a component is NaN
      if (!(len2 >= T(0x1p-101)) || !(len2 <= T(0x1p122))) return vec3<T>(T(0));
      return flush_denormal(v * (T(1) / std::sqrt(len2)));
    }
  }
  return detail::unit_or_zero_scaled(v);
}

// |v| with the scale-first rule of unit_or_zero, for vectors of any magnitude. Where the largest
// component lies in [2^-50, 2^62] (float; [2^-483, 2^510] in double) it is sqrt(dot(v, v)), the
// bits of glm::length: every square a flushing device drops there is below half an ulp of the sum,
// and nothing overflows, so IEEE and flushing arithmetic give the same value. Elsewhere v is
// scaled first by the power of two that brings its largest component into [1, 2) ([2, 4) in the
// top binade), and the length of the scaled vector is scaled back (exact, or +Inf when |v| exceeds
// the largest T): sqrt(dot(v, v)) itself would be 0 or a denormal (a GPU flushes it) below 2^-63
// and Inf beyond 2^64. A component below the smallest normal T counts as 0 (0 for a vector of
// them); +Inf with an infinite component; NaN with a NaN one (0 if all are NaN).
template <class T>
inline T scaled_length(vec3<T> v) {
  using lim = std::numeric_limits<T>;
  v = flush_denormal(v);
  const T m = max_abs_component(v);
  if (!(m > T(0))) return T(0);
  if (!(m <= lim::max())) return lim::infinity();
  if (m >= exp2i<T>((lim::min_exponent - 1 + lim::digits + 2) / 2) && m <= exp2i<T>((lim::max_exponent - 4) / 2))
    return detail::sqrt_of(glm::dot(v, v));
  const int e = binary_exponent(m);
  const int k = e < lim::max_exponent - 2 ? -e : 2 - lim::max_exponent;
  const vec3<T> s = flush_denormal(v * exp2i<T>(k));
  // |s| >= 1 (its largest component is): the max only undoes a sqrt rounded below 1 (a GPU's may
  // be 4.5 ulp off), which scaled back by 2^-126 would be a denormal, flushed to 0.
  const T len = detail::sqrt_of(glm::dot(s, s));
  return (len > T(1) ? len : T(1)) * exp2i<T>(-k);
}

}  // namespace vplkit
