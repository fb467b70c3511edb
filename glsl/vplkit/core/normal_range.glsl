// SPDX-License-Identifier: MIT
// vplkit GLSL pack: keeping values in the normal float range, so that the pack computes what the
// C++ templates compute on every conforming GPU (docs/math.md, "GPU arithmetic model"). Mirrors
// include/vplkit/core/normal_range.hpp (T = float): a GPU may flush denormal inputs and results to
// 0, and may divide as a * (1 / b), so the pack counts values below the smallest normal float as 0
// where a decision or a result depends on them, and scales by exact powers of two before it
// divides or squares a quantity of unknown magnitude.
#ifndef VPLKIT_CORE_NORMAL_RANGE_GLSL
#define VPLKIT_CORE_NORMAL_RANGE_GLSL

#include "vplkit/core/constants.glsl"

// NaN and finiteness decided on the bits (C++ std::isnan, std::isfinite). A GPU compiler may
// assume that no value is NaN or infinite and fold a comparison such as !(x > 0.0) into x <= 0.0,
// which NaN then passes (NVIDIA 580 did, docs/results/h200-6044fb0); isnan() may be folded alike.
// Integer tests of the bits are not: every NaN or Inf guard of the pack goes through these.
bool vplkit_is_nan(float x) { return (floatBitsToUint(x) & 0x7FFFFFFFu) > 0x7F800000u; }
bool vplkit_is_finite(float x) { return (floatBitsToUint(x) & 0x7F800000u) != 0x7F800000u; }
bool vplkit_is_finite(vec3 v) { return all(notEqual(floatBitsToUint(v) & 0x7F800000u, uvec3(0x7F800000u))); }

// +0 when |x| is below the smallest normal float, else x (C++ flush_denormal): a device that keeps
// denormals and one that flushes them give the same value.
float vplkit_flush_denormal(float x) {
  return (x < vplkit_FLT_MIN && x > -vplkit_FLT_MIN) ? 0.0 : x;
}

vec3 vplkit_flush_denormal(vec3 v) {
  return vec3(vplkit_flush_denormal(v.x), vplkit_flush_denormal(v.y), vplkit_flush_denormal(v.z));
}

// floor(log2(x)) for a normal, finite, positive x, from the exponent bits.
int vplkit_binary_exponent(float x) {
  return int((floatBitsToUint(x) >> 23u) & 0xFFu) - 127;
}

// 2^k, exact, for k in [-126, 127] (built from the bits: no ldexp, whose handling of extreme k
// varies between drivers).
float vplkit_exp2i(int k) {
  return uintBitsToFloat(uint(k + 127) << 23u);
}

// x * 2^k, k clamped to [-378, 378], as three products by normal powers of two (C++
// scale_by_exp2): exact when the result is normal, +-Inf beyond the largest float, 0 below the
// smallest normal one. precise: the products must stay correctly rounded products in this order.
float vplkit_scale_by_exp2(float x, int k) {
  k = clamp(k, -378, 378);
  int k1 = k / 3;
  int k2 = (k - k1) / 2;
  int k3 = k - k1 - k2;
  precise float y = x * vplkit_exp2i(k1);
  precise float z = y * vplkit_exp2i(k2);
  precise float r = z * vplkit_exp2i(k3);
  return vplkit_flush_denormal(r);
}

// A positive normal finite x as mantissa * 2^exponent, mantissa in [1, 2) (C++ split_binary).
struct vplkit_binary_split {
  float mantissa;
  int exponent;
};

vplkit_binary_split vplkit_split_binary(float x) {
  int e = vplkit_binary_exponent(x);
  return vplkit_binary_split(vplkit_scale_by_exp2(x, -e), e);
}

#endif  // VPLKIT_CORE_NORMAL_RANGE_GLSL
