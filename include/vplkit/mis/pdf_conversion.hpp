// SPDX-License-Identifier: MIT
#pragma once
// Densities of the two strategies of docs/math.md section 5, expressed in one measure — solid angle
// at the gather point x — so that the heuristics of heuristics.hpp may compare them.
//
//   gathering:    p1(omega) = cos(theta2) / pi                        (theta2 at x, vs n_x)
//   VPL sampling: p2(omega) = pmf(t) * d2^2 / (A_t * cos(theta1))     (theta1 at y_t, vs n_t)
// p2 converts "pick texel t with probability pmf(t), then a point uniformly on its patch of area
// A_t" (area density pmf/A_t) to solid angle at x with the Jacobian dA = d2^2 / cos(theta1) domega.
// A_t = Omega_t d1^2 / cos(alpha) (docs/math.md section 2) comes from the VPL model
// (vpl_patch_area); it is taken here as a number. For a VPL sample, f/p2 = L_t(x)/pmf(t) without
// any distance clamp; as d2 -> 0, p2 -> 0 and the balance heuristic hands the point to the
// gathering strategy.
//
// The paper's forms (eq. 10, 11, 15) are kept as `_as_published`; see mis_weights_as_published.
#include <vplkit/core/normal_range.hpp>
#include <vplkit/mis/heuristics.hpp>
#include <vplkit/sampling/cosine_hemisphere.hpp>

#include <limits>
#include <type_traits>

