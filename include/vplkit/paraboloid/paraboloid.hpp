// SPDX-License-Identifier: MIT
#pragma once
// Dual paraboloid mapping in light space (docs/math.md section 1): direction <-> (face, uv).
//
// Convention (mirrored by glsl/vplkit): the front face covers d.z >= 0 (-0.0 included), the back
// face d.z < 0. The back face is NOT mirrored: uv = (d.x, d.y) / (1 + |d.z|) on both faces, so a
// rim direction (d.z = 0) has the same uv on either face and the two maps join continuously
// along the rim. Consequence for a rasteriser: the back projection is a reflection (z -> -z) of
// the front one, so triangle winding flips on the back face.
#include <vplkit/core/normal_range.hpp>
#include <vplkit/core/unit_or_zero.hpp>
#include <vplkit/core/vector.hpp>

#include <cmath>
#include <limits>

namespace vplkit {

inline constexpr int paraboloid_front = 0;
inline constexpr int paraboloid_back = 1;

template <class T>
struct paraboloid_point {
  int face;    // paraboloid_front or paraboloid_back
  vec2<T> uv;  // in the closed unit disk
};

// Pulls a uv that rounding left just outside the unit disk back inside, so that
// dot(uv, uv) <= 1 holds exactly in T. Multiplying by 1/sqrt(r2) alone still lands above 1 in
// most cases (the product rounds up); the extra factor (1 - 2 eps) moves uv by at most ~2 ulp and
// was checked on 2e7 rim directions in float and double. Leaves uv untouched when r2 <= 1.
// A uv with a component beyond 2^63 (float; 2^511 in double), whose r2 may overflow, is
// normalised scale-first (unit_or_zero) instead, so it lands on the rim in its own direction
// rather than at uv / sqrt(Inf) = 0, the centre; one with an infinite component gives (0, 0),
// unit_or_zero's answer for a non-finite vector. The test is on uv, not on r2 == Inf: a GPU
// compiler may assume that no value is infinite (docs/math.md, "GPU arithmetic model").
template <class T>
inline vec2<T> paraboloid_clamp_to_disk(vec2<T> uv) {
  const T r2 = glm::dot(uv, uv);
  if (r2 > T(1)) {
    const T scale = T(1) - T(2) * std::numeric_limits<T>::epsilon();
    const vec3<T> v(uv.x, uv.y, T(0));
    if (max_abs_component(v) <= exp2i<T>((std::numeric_limits<T>::max_exponent - 2) / 2)) {
      uv = uv * (detail::inversesqrt_of(r2) * scale);
    } else {
      const vec3<T> n = unit_or_zero(v);
      uv = vec2<T>(n.x, n.y) * scale;
    }
  }
  return uv;
}

// Direction (light space, any length) -> face and uv. d is normalised first (robust to
// |d| ~ 1e-30 or 1e30); a zero, NaN or infinite d gives {front, (0,0)} rather than NaN.
// The denominator is 1 + |d.z| >= 1 on whichever face d falls: the map never divides by the
// cancelling 1 - |d.z| of the opposite face, so the back pole (0,0,-1) is as accurate as the
// front one. Rim directions give r2 <= 1 exactly (paraboloid_clamp_to_disk).
// The face is decided on d.z itself (below the smallest normal T it counts as 0, i.e. front), not
// on the normalised z: a tiny negative z can normalise to a denormal, which a GPU flushes and a
// CPU may keep, and the decision must not depend on that (docs/math.md, "GPU arithmetic model").
template <class T>
inline paraboloid_point<T> paraboloid_from_direction(vec3<T> d) {
  const vec3<T> n = unit_or_zero(d);
  paraboloid_point<T> p;
  const bool has_direction = n.x != T(0) || n.y != T(0) || n.z != T(0);
  p.face = (has_direction && flush_denormal(d.z) < T(0)) ? paraboloid_back : paraboloid_front;
  const T denom = T(1) + detail::abs_of(n.z);
  p.uv = paraboloid_clamp_to_disk(vec2<T>(n.x, n.y) / denom);
  return p;
}

// (face, uv) -> unit direction in light space; the exact inverse of paraboloid_from_direction
// for uv in the unit disk: r2 = |uv|^2, d = (2u, 2v, 1 - r2) / (1 + r2), z negated on the back
// face. Unit length to a few ulp (no final normalisation). At r2 = 1 the result has z = +-0,
// which paraboloid_from_direction files under the front face with the same uv (seam
// convention). For r2 > 1 (map corners, outside every valid texel) the formula continues into
// the other hemisphere: still a unit vector, but not on this face.
template <class T>
inline vec3<T> paraboloid_to_direction(int face, vec2<T> uv) {
  const T r2 = glm::dot(uv, uv);
  const T s = T(1) / (T(1) + r2);
  vec3<T> d(T(2) * uv.x * s, T(2) * uv.y * s, (T(1) - r2) * s);
  if (face == paraboloid_back) d.z = -d.z;
  return d;
}

// Solid-angle Jacobian of the map: d(omega) = 4 / (1 + r2)^2 du dv (1 at the rim, 4 at the pole).
template <class T>
inline T paraboloid_jacobian(vec2<T> uv) {
  const T q = T(1) + glm::dot(uv, uv);
  return T(4) / (q * q);
}

}  // namespace vplkit
