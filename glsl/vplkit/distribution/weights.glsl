// SPDX-License-Identifier: MIT
// vplkit GLSL pack: the per-sample helpers shared by every discrete sampler (mirrors the sampling
// side of include/vplkit/distribution/weights.hpp, T = float): the clamp of a random number u into
// [0, 1), and the product of two probabilities that never underflows to 0. Weight validation and
// the accurate running sum are build-time code: on the GPU see cdf_build.comp.
// The normal-range contract (C++ weights.hpp, docs/math.md "GPU arithmetic model"): the stored
// arrays hold no value between 0 and the smallest normal float, u below it reads as 0 and a pmf
// product below it becomes it, so a device that flushes denormals and one that keeps them return
// the same index and pmf.
#ifndef VPLKIT_DISTRIBUTION_WEIGHTS_GLSL
#define VPLKIT_DISTRIBUTION_WEIGHTS_GLSL

#include "vplkit/core/normal_range.glsl"

// The largest float below 1 (0x1.fffffep-1, bits 0x3F7FFFFF): where u >= 1 is clamped, so that
// u * n < n and cdf[n] = 1 > u. C++ discrete_u_max<float>().
float vplkit_discrete_u_max() {
  return uintBitsToFloat(0x3F7FFFFFu);
}

// u NaN, negative or below the smallest normal float -> 0, u >= 1 (and +Inf) -> the largest float
// below 1. Every sampler applies this first. C++ writes the first test as !(u >= FLT_MIN); GLSL
// leaves comparisons with NaN to the driver (and optimizers may rewrite !(u >= x) as u < x), so it
// is made on the bits instead: a set sign bit (negative, -0) or a NaN pattern is above 0x7F800000
// (+Inf), a denormal or +0 below 0x00800000 (FLT_MIN).
float vplkit_discrete_clamp_u(float u) {
  uint bits = floatBitsToUint(u);
  if (bits > 0x7F800000u || bits < 0x00800000u) return 0.0;
  return u < vplkit_discrete_u_max() ? u : vplkit_discrete_u_max();
}

// a * b for probabilities a, b >= 0, but the smallest normal float (2^-126) instead of a product
// below it when both are > 0: a product that underflows would turn a valid sample into a division
// by zero. Factors below 2^-126 count as 0. C++ detail::probability_product<float>: 0 or a normal
// float, the same bits whether the device flushes the denormal product (or one whose exact value
// is below 2^-126) or keeps it. `precise`: the product must not be fused into the sum that follows
// it (defensive_mixture_pmf), or the pmf would differ from the C++ in the last bit.
float vplkit_probability_product(float a, float b) {
  a = vplkit_flush_denormal(a);
  b = vplkit_flush_denormal(b);
  precise float p = a * b;
  return p >= vplkit_FLT_MIN ? p : ((a > 0.0 && b > 0.0) ? vplkit_FLT_MIN : 0.0);
}

// 1 / p for the rescaling of a reused u, 0 for p <= 0 (or NaN), capped at the largest finite
// float. The C++ (detail::reciprocal_or_zero) divides in double and rounds once, which gives the
// correctly rounded float reciprocal; a GLSL float division may be off by up to 2.5 ulp. Only the
// vplkit_make_* convenience constructors use this: for bit-exact parity, upload the scales the
// C++ objects report (fallback_scale(), learned_scale(), front_scale(), back_scale()).
// p below the smallest normal float counts as 0 (the C++ callers flush it before they get here).
float vplkit_reciprocal_or_zero(float p) {
  uint bits = floatBitsToUint(p);  // p <= 0, denormal or NaN, tested on the bits as above
  if (bits < 0x00800000u || bits > 0x7F800000u) return 0.0;
  float r = 1.0 / p;
  return r < uintBitsToFloat(0x7F7FFFFFu) ? r : uintBitsToFloat(0x7F7FFFFFu);
}

#endif  // VPLKIT_DISTRIBUTION_WEIGHTS_GLSL
