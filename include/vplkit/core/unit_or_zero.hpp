// SPDX-License-Identifier: MIT
#pragma once
// Normalisation that cannot produce NaN or Inf, shared by the paraboloid mapping and the VPL
// model (GLSL: vplkit_unit_or_zero).
#include <vplkit/core/vector.hpp>

#include <cmath>
#include <limits>

namespace vplkit {

// Largest absolute component (the L-infinity norm). NaN components are skipped by the
// comparisons, so a NaN vector gives 0 and is then treated as the zero vector.
template <class T>
inline T max_abs_component(vec3<T> v) {
  T m = T(0);
  if (std::abs(v.x) > m) m = std::abs(v.x);
  if (std::abs(v.y) > m) m = std::abs(v.y);
  if (std::abs(v.z) > m) m = std::abs(v.z);
  return m;
}

// v / |v|, or (0,0,0) when v is zero or has a NaN or infinite component. Dividing by the
// largest component first keeps dot(v, v) away from underflow (|v| ~ 1e-30 in float squares to
// 0) and overflow (|v| ~ 1e30 squares to Inf), so any finite non-zero v gives a unit vector.
template <class T>
inline vec3<T> unit_or_zero(vec3<T> v) {
  const T m = max_abs_component(v);
  if (!(m > T(0)) || !(m <= std::numeric_limits<T>::max())) return vec3<T>(T(0));
  const vec3<T> s = v / m;
  // len2 is in [1, 3] unless a component of v was NaN. The test uses the looser [0.5, 4] so that
  // it stays a pure NaN check under GPU division and sqrt, which are not correctly rounded.
  const T len2 = glm::dot(s, s);
  if (!(len2 >= T(0.5)) || !(len2 <= T(4))) return vec3<T>(T(0));
  return s / std::sqrt(len2);
}

}  // namespace vplkit
