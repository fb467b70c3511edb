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
// - the terms are rescaled by the larger pdf and then by the larger term before anything is
//   multiplied or squared, so denormal pdfs (whose squares would flush to 0) and huge ones
//   (1e38, whose sums or squares would overflow) give the same weights as moderate ones.
// Consequently heuristic(n1,p1,n2,p2) + heuristic(n2,p2,n1,p1) = 1 to within 2 ulps whenever at
// least one strategy has n > 0 and p > 0 (finite or not), and 0 when neither has.
#include <limits>

namespace vplkit {

// Finite and positive -> n, anything else (0, negative, NaN, inf) -> 0.
template <class T> inline T mis_clean_count(T n) {
  return (n > T(0) && n <= std::numeric_limits<T>::max()) ? n : T(0);
}

// Positive (+inf included) -> p; 0, negative, NaN -> 0.
template <class T> inline T mis_clean_pdf(T p) { return p > T(0) ? p : T(0); }

// The two MIS terms n1 p1 and n2 p2 scaled by one common positive factor so that the larger is
// exactly 1, or (0, 0) when both vanish. Infinite pdfs replace the finite ones: the terms become
// the counts of the infinite strategies.
template <class T> struct mis_terms {
  T a;  // ~ n1 p1
  T b;  // ~ n2 p2
};

template <class T> inline mis_terms<T> mis_scaled_terms(T n1, T p1, T n2, T p2) {
  const T inf = std::numeric_limits<T>::infinity();
  n1 = mis_clean_count(n1);
  n2 = mis_clean_count(n2);
  p1 = n1 > T(0) ? mis_clean_pdf(p1) : T(0);
  p2 = n2 > T(0) ? mis_clean_pdf(p2) : T(0);
  mis_terms<T> r{T(0), T(0)};
  if (p1 == inf || p2 == inf) {
    r.a = p1 == inf ? n1 : T(0);
    r.b = p2 == inf ? n2 : T(0);
  } else {
    const T m = p1 > p2 ? p1 : p2;
    if (!(m > T(0))) return r;
    r.a = n1 * (p1 / m);  // p/m in [0, 1]: no overflow; a denormal pdf is lifted, not squared
    r.b = n2 * (p2 / m);
  }
  const T s = r.a > r.b ? r.a : r.b;  // > 0 here: the larger pdf's strategy has n > 0
  r.a = r.a / s;
  r.b = r.b / s;
  return r;
}

template <class T> inline T balance_heuristic(T n1, T p1, T n2, T p2) {
  const mis_terms<T> t = mis_scaled_terms(n1, p1, n2, p2);
  const T d = t.a + t.b;  // 0 or in [1, 2]
  return d > T(0) ? t.a / d : T(0);
}

template <class T> inline T power_heuristic(T n1, T p1, T n2, T p2) {
  const mis_terms<T> t = mis_scaled_terms(n1, p1, n2, p2);
  const T a2 = t.a * t.a, b2 = t.b * t.b;  // squares of numbers in [0, 1]: underflow only to a
  const T d = a2 + b2;                     // value that cannot matter next to the other's 1
  return d > T(0) ? a2 / d : T(0);
}

// f / (n1 p1 + n2 p2), the balance-heuristic estimator's value for one sample of either strategy.
// 0 when the denominator is 0 (no strategy produces the point) or infinite (a delta pdf: the
// finite f of a continuous sample has measure zero next to it), and 0 when f is not finite or the
// quotient overflows — a guard against poisoning an image, reached only for samples of negligible
// probability. f may be negative.
template <class T> inline T balance_combined(T f, T n1, T p1, T n2, T p2) {
  const T inf = std::numeric_limits<T>::infinity();
  const T big = std::numeric_limits<T>::max();
  n1 = mis_clean_count(n1);
  n2 = mis_clean_count(n2);
  p1 = n1 > T(0) ? mis_clean_pdf(p1) : T(0);
  p2 = n2 > T(0) ? mis_clean_pdf(p2) : T(0);
  if (p1 == inf || p2 == inf) return T(0);
  const T m = p1 > p2 ? p1 : p2;
  if (!(m > T(0))) return T(0);
  // Denominator = m * d with d in [n of the larger pdf, n1 + n2] (d >= 1 for whole sample
  // counts). Divide first by whichever factor moves f towards the result: by m first when m < 1
  // (f/m grows, then shrinks by d), by d first otherwise, so an intermediate over- or underflows
  // only when the result itself does (a denormal f and m then give f/m = 1, not 0).
  const T d = n1 * (p1 / m) + n2 * (p2 / m);
  const T r = m < T(1) ? (f / m) / d : (f / d) / m;
  const T ar = r < T(0) ? -r : r;
  return ar <= big ? r : T(0);
}

}  // namespace vplkit
