// SPDX-License-Identifier: MIT
// vplkit GLSL pack: densities of the two strategies of docs/math.md section 5 in one measure (solid
// angle at the gather point x), and the paper's mixed-measure forms (`_as_published`); the float
// mirror of include/vplkit/mis/pdf_conversion.hpp (docs/api/mis.md, docs/glsl/mis.md).
//   gathering:    p1(omega) = cos(theta2) / pi                        (theta2 at x, vs n_x)
//   VPL sampling: p2(omega) = pmf(t) * d2^2 / (A_t * cos(theta1))     (theta1 at y_t, vs n_t)
// Paper (eq. 10/15, 11, 8/9): p1 = cos sin / pi against the texel pmf alpha; biased in a
// renderer (mixed measures), kept for reproducing the paper. Nothing here returns NaN.
// GLSL-only lines (marked) reject NaN on its bits and keep divisors in the range where GLSL
// specifies division (vplkit_mis_is_nan, vplkit_mis_div in heuristics.glsl).
#ifndef VPLKIT_MIS_PDF_CONVERSION_GLSL
#define VPLKIT_MIS_PDF_CONVERSION_GLSL

#include "vplkit/mis/heuristics.glsl"
#include "vplkit/sampling/cosine_hemisphere.glsl"

float vplkit_cosine_pdf_solid_angle(float cos_theta2) {
  return vplkit_cosine_hemisphere_pdf(cos_theta2);
}

// Solid-angle density at x with which VPL sampling produces the direction towards a point of
// texel t's patch of area patch_area. pmf <= 0, cos_theta1 <= 0 (x behind the one-sided patch),
// d2_squared == 0, patch_area or cos_theta1 infinite, NaN or negative geometry -> 0;
// patch_area == 0, d2_squared or pmf infinite -> +inf.
float vplkit_vpl_pdf_solid_angle(float pmf, float d2_squared, float patch_area, float cos_theta1) {
  float inf = uintBitsToFloat(0x7F800000u);
  // GLSL-only: NaN geometry -> 0 on the bits; the comparisons below cannot be trusted with NaN
  // (see vplkit_mis_is_nan).
  if (vplkit_mis_is_nan(pmf) || vplkit_mis_is_nan(d2_squared) || vplkit_mis_is_nan(patch_area) ||
      vplkit_mis_is_nan(cos_theta1)) {
    return 0.0;
  }
  if (!(pmf >= vplkit_FLT_MIN) || !(cos_theta1 >= vplkit_FLT_MIN) || !(d2_squared >= vplkit_FLT_MIN)) return 0.0;
  // cos_theta1 = inf is no cosine.
  if (!(patch_area >= 0.0) || patch_area == inf || cos_theta1 == inf) return 0.0;
  patch_area = vplkit_flush_denormal(patch_area);
  if (patch_area == 0.0 || d2_squared == inf || pmf == inf) return inf;
  // pmf d2^2 / (A cos): the mantissas' quotient (numerator and divisor in [1, 4): inside the range
  // where GLSL promises 2.5 ulp), then the exact power of two (C++ vpl_pdf_solid_angle).
  vplkit_binary_split sp = vplkit_split_binary(pmf);
  vplkit_binary_split sd = vplkit_split_binary(d2_squared);
  vplkit_binary_split sa = vplkit_split_binary(patch_area);
  vplkit_binary_split sc = vplkit_split_binary(cos_theta1);
  precise float num = sp.mantissa * sd.mantissa;
  precise float den = sa.mantissa * sc.mantissa;
  return vplkit_scale_by_exp2(num / den, sp.exponent + sd.exponent - sa.exponent - sc.exponent);
}

float vplkit_cosine_pdf_as_published(float cos_theta, float sin_theta) {
  const float inv_pi = 0.318309886183790671537767526745028724;
  // GLSL: NaN excluded on the bits (see vplkit_mis_is_nan).
  bool ok = cos_theta >= vplkit_FLT_MIN && sin_theta >= vplkit_FLT_MIN && !vplkit_mis_is_nan(cos_theta) &&
            !vplkit_mis_is_nan(sin_theta);
  // GLSL: `precise` keeps the C++ order (cos * sin) * inv_pi. Without it GLSL allows
  // reassociation, and Mesa computes (cos * inv_pi) * sin: 2 ulps off, and 0 * inf = NaN for a
  // denormal cos times an infinite sin, where the C++ gives inf.
  precise float p = cos_theta * sin_theta * inv_pi;
  return ok ? vplkit_flush_denormal(p) : 0.0;
}

struct vplkit_mis_weight_pair {
  float gathering;  // weight of the cosine-gathering sample (paper eq. 8)
  float vpl;        // weight of the CDF-selected VPL sample (paper eq. 9)
};

// Never NaN; both 0 when p1 = alpha = 0.
vplkit_mis_weight_pair vplkit_mis_weights_as_published(float cos_theta, float sin_theta,
                                                       float alpha) {
  float p1 = vplkit_cosine_pdf_as_published(cos_theta, sin_theta);
  vplkit_mis_weight_pair w;
  w.gathering = vplkit_balance_heuristic(1.0, p1, 1.0, alpha);
  w.vpl = vplkit_balance_heuristic(1.0, alpha, 1.0, p1);
  return w;
}

#endif  // VPLKIT_MIS_PDF_CONVERSION_GLSL
