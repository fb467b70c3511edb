// SPDX-License-Identifier: MIT
// vplkit GLSL pack: multiple importance sampling weights for two strategies (n1 samples of
// density p1, n2 of p2, both densities of the same point in the same measure: solid angle at the
// gather point, docs/math.md section 5); the float mirror of include/vplkit/mis/heuristics.hpp
// (docs/api/mis.md, docs/glsl/mis.md).
//   vplkit_balance_heuristic(n1,p1,n2,p2)   = n1 p1 / (n1 p1 + n2 p2)
//   vplkit_power_heuristic(n1,p1,n2,p2)     = (n1 p1)^2 / ((n1 p1)^2 + (n2 p2)^2)
//   vplkit_balance_combined(f,n1,p1,n2,p2)  = f / (n1 p1 + n2 p2)
// Never NaN: invalid counts (not finite and > 0) and pdfs (NaN, <= 0) count as 0; a strategy with
// n = 0 has no term; both terms 0 -> 0; an infinite pdf outweighs every finite one; two infinite
// pdfs are weighed by their counts; counts and pdfs below the smallest normal float count as 0;
// each term is formed from the mantissas and exponents of its count and pdf and scaled by exact
// powers of two so that the larger lies in [1, 4) before anything is added, squared or divided
// (tiny and huge pdfs give the weights of moderate ones, and every division has a divisor in
// [1, 32), where GLSL promises 2.5 ulp). +inf is uintBitsToFloat(0x7F800000u) and is tested with
// `==`, as in the C++.
//
// Every weight lies in [0, 1] on every device: its quotient is capped at 1
// (vplkit_mis_unit_quotient), since a 2.5-ulp division may return 1 + 2^-23 for a / a.
// GLSL-only additions (the rest reads line for line like the C++):
// - vplkit_mis_is_nan(x) decides NaN on the bits, and guards every place where the C++ relies on
//   a comparison being false for NaN: compilers may fold such comparisons into min/max, which drop
//   a NaN (docs/glsl.md, "NaN, FMA and compiler rewrites"), so the C++ form alone lets NaN through.
// - vplkit_mis_div(x, y): x / y for a divisor that may lie outside [2^-126, 2^126] (the
//   heuristics no longer need it: their divisors lie in [1, 32); kept for callers).
// Every input and result below the smallest normal float is 0 on both sides (the normal-range
// contract, docs/math.md "GPU arithmetic model"), so a GPU that flushes denormals computes what
// the C++ computes.
#ifndef VPLKIT_MIS_HEURISTICS_GLSL
#define VPLKIT_MIS_HEURISTICS_GLSL

#include "vplkit/core/constants.glsl"
#include "vplkit/core/normal_range.glsl"

// x / y for any y. GLSL 4.30 (section 4.7.1) specifies x / y (to 2.5 ulp) only for |y| in
// [2^-126, 2^126]: GPUs divide through a reciprocal, which flushes to 0 above 2^126 (there
// 1e38 / 1e38 would give 0, and 0 / 0 one step later) and overflows below 2^-126. Multiplying x
// and y by one power of two brings y into that range without changing the quotient: the
// products are exact except where |x| drops below 2^-94 (then |x / y| < 2^-220, 0 either way) or
// overflows (then |x / y| > 2^222, inf either way). On a device that flushes denormals, a
// denormal y becomes 0 here; the callers only divide by values that passed a `> 0.0` test, which
// such a device evaluates on the flushed value.
float vplkit_mis_div(float x, float y) {
  float ay = abs(y);
  if (ay >= 85070591730234615865843651857942052864.0) {  // 2^126
    x *= 2.3283064365386962890625e-10;                   // 2^-32
    y *= 2.3283064365386962890625e-10;
  } else if (ay < vplkit_FLT_MIN) {
    x *= 4294967296.0;  // 2^32
    y *= 4294967296.0;
  }
  return x / y;
}

// GLSL-only: NaN, decided on the bits (any exponent-all-ones pattern with a non-zero mantissa).
bool vplkit_mis_is_nan(float x) { return vplkit_is_nan(x); }

// Finite and at least the smallest normal float -> n, anything else (0, denormal, negative, NaN,
// inf) -> 0.
float vplkit_mis_clean_count(float n) {
  return (n >= vplkit_FLT_MIN && n <= vplkit_FLT_MAX && !vplkit_mis_is_nan(n)) ? n : 0.0;
}

// At least the smallest normal float (+inf included) -> p; 0, denormal, negative, NaN -> 0.
float vplkit_mis_clean_pdf(float p) {
  return (p >= vplkit_FLT_MIN && !vplkit_mis_is_nan(p)) ? p : 0.0;
}

// n * p = mantissa * 2^exponent, mantissa in [1, 4), for a cleaned count and a finite pdf;
// mantissa 0 when either is 0 (C++ mis_term).
vplkit_binary_split vplkit_mis_term(float n, float p) {
  if (!(n > 0.0) || !(p > 0.0)) return vplkit_binary_split(0.0, 0);
  vplkit_binary_split sn = vplkit_split_binary(n);
  vplkit_binary_split sp = vplkit_split_binary(p);
  precise float m = sn.mantissa * sp.mantissa;
  return vplkit_binary_split(m, sn.exponent + sp.exponent);
}

// The exponent both terms are scaled by: the larger term's (C++ mis_scaled_terms).
int vplkit_mis_common_exponent(vplkit_binary_split ta, vplkit_binary_split tb) {
  if (!(tb.mantissa > 0.0)) return ta.exponent;
  if (!(ta.mantissa > 0.0)) return tb.exponent;
  return max(ta.exponent, tb.exponent);
}

