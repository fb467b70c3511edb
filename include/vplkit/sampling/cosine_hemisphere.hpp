// SPDX-License-Identifier: MIT
#pragma once
// Cosine-weighted directions on the hemisphere z >= 0 (local frame; see orthonormal_basis.hpp).
//
// Malley's method: a uniform point on the unit disk lifted to the hemisphere, z = sqrt(1 - r^2),
// has solid-angle density cos(theta) / pi. The disk point comes from Shirley & Chiu 1997, "A low
// distortion map between disk and square" (concentric mapping), which keeps strata of u compact
// on the disk (the polar map r = sqrt(u0) stretches them):
//   a = 2 u - 1  (each component clamped to [-1, 1]);  a == (0, 0): r = 0, phi = 0
//   |a.x| > |a.y|:  r = a.x,  phi = (pi/4) (a.y / a.x)
//   otherwise:      r = a.y,  phi = pi/2 - (pi/4) (a.x / a.y)
//   disk = r (cos phi, sin phi);   z = sqrt(max(0, (1 - |r|)(1 + |r|)))
// z is taken from r rather than from the disk point: 1 - |r| is exact near the rim, so the
// direction is unit to a few ulps and z >= 0 always, also at u = 0 or u = 1 (the rim, z = 0).
// r is signed (phi covers only [-pi/4, 3pi/4]; the sign of r supplies the other half turn).
#include <vplkit/core/normal_range.hpp>
#include <vplkit/core/vector.hpp>

#include <cmath>
#include <limits>

namespace vplkit {

template <class T> struct concentric_polar {
  T r;    // signed radius, |r| <= 1
  T phi;  // angle in [-pi/4, 3pi/4]
};

template <class T> inline concentric_polar<T> concentric_disk_polar(vec2<T> u) {
  const T pi = T(3.14159265358979323846);
  T ax = T(2) * u.x - T(1);
  T ay = T(2) * u.y - T(1);
  ax = ax < T(-1) ? T(-1) : (ax > T(1) ? T(1) : ax);
  ay = ay < T(-1) ? T(-1) : (ay > T(1) ? T(1) : ay);
  concentric_polar<T> p{T(0), T(0)};
  if (ax == T(0) && ay == T(0)) return p;
  if (std::abs(ax) > std::abs(ay)) {
    p.r = ax;
    p.phi = (pi / T(4)) * (ay / ax);
  } else {
    p.r = ay;
    p.phi = pi / T(2) - (pi / T(4)) * (ax / ay);
  }
  return p;
}

// u in [0,1]^2 -> uniform point on the unit disk (Shirley-Chiu).
template <class T> inline vec2<T> concentric_disk(vec2<T> u) {
  const concentric_polar<T> p = concentric_disk_polar(u);
  return vec2<T>(p.r * std::cos(p.phi), p.r * std::sin(p.phi));
}

// u in [0,1]^2 (1 included) -> unit direction with z >= 0, density cos(theta)/pi per steradian.
template <class T> inline vec3<T> sample_cosine_hemisphere(vec2<T> u) {
  const concentric_polar<T> p = concentric_disk_polar(u);
  const T ar = std::abs(p.r);
  const T z2 = (T(1) - ar) * (T(1) + ar);
  return vec3<T>(p.r * std::cos(p.phi), p.r * std::sin(p.phi), std::sqrt(z2 > T(0) ? z2 : T(0)));
}

// Solid-angle density of sample_cosine_hemisphere; 0 below the horizon (and for NaN).
template <class T> inline T cosine_hemisphere_pdf(T cos_theta) {
  const T inv_pi = T(0.318309886183790671537767526745028724);
  // A cosine, or a density, below the smallest normal T is 0 (docs/math.md, "GPU arithmetic
  // model": the same on a GPU that flushes denormals).
  return cos_theta >= std::numeric_limits<T>::min() ? flush_denormal(cos_theta * inv_pi) : T(0);
}

}  // namespace vplkit
