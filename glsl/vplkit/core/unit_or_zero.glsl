// SPDX-License-Identifier: MIT
// vplkit GLSL pack: normalisation that cannot produce NaN or Inf, shared by the paraboloid mapping
// and the VPL model. Mirrors include/vplkit/core/unit_or_zero.hpp (T = float) line for line.
#ifndef VPLKIT_CORE_UNIT_OR_ZERO_GLSL
#define VPLKIT_CORE_UNIT_OR_ZERO_GLSL

#include "vplkit/core/constants.glsl"

// Largest absolute component (the L-infinity norm). NaN components are skipped by the
// comparisons on the CPU; GPU compilers may assume NaN never occurs, so that is a CPU guarantee.
float vplkit_max_abs_component(vec3 v) {
  float m = 0.0;
  if (abs(v.x) > m) m = abs(v.x);
  if (abs(v.y) > m) m = abs(v.y);
  if (abs(v.z) > m) m = abs(v.z);
  return m;
}

// v / |v|, or (0,0,0) when v is zero or has an infinite (CPU: or NaN) component. Dividing by the
// largest component first keeps dot(v, v) away from underflow and overflow, so any finite
// non-zero v gives a unit vector.
vec3 vplkit_unit_or_zero(vec3 v) {
  float m = vplkit_max_abs_component(v);
  if (!(m > 0.0) || !(m <= vplkit_FLT_MAX)) return vec3(0.0);
  vec3 s = v / m;
  // len2 is in [1, 3] unless a component was NaN; [0.5, 4] keeps the test a pure NaN check under
  // GPU division and sqrt, which are not correctly rounded.
  float len2 = dot(s, s);
  if (!(len2 >= 0.5) || !(len2 <= 4.0)) return vec3(0.0);
  return s / sqrt(len2);
}

#endif  // VPLKIT_CORE_UNIT_OR_ZERO_GLSL
