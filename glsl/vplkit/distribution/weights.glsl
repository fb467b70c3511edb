// SPDX-License-Identifier: MIT
// vplkit GLSL pack: the per-sample helpers shared by every discrete sampler (mirrors the sampling
// side of include/vplkit/distribution/weights.hpp, T = float): the clamp of a random number u into
// [0, 1), and the product of two probabilities that never underflows to 0. Weight validation and
// the accurate running sum are build-time code: on the GPU see cdf_build.comp.
#ifndef VPLKIT_DISTRIBUTION_WEIGHTS_GLSL
#define VPLKIT_DISTRIBUTION_WEIGHTS_GLSL

// The largest float below 1 (0x1.fffffep-1, bits 0x3F7FFFFF): where u >= 1 is clamped, so that
// u * n < n and cdf[n] = 1 > u. C++ discrete_u_max<float>().
float vplkit_discrete_u_max() {
  return uintBitsToFloat(0x3F7FFFFFu);
}

// u NaN or < 0 -> 0, u >= 1 (and +Inf) -> the largest float below 1. Every sampler applies this
// first. C++ writes the first test as !(u >= 0); GLSL leaves comparisons with NaN to the driver
// (and optimizers may rewrite !(u >= 0) as u < 0), so it is made on the bits instead: a set sign
// bit (negative, -0) or a NaN pattern is above 0x7F800000 (+Inf). -0 -> +0 where C++ keeps -0:
// no index or pmf depends on the sign of a zero u.
float vplkit_discrete_clamp_u(float u) {
  if (floatBitsToUint(u) > 0x7F800000u) return 0.0;
  return u < vplkit_discrete_u_max() ? u : vplkit_discrete_u_max();
}

// a * b for probabilities a, b >= 0, but the smallest positive float (2^-149) instead of 0 when
// both are > 0: a product that underflows to 0 would turn a valid sample into a division by zero.
// C++ detail::probability_product<float>. `precise`: the product must not be fused into the sum
// that follows it (defensive_mixture_pmf), or the pmf would differ from the C++ in the last bit.
// On a device that flushes denormals the product is already 0 where the C++ has a denormal, and
// the 2^-149 returned here becomes 0 in the next arithmetic (llvmpipe keeps denormals); only
// products below 2^-126 are concerned.
float vplkit_probability_product(float a, float b) {
  precise float p = a * b;
  return (p == 0.0 && a > 0.0 && b > 0.0) ? uintBitsToFloat(1u) : p;
}

// 1 / p for the rescaling of a reused u, 0 for p <= 0 (or NaN), capped at the largest finite
// float. The C++ (detail::reciprocal_or_zero) divides in double and rounds once, which gives the
// correctly rounded float reciprocal; a GLSL float division may be off by up to 2.5 ulp. Only the
// vplkit_make_* convenience constructors use this: for bit-exact parity, upload the scales the
// C++ objects report (fallback_scale(), learned_scale(), front_scale(), back_scale()).
float vplkit_reciprocal_or_zero(float p) {
  uint bits = floatBitsToUint(p);  // p <= 0 or NaN, tested on the bits as in the clamp above
  if (bits == 0u || bits > 0x7F800000u) return 0.0;
  float r = 1.0 / p;
  return r < uintBitsToFloat(0x7F7FFFFFu) ? r : uintBitsToFloat(0x7F7FFFFFu);
}

#endif  // VPLKIT_DISTRIBUTION_WEIGHTS_GLSL
