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
// pdfs are weighed by their counts; the terms are rescaled so that the larger is exactly 1 before
// anything is added or squared (denormal and huge pdfs give the weights of moderate ones).
// +inf is uintBitsToFloat(0x7F800000u) and is tested with `==`, as in the C++.
//
// GLSL-only additions (the rest reads line for line like the C++):
// - vplkit_mis_is_nan(x) decides NaN on the bits, and guards every place where the C++ relies on
//   a comparison being false for NaN: compilers may fold such comparisons into min/max, which drop
//   a NaN (docs/glsl.md, "NaN, FMA and compiler rewrites"), so the C++ form alone lets NaN through.
// - vplkit_mis_div(x, y) stands where the C++ writes x / y with a divisor that may lie outside
//   [2^-126, 2^126]; on an IEEE device it gives the bits of x / y.
// On a GPU that flushes denormals to zero, denormal inputs and results read as 0 (see
// docs/glsl/mis.md); the results are still never NaN.
#ifndef VPLKIT_MIS_HEURISTICS_GLSL
#define VPLKIT_MIS_HEURISTICS_GLSL

#include "vplkit/core/constants.glsl"

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
bool vplkit_mis_is_nan(float x) {
  return (floatBitsToUint(x) & 0x7FFFFFFFu) > 0x7F800000u;
}

// Finite and positive -> n, anything else (0, negative, NaN, inf) -> 0.
float vplkit_mis_clean_count(float n) {
  return (n > 0.0 && n <= vplkit_FLT_MAX && !vplkit_mis_is_nan(n)) ? n : 0.0;
}

// Positive (+inf included) -> p; 0, negative, NaN -> 0.
float vplkit_mis_clean_pdf(float p) {
  return (p > 0.0 && !vplkit_mis_is_nan(p)) ? p : 0.0;
}

// The two MIS terms n1 p1 and n2 p2 scaled by one common positive factor so that the larger is
// exactly 1, or (0, 0) when both vanish. Infinite pdfs replace the finite ones: the terms become
// the counts of the infinite strategies.
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
  vplkit_mis_terms r = vplkit_mis_terms(0.0, 0.0);
  if (p1 == inf || p2 == inf) {
    r.a = p1 == inf ? n1 : 0.0;
    r.b = p2 == inf ? n2 : 0.0;
  } else {
    float m = p1 > p2 ? p1 : p2;
    if (!(m > 0.0)) return r;
    r.a = n1 * vplkit_mis_div(p1, m);  // p/m in [0, 1]: no overflow; a denormal pdf is lifted
    r.b = n2 * vplkit_mis_div(p2, m);
  }
  float s = r.a > r.b ? r.a : r.b;  // > 0 here: the larger pdf's strategy has n > 0
  // GLSL-only: never taken on an IEEE device; where denormals flush, a denormal count times 1
  // can give s = 0, and then there is no term.
  if (!(s > 0.0)) return vplkit_mis_terms(0.0, 0.0);
  r.a = vplkit_mis_div(r.a, s);
  r.b = vplkit_mis_div(r.b, s);
  return r;
}

float vplkit_balance_heuristic(float n1, float p1, float n2, float p2) {
  vplkit_mis_terms t = vplkit_mis_scaled_terms(n1, p1, n2, p2);
  float d = t.a + t.b;  // 0 or in [1, 2]
  return d > 0.0 ? t.a / d : 0.0;
}

float vplkit_power_heuristic(float n1, float p1, float n2, float p2) {
  vplkit_mis_terms t = vplkit_mis_scaled_terms(n1, p1, n2, p2);
  float a2 = t.a * t.a, b2 = t.b * t.b;  // squares of numbers in [0, 1]: underflow only to a
  float d = a2 + b2;                     // value that cannot matter next to the other's 1
  return d > 0.0 ? a2 / d : 0.0;
}

// f / (n1 p1 + n2 p2), the balance-heuristic estimator's value for one sample of either strategy.
// 0 when the denominator is 0 or infinite, and 0 when f is not finite or the quotient overflows
// (a guard against poisoning an image, reached only for samples of negligible probability).
// f may be negative.
float vplkit_balance_combined(float f, float n1, float p1, float n2, float p2) {
  float inf = uintBitsToFloat(0x7F800000u);
  float big = vplkit_FLT_MAX;
  n1 = vplkit_mis_clean_count(n1);
  n2 = vplkit_mis_clean_count(n2);
  p1 = n1 > 0.0 ? vplkit_mis_clean_pdf(p1) : 0.0;
  p2 = n2 > 0.0 ? vplkit_mis_clean_pdf(p2) : 0.0;
  if (p1 == inf || p2 == inf) return 0.0;
  float m = p1 > p2 ? p1 : p2;
  if (!(m > 0.0)) return 0.0;
  // Denominator = m * d with d in [n of the larger pdf, n1 + n2]. Divide first by whichever
  // factor moves f towards the result, so an intermediate over- or underflows only when the
  // result itself does.
  float d = n1 * vplkit_mis_div(p1, m) + n2 * vplkit_mis_div(p2, m);
  float r = m < 1.0 ? vplkit_mis_div(vplkit_mis_div(f, m), d)
                    : vplkit_mis_div(vplkit_mis_div(f, d), m);
  float ar = r < 0.0 ? -r : r;
  return (ar <= big && !vplkit_mis_is_nan(r)) ? r : 0.0;  // GLSL: NaN (from f) by its bits
}

#endif  // VPLKIT_MIS_HEURISTICS_GLSL
