// SPDX-License-Identifier: MIT
#pragma once
// Multiple importance sampling weights (Veach & Guibas 1995) for two strategies: n1 samples from
// density p1 and n2 from p2, both densities of the same point in the same measure (for vplkit:
// solid angle at the gather point, docs/math.md section 5; see pdf_conversion.hpp).
//
//   balance_heuristic(n1,p1,n2,p2) = n1 p1 / (n1 p1 + n2 p2)
//   power_heuristic(n1,p1,n2,p2)   = (n1 p1)^2 / ((n1 p1)^2 + (n2 p2)^2)        (beta = 2)
//   balance_combined(f,n1,p1,n2,p2) = f / (n1 p1 + n2 p2)
// balance_combined is the value every sample of either strategy adds to the estimate
//   F = sum_{j<n1} f(X1j)/(n1 p1 + n2 p2) + sum_{j<n2} f(X2j)/(n1 p1 + n2 p2)
// (balance weight times f / (n_i p_i); the per-strategy 1/n_i is already inside).
//
// None of them returns NaN, whatever the input:
// - counts that are not finite and > 0, and pdfs that are NaN or negative, count as 0; a strategy
//   with n = 0 has no term, whatever its pdf (so 0 * inf never happens);
// - both terms 0: weight 0 and balance_combined 0 (no strategy can produce the point);
// - an infinite pdf (a delta, or a VPL patch seen edge-on) outweighs every finite one (weight 1
//   against finite, 0 for the finite side); two infinite pdfs are weighed as equal densities, by
//   their counts: balance n1/(n1+n2), power n1^2/(n1^2+n2^2) (the limit p1 = p2 -> inf);
// - counts and pdfs below the smallest normal T count as 0 (the normal-range contract,
//   docs/math.md "GPU arithmetic model": a GPU may flush them on input);
// - each count and pdf is split into a mantissa in [1, 2) and a power of two, and the terms are
//   scaled by exact powers of two so that the larger lies in [1, 4) before anything is added,
//   squared or divided: tiny pdfs (whose squares would underflow) and huge ones (1e38, whose sums
//   or squares would overflow) give the same weights as moderate ones, and every division has a
//   divisor in [1, 32), where GLSL guarantees 2.5 ulp (a GPU may divide as a * (1 / b), whose
//   1 / b is a denormal for b > 2^126). A term below 2^-126 of the other is 0 (flushed, on every
//   device).
// Consequently heuristic(n1,p1,n2,p2) + heuristic(n2,p2,n1,p1) = 1 to within 2 ulps whenever at
// least one strategy has n > 0 and p > 0 (finite or not), and 0 when neither has.
// - every weight lies in [0, 1] on every device: the quotient a / (a + b) is at most 1 when the
//   division is correctly rounded, but a GPU's 2.5-ulp division (docs/math.md "GPU arithmetic
//   model") gives a / a = 1 + 2^-23 (NVIDIA H200: weights 1.0000001 wherever the other term is 0 or
//   negligible), so the quotient is capped at 1 (mis_unit_quotient). The cap never changes a
//   correctly rounded result.
#include <vplkit/core/normal_range.hpp>

#include <limits>
#include <type_traits>