// The two MIS terms n1 p1 and n2 p2 scaled by one common power of two so that the larger lies in
// [1, 4) (the other 0 below 2^-126 of it), or (0, 0) when both vanish. Infinite pdfs replace the
// finite ones: the terms become the counts of the infinite strategies, scaled likewise.
struct vplkit_mis_terms {
  float a;  // ~ n1 p1
  float b;  // ~ n2 p2
};

vplkit_mis_terms vplkit_mis_scaled_terms(float n1, float p1, float n2, float p2) {
  float inf = uintBitsToFloat(0x7F800000u);
  n1 = vplkit_mis_clean_count(n1);
  n2 = vplkit_mis_clean_count(n2);
  p1 = n1 > 0.0 ? vplkit_mis_clean_pdf(p1) : 0.0;
  p2 = n2 > 0.0 ? vplkit_mis_clean_pdf(p2) : 0.0;
  if (p1 == inf || p2 == inf) {
    float a = p1 == inf ? n1 : 0.0;
    float b = p2 == inf ? n2 : 0.0;
    int k = -vplkit_binary_exponent(max(a, b));  // the larger count is > 0 here
    return vplkit_mis_terms(vplkit_scale_by_exp2(a, k), vplkit_scale_by_exp2(b, k));
  }
  vplkit_binary_split ta = vplkit_mis_term(n1, p1);
  vplkit_binary_split tb = vplkit_mis_term(n2, p2);
  if (!(ta.mantissa > 0.0) && !(tb.mantissa > 0.0)) return vplkit_mis_terms(0.0, 0.0);
  int e = vplkit_mis_common_exponent(ta, tb);
  return vplkit_mis_terms(vplkit_scale_by_exp2(ta.mantissa, ta.exponent - e),
                          vplkit_scale_by_exp2(tb.mantissa, tb.exponent - e));
}

// a / d for 0 <= a <= d, d > 0, capped at 1: GLSL's 2.5-ulp division may give a / a = 1 + 2^-23
// (NVIDIA does), and a weight must stay in [0, 1] (C++ mis_unit_quotient). d in [1, 32) and a
// finite: the quotient is never NaN, so min() cannot drop one.
float vplkit_mis_unit_quotient(float a, float d) {
  float q = a / d;
  return q < 1.0 ? q : 1.0;
}

float vplkit_balance_heuristic(float n1, float p1, float n2, float p2) {
  vplkit_mis_terms t = vplkit_mis_scaled_terms(n1, p1, n2, p2);
  float d = t.a + t.b;  // 0 or in [1, 8)
  return d > 0.0 ? vplkit_mis_unit_quotient(t.a, d) : 0.0;
}

float vplkit_power_heuristic(float n1, float p1, float n2, float p2) {
  vplkit_mis_terms t = vplkit_mis_scaled_terms(n1, p1, n2, p2);
  // precise: each square is rounded (and flushed below FLT_MIN) before the sum, as in the C++.
  precise float a2 = vplkit_flush_denormal(t.a * t.a);
  precise float b2 = vplkit_flush_denormal(t.b * t.b);
  precise float d = a2 + b2;  // 0 or in [1, 32)
  return d > 0.0 ? vplkit_mis_unit_quotient(a2, d) : 0.0;
}

// f / (n1 p1 + n2 p2), the balance-heuristic estimator's value for one sample of either strategy.
// 0 when the denominator is 0 or infinite, and 0 when f is not finite or the quotient overflows
// (a guard against poisoning an image, reached only for samples of negligible probability).
// f may be negative (0 below the smallest normal float). The denominator is d * 2^e with d in
// [1, 8): one division of f's mantissa by d, then an exact scaling; a result below the smallest
// normal float is 0.
float vplkit_balance_combined(float f, float n1, float p1, float n2, float p2) {
  float inf = uintBitsToFloat(0x7F800000u);
  float big = vplkit_FLT_MAX;
  n1 = vplkit_mis_clean_count(n1);
  n2 = vplkit_mis_clean_count(n2);
  p1 = n1 > 0.0 ? vplkit_mis_clean_pdf(p1) : 0.0;
  p2 = n2 > 0.0 ? vplkit_mis_clean_pdf(p2) : 0.0;
  if (p1 == inf || p2 == inf) return 0.0;
  vplkit_binary_split ta = vplkit_mis_term(n1, p1);
  vplkit_binary_split tb = vplkit_mis_term(n2, p2);
  if (!(ta.mantissa > 0.0) && !(tb.mantissa > 0.0)) return 0.0;
  int e = vplkit_mis_common_exponent(ta, tb);
  precise float d = vplkit_scale_by_exp2(ta.mantissa, ta.exponent - e) +
                    vplkit_scale_by_exp2(tb.mantissa, tb.exponent - e);
  // f's mantissa over d (in (1/8, 2]), then the exact power of two, as in the C++.
  f = vplkit_flush_denormal(f);
  if (f == 0.0) return 0.0;
  vplkit_binary_split sf = vplkit_split_binary(abs(f));
  float q = vplkit_scale_by_exp2(sf.mantissa / d, sf.exponent - e);
  float r = f < 0.0 ? -q : q;
  float ar = r < 0.0 ? -r : r;
  return (ar <= big && !vplkit_mis_is_nan(r)) ? r : 0.0;  // GLSL: NaN (from f) by its bits
}

#endif  // VPLKIT_MIS_HEURISTICS_GLSL
