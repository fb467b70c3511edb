// SPDX-License-Identifier: MIT
// vplkit GLSL pack: normalisation that cannot produce NaN or Inf, shared by the paraboloid mapping
// and the VPL model. Mirrors include/vplkit/core/unit_or_zero.hpp (T = float) line for line.
#ifndef VPLKIT_CORE_UNIT_OR_ZERO_GLSL
#define VPLKIT_CORE_UNIT_OR_ZERO_GLSL

#include "vplkit/core/constants.glsl"
#include "vplkit/core/normal_range.glsl"

// Largest absolute component (the L-infinity norm). NaN components are skipped by the
// comparisons on the CPU; GPU compilers may assume NaN never occurs, so a NaN component may or may
// not be skipped there (vplkit_unit_or_zero does not depend on it).
float vplkit_max_abs_component(vec3 v) {
  float m = 0.0;
  if (abs(v.x) > m) m = abs(v.x);
  if (abs(v.y) > m) m = abs(v.y);
  if (abs(v.z) > m) m = abs(v.z);
  return m;
}

// v / |v|, or (0,0,0) when v is zero or has an infinite or NaN component. Components below
// the smallest normal float count as 0, in v and in the result (C++: the same flushes), so a
// device that flushes denormals and one that keeps them agree. v is scaled by the power of two
// that brings its largest component into [1, 2) ([2, 4) in the top binade) first: exact, so
// dot(v, v) neither under- nor overflows, and no division by a huge |v| (a / b may be computed as
// a * (1 / b), and 1 / b is a denormal for b > 2^126). The length is applied as
// s * inversesqrt(len2) (2 ulp in GLSL) where the C++ divides by sqrt(len2) (correctly rounded):
// the pack's sqrt is itself 1 / inversesqrt, and a division adds 2.5 ulp.
vec3 vplkit_unit_or_zero(vec3 v) {
  v = vplkit_flush_denormal(v);
  float m = vplkit_max_abs_component(v);
  if (!(m > 0.0) || !(m <= vplkit_FLT_MAX)) return vec3(0.0);
  int e = vplkit_binary_exponent(m);
  float scale = vplkit_exp2i(e < 126 ? -e : -126);
  vec3 s = vplkit_flush_denormal(v * scale);
  // len2 is in [1, 48] unless a component was NaN; [0.5, 64] keeps the range test exact under GPU
  // arithmetic. A NaN component makes len2 NaN (arithmetic propagates it), and the bit test
  // catches it where a compiler that assumes no NaN folds the comparisons (normal_range.glsl).
  float len2 = dot(s, s);
  if (!(len2 >= 0.5) || !(len2 <= 64.0) || vplkit_is_nan(len2)) return vec3(0.0);
  return vplkit_flush_denormal(s * inversesqrt(len2));
}

// |v| with the scale-first rule (C++ scaled_length): sqrt(dot(v, v)) where the largest component
// lies in [2^-50, 2^62] (a square a flushing device drops there is below half an ulp of the sum);
// elsewhere the length of v scaled by a power of two, scaled back. Components below the smallest
// normal float count as 0; an infinite component gives +Inf (a bit cast: never flushed or folded).
float vplkit_scaled_length(vec3 v) {
  v = vplkit_flush_denormal(v);
  float m = vplkit_max_abs_component(v);
  if (!(m > 0.0)) return 0.0;
  if (!(m <= vplkit_FLT_MAX)) return uintBitsToFloat(0x7f800000u);
  if (m >= 8.8817841970012523e-16 && m <= 4.6116860184273879e18) return sqrt(dot(v, v));  // 2^-50, 2^62
  int e = vplkit_binary_exponent(m);
  int k = e < 126 ? -e : -126;
  vec3 s = vplkit_flush_denormal(v * vplkit_exp2i(k));
  float len = sqrt(dot(s, s));  // >= 1 exactly; the max undoes a GPU sqrt rounded below 1
  return (len > 1.0 ? len : 1.0) * vplkit_exp2i(-k);
}

#endif  // VPLKIT_CORE_UNIT_OR_ZERO_GLSL