namespace vplkit {

// Finite and at least the smallest normal T -> n, anything else (0, denormal, negative, NaN, inf)
// -> 0.
template <class T>
inline T mis_clean_count(T n) {
  return (n >= std::numeric_limits<T>::min() && n <= std::numeric_limits<T>::max()) ? n : T(0);
}

// At least the smallest normal T (+inf included) -> p; 0, denormal, negative, NaN -> 0.
template <class T>
inline T mis_clean_pdf(T p) {
  return p >= std::numeric_limits<T>::min() ? p : T(0);
}

// n * p = mantissa * 2^exponent with mantissa in [1, 4), for a cleaned count and a finite pdf;
// {0, 0} when either is 0. Exact products of mantissas: no over- or underflow whatever n and p.
template <class T>
inline binary_split<T> mis_term(T n, T p) {
  if (!(n > T(0)) || !(p > T(0))) return {T(0), 0};
  const binary_split<T> sn = split_binary(n), sp = split_binary(p);
  return {sn.mantissa * sp.mantissa, sn.exponent + sp.exponent};
}

// The two MIS terms n1 p1 and n2 p2 scaled by one common power of two so that the larger lies in
// [1, 4) (the other in [0, 4), 0 when it is below 2^-126 of the larger), or (0, 0) when both
// vanish. Infinite pdfs replace the finite ones: the terms become the counts of the infinite
// strategies, scaled likewise (the larger in [1, 2)).
template <class T>
struct mis_terms {
  T a;  // ~ n1 p1
  T b;  // ~ n2 p2
};

template <class T>
inline mis_terms<T> mis_scaled_terms(T n1, T p1, T n2, T p2) {
  const T inf = std::numeric_limits<T>::infinity();
  n1 = mis_clean_count(n1);
  n2 = mis_clean_count(n2);
  p1 = n1 > T(0) ? mis_clean_pdf(p1) : T(0);
  p2 = n2 > T(0) ? mis_clean_pdf(p2) : T(0);
  if (p1 == inf || p2 == inf) {
    const T a = p1 == inf ? n1 : T(0);
    const T b = p2 == inf ? n2 : T(0);
    const int k = -binary_exponent(a > b ? a : b);  // the larger count is > 0 here
    return {scale_by_exp2(a, k), scale_by_exp2(b, k)};
  }
  const binary_split<T> ta = mis_term(n1, p1), tb = mis_term(n2, p2);
  if (!(ta.mantissa > T(0)) && !(tb.mantissa > T(0))) return {T(0), T(0)};
  const int e = !(tb.mantissa > T(0))                       ? ta.exponent
                : !(ta.mantissa > T(0))                     ? tb.exponent
                : ta.exponent > tb.exponent ? ta.exponent : tb.exponent;
  return {scale_by_exp2(ta.mantissa, ta.exponent - e), scale_by_exp2(tb.mantissa, tb.exponent - e)};
}

// a / d for 0 <= a <= d, d > 0: the weight's quotient, capped at 1 (see the file comment).
template <class T> inline T mis_unit_quotient(T a, T d) {
  const T q = a / d;
  return q < T(1) ? q : T(1);
}

template <class T>
inline T balance_heuristic(T n1, T p1, T n2, T p2) {
  const mis_terms<T> t = mis_scaled_terms(n1, p1, n2, p2);
  const T d = t.a + t.b;  // 0 or in [1, 8)
  return d > T(0) ? mis_unit_quotient(t.a, d) : T(0);
}

template <class T>
inline T power_heuristic(T n1, T p1, T n2, T p2) {
  const mis_terms<T> t = mis_scaled_terms(n1, p1, n2, p2);
  // Squares of numbers in [0, 4): the larger's is in [1, 16), the other's is 0 where it falls
  // below the smallest normal T (a value that cannot matter next to the other's >= 1).
  const T a2 = flush_denormal(t.a * t.a), b2 = flush_denormal(t.b * t.b);
  const T d = a2 + b2;  // 0 or in [1, 32)
  return d > T(0) ? mis_unit_quotient(a2, d) : T(0);
}

// The denominator n1 p1 + n2 p2 of balance_combined as d * 2^e with d in [1, 8) (mis_scaled_terms's
// scaling); none (0) where both terms are 0 or a pdf is infinite.
template <class T>
struct mis_balance_denominator {
  T d = T(0);  // 0: none
  int e = 0;
};

template <class T>
inline mis_balance_denominator<T> balance_denominator(T n1, T p1, T n2, T p2) {
  const T inf = std::numeric_limits<T>::infinity();
  n1 = mis_clean_count(n1);
  n2 = mis_clean_count(n2);
  p1 = n1 > T(0) ? mis_clean_pdf(p1) : T(0);
  p2 = n2 > T(0) ? mis_clean_pdf(p2) : T(0);
  if (p1 == inf || p2 == inf) return {};
  const binary_split<T> ta = mis_term(n1, p1), tb = mis_term(n2, p2);
  if (!(ta.mantissa > T(0)) && !(tb.mantissa > T(0))) return {};
  const int e = !(tb.mantissa > T(0))   ? ta.exponent
                : !(ta.mantissa > T(0)) ? tb.exponent
                : ta.exponent > tb.exponent ? ta.exponent : tb.exponent;
  return {scale_by_exp2(ta.mantissa, ta.exponent - e) + scale_by_exp2(tb.mantissa, tb.exponent - e), e};
}

// f / (n1 p1 + n2 p2) with the denominator from balance_denominator: balance_combined's value, for
// several f over one denominator (the three channels of a sample) without recomputing it.
template <class T>
inline T balance_divide(T f, const mis_balance_denominator<T>& den) {
  const T big = std::numeric_limits<T>::max();
  if (!(den.d > T(0))) return T(0);
  // f as a mantissa in [1, 2) and a power of two too (an f below the smallest normal T is 0): the
  // quotient of the mantissas lies in (1/8, 2], so no denormal quotient loses bits before the
  // exact scaling. NaN and infinite f pass through to the guard below.
  f = flush_denormal(f);
  if (f == T(0)) return T(0);
  const T af = f < T(0) ? -f : f;
  const binary_split<T> sf = split_binary(af);
  const T q = scale_by_exp2(sf.mantissa / den.d, sf.exponent - den.e);
  const T r = f < T(0) ? -q : q;
  const T ar = r < T(0) ? -r : r;
  return ar <= big ? r : T(0);
}

// f / (n1 p1 + n2 p2), the balance-heuristic estimator's value for one sample of either strategy.
// 0 when the denominator is 0 (no strategy produces the point) or infinite (a delta pdf: the
// finite f of a continuous sample has measure zero next to it), and 0 when f is not finite or the
// quotient overflows — a guard against poisoning an image, reached only for samples of negligible
// probability. f may be negative (and counts as 0 below the smallest normal T). The denominator is
// d * 2^e with d in [1, 8) (mis_scaled_terms): one division of f's mantissa by d, then an exact
// power-of-two scaling, so an intermediate over- or underflows only when the result itself does;
// a result below the smallest normal T is 0.
//
// Host shortcut of balance_denominator and balance_divide (float and double, whose products, sum
// and quotient are correctly rounded; not a test's GPU model of float): the plain n1 p1 + n2 p2 and
// f / d, taken only where they are the scaled forms' bits. Rounding commutes with the scaling by a
// power of two wherever the value stays at least twice the smallest normal T (below that the
// denormal grid is coarser than a normal one's) and finite, so a term n p, the sum d and a quotient
// f / d in [2 min, max] are the scaled forms' mantissas at their exponents; a term below 2^-126 of
// the other, which the scaled sum drops, leaves the plain sum unrounded too (it is below half an
// ulp). Anything else (an infinite pdf, a term or quotient near the ends of the range, a NaN or
// infinite f) returns false: the general form runs. Compared over the whole range of magnitudes in
// tests/hardcases/mis_host_shortcut_hardcases_test.cpp, with IEEE arithmetic and under FTZ|DAZ.
namespace detail {
template <class T>
inline constexpr bool mis_host_arithmetic = std::is_same<T, float>::value || std::is_same<T, double>::value;

// n1 p1 + n2 p2 as a plain T in d (0 when both terms are), or false.
template <class T>
inline bool balance_denominator_plain(T n1, T p1, T n2, T p2, T& d) {
  constexpr T lo2 = T(2) * std::numeric_limits<T>::min(), big = std::numeric_limits<T>::max();
  n1 = mis_clean_count(n1);
  n2 = mis_clean_count(n2);
  p1 = n1 > T(0) ? mis_clean_pdf(p1) : T(0);
  p2 = n2 > T(0) ? mis_clean_pdf(p2) : T(0);
  if (!(p1 <= big) || !(p2 <= big)) return false;  // an infinite pdf
  // A term is 0 where a factor is (the cleaning above); a product that underflows to 0 is not.
  const T a = n1 * p1, b = n2 * p2;
  if ((p1 != T(0) && !(a >= lo2 && a <= big)) || (p2 != T(0) && !(b >= lo2 && b <= big))) return false;
  d = a + b;
  return d <= big;
}

// f / d for d from balance_denominator_plain (> 0) in q, or false.
template <class T>
inline bool balance_divide_plain(T f, T d, T& q) {
  constexpr T lo2 = T(2) * std::numeric_limits<T>::min(), big = std::numeric_limits<T>::max();
  f = flush_denormal(f);
  if (f == T(0)) {
    q = T(0);
    return true;
  }
  q = f / d;
  const T aq = q < T(0) ? -q : q;
  return aq >= lo2 && aq <= big;  // false for a NaN or infinite f too
}
}  // namespace detail

template <class T>
inline T balance_combined(T f, T n1, T p1, T n2, T p2) {
  if constexpr (detail::mis_host_arithmetic<T>) {
    T d, q;
    if (detail::balance_denominator_plain(n1, p1, n2, p2, d)) {
      if (!(d > T(0))) return T(0);
      if (detail::balance_divide_plain(f, d, q)) return q;
    }
  }
  return balance_divide(f, balance_denominator(n1, p1, n2, p2));
}

}  // namespace vplkit