namespace vplkit {

template <class T> inline T cosine_pdf_solid_angle(T cos_theta2) {
  return cosine_hemisphere_pdf(cos_theta2);
}

// Solid-angle density at x with which VPL sampling produces the direction towards a point of
// texel t's patch. Never NaN:
// - pmf <= 0: the texel is never drawn -> 0. A pmf, cosine, distance or area below the smallest
//   normal T counts as 0 (the normal-range contract, docs/math.md "GPU arithmetic model").
// - cos_theta1 <= 0: x is behind the patch. VPL emission is one-sided (L_t has the factor
//   max(cos theta1, 0)), so neither strategy gets a non-zero value there and no weight is ever
//   applied to one; we return 0, the density of *contributing* VPL samples in that direction.
//   Gathering code must likewise give a ray that hits a patch from behind the value 0.
// - d2_squared == 0: x on the VPL; the small-patch Jacobian tends to 0 and so does p2: 0.
// - patch_area == 0 (with the rest positive): the texel's probability sits in zero solid angle:
//   +inf (balance weight 1 for the VPL strategy, balance_combined 0 for a gathering sample).
// - patch_area infinite -> 0; d2_squared infinite -> +inf; NaN or negative geometry -> 0;
//   cos_theta1 infinite (not a cosine) -> 0.
namespace detail {
// vpl_pdf_solid_angle's general form, which every T runs.
template <class T> inline T vpl_pdf_solid_angle_scaled(T pmf, T d2_squared, T patch_area, T cos_theta1) {
  const T inf = std::numeric_limits<T>::infinity();
  constexpr T lo = std::numeric_limits<T>::min();
  if (!(pmf >= lo) || !(cos_theta1 >= lo) || !(d2_squared >= lo)) return T(0);
  // cos_theta1 = inf is no cosine.
  if (!(patch_area >= T(0)) || patch_area == inf || cos_theta1 == inf) return T(0);
  patch_area = flush_denormal(patch_area);
  if (patch_area == T(0) || d2_squared == inf || pmf == inf) return inf;
  // The mantissas' quotient (numerator and divisor in [1, 4), where GLSL promises 2.5 ulp: a GPU
  // divides 1e38 / 1e38 through a denormal reciprocal), then the exact power of two: the result
  // overflows to +inf, or is 0 below the smallest normal T, where the computed quotient leaves the
  // range of T. With correct rounding that is where the true density does; a GPU's 2.5-ulp
  // quotient may cross FLT_MAX (or FLT_MIN) when the true density lies within 2.5 ulps of it, so
  // there one device gives FLT_MAX and another +inf (NVIDIA H200: +inf for 3e38 * FLT_MAX /
  // 3e38): the two neighbours that Vulkan's ULP rule lets a bound reaching past FLT_MAX return.
  const binary_split<T> sp = split_binary(pmf), sd = split_binary(d2_squared),
                        sa = split_binary(patch_area), sc = split_binary(cos_theta1);
  const T q = (sp.mantissa * sd.mantissa) / (sa.mantissa * sc.mantissa);
  return scale_by_exp2(q, sp.exponent + sd.exponent - sa.exponent - sc.exponent);
}
}  // namespace detail

// Host shortcut (float and double, correctly rounded; not a test's GPU model of float): the plain
// (pmf d2^2) / (A cos(theta1)) where the four inputs are normal and finite and both products and
// the quotient lie in [2 min, max]. There the roundings commute with the general form's scalings
// by powers of two (heuristics.hpp, balance_combined's shortcut): the same bits. Compared over the
// whole range in tests/hardcases/mis_host_shortcut_hardcases_test.cpp, IEEE and FTZ|DAZ.
template <class T> inline T vpl_pdf_solid_angle(T pmf, T d2_squared, T patch_area, T cos_theta1) {
  if constexpr (detail::mis_host_arithmetic<T>) {
    constexpr T lo = std::numeric_limits<T>::min(), lo2 = T(2) * lo, big = std::numeric_limits<T>::max();
    if (pmf >= lo && pmf <= big && d2_squared >= lo && d2_squared <= big && patch_area >= lo && patch_area <= big &&
        cos_theta1 >= lo && cos_theta1 <= big) {
      const T num = pmf * d2_squared, den = patch_area * cos_theta1;
      if (num >= lo2 && num <= big && den >= lo2 && den <= big) {
        const T q = num / den;
        if (q >= lo2 && q <= big) return q;
      }
    }
  }
  return detail::vpl_pdf_solid_angle_scaled(pmf, d2_squared, patch_area, cos_theta1);
}

// ---- the paper's mixed-measure forms (as published) -------------------------------------------
//
// Eq. 10 / 15: p1 = cos(theta) sin(theta) / pi, the density of cosine-weighted directions over
// the (theta, phi) parameter square — the solid-angle density cos/pi times the Jacobian
// sin(theta). Eq. 11: p2 = alpha, the discrete probability of the VPL (texel). Eq. 8 / 9: balance
// heuristic with these, no sample counts:
//   w_gathering = p1 / (p1 + alpha),   w_vpl = alpha / (p1 + alpha)
// both evaluated for the same (direction, texel) pair: theta between n_x and the ray (gathering
// sample) or the direction to y_t (VPL sample); alpha the pmf of the texel hit or drawn.
// The paper computes theta = acos(dot(N, pv)); sin_theta = sqrt(max(0, 1 - cos^2)) is the same.
//
// Why this is not our default: p1 is per unit (theta, phi), alpha per texel. The ratio that sets
// the weights, alpha / p1, therefore changes with the DPRSM resolution and with sin(theta) (p1
// vanishes at the pole theta = 0 as well as at the horizon) instead of measuring how densely each
// strategy actually samples the point. The weights still add up to 1 for one (direction, texel)
// pair, but they do not fall to 0 for the VPL strategy where its density in solid angle does
// (d2 -> 0), so the VPL estimate's point-light singularity and its clamp bias stay in the image,
// and the combination converges to a blend of the clamped VPL sum and the gathering integral
// rather than to either. And where eq. 10 is also used as the divisor of a gathering value that
// is an integrand per steradian (Veach's F = w f/p with p from eq. 10), the estimate is off by
// the factor 1/sin(theta): biased. Algorithm 6 of the paper calls balanceHeuristic(pdf4, pdf3)
// with the gathering density first; we follow eq. 9 (the VPL weight has alpha in the numerator).

template <class T> inline T cosine_pdf_as_published(T cos_theta, T sin_theta) {
  const T inv_pi = T(0.318309886183790671537767526745028724);
  constexpr T lo = std::numeric_limits<T>::min();
  return (cos_theta >= lo && sin_theta >= lo) ? flush_denormal(cos_theta * sin_theta * inv_pi) : T(0);
}

template <class T> struct mis_weight_pair {
  T gathering;  // weight of the cosine-gathering sample (paper eq. 8)
  T vpl;        // weight of the CDF-selected VPL sample (paper eq. 9)
};

// Never NaN; both 0 when p1 = alpha = 0; inf/denormal/huge as in heuristics.hpp.
template <class T> inline mis_weight_pair<T> mis_weights_as_published(T cos_theta, T sin_theta,
                                                                      T alpha) {
  const T p1 = cosine_pdf_as_published(cos_theta, sin_theta);
  mis_weight_pair<T> w;
  w.gathering = balance_heuristic(T(1), p1, T(1), alpha);
  w.vpl = balance_heuristic(T(1), alpha, T(1), p1);
  return w;
}

}  // namespace vplkit
