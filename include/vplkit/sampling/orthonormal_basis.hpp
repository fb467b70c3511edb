// SPDX-License-Identifier: MIT
#pragma once
// A right-handed orthonormal frame (t, b, n) around a normal, for turning locally sampled
// directions (z = up) into world directions and back.
//
// Construction: Duff, Burgess, Christensen, Hery, Kensler, Liani, Villemin 2017, "Building an
// orthonormal basis, revisited" (JCGT 6(1)), the branchless listing:
//   s = (n.z >= 0 ? 1 : -1);  a = -1 / (s + n.z);  c = n.x n.y a
//   t = (1 + s n.x^2 a, s c, -s n.x);   b = (c, s + n.y^2 a, -n.y)
// s + n.z has magnitude >= 1, so nothing cancels near n = (0,0,-1) (Frisvad's 2012 version divides
// by 1 + n.z there). Deviation from the paper: s comes from `n.z >= 0` rather than copysign, so
// n.z = -0.0 takes s = +1; both are exact, and GLSL has no copysign, so CPU and GPU agree.
//
// The input is normalised first, after dividing by its largest component magnitude: that keeps
// the squared length in [1, 3], so denormal or huge components neither underflow nor overflow.
// A zero or non-finite input has no direction; it gets the canonical frame (x, y, z) rather than
// NaN (documented fallback, no exception: this runs per sample).
#include <vplkit/core/vector.hpp>

#include <cmath>
#include <limits>

namespace vplkit {

template <class T> struct orthonormal_basis {
  vec3<T> t;  // tangent
  vec3<T> b;  // bitangent
  vec3<T> n;  // normal (unit)
};

// Unit vector along n; (0,0,1) when n is zero, NaN or infinite.
template <class T> inline vec3<T> onb_normalize(vec3<T> n) {
  const T big = std::numeric_limits<T>::max();
  const T ax = std::abs(n.x), ay = std::abs(n.y), az = std::abs(n.z);
  // Written as `<= big` so NaN fails the test too.
  if (!(ax <= big && ay <= big && az <= big)) return vec3<T>(T(0), T(0), T(1));
  const T m = ax > ay ? (ax > az ? ax : az) : (ay > az ? ay : az);
  if (!(m > T(0))) return vec3<T>(T(0), T(0), T(1));
  const vec3<T> s = n / m;  // largest component is exactly +-1
  return s / std::sqrt(s.x * s.x + s.y * s.y + s.z * s.z);
}

template <class T> inline orthonormal_basis<T> make_orthonormal_basis(vec3<T> normal) {
  const vec3<T> n = onb_normalize(normal);
  const T s = n.z >= T(0) ? T(1) : T(-1);
  const T a = T(-1) / (s + n.z);
  const T c = n.x * n.y * a;
  orthonormal_basis<T> f;
  f.t = vec3<T>(T(1) + s * n.x * n.x * a, s * c, -s * n.x);
  f.b = vec3<T>(c, s + n.y * n.y * a, -n.y);
  f.n = n;
  return f;
}

// local = (x along t, y along b, z along n).
template <class T> inline vec3<T> to_world(const orthonormal_basis<T>& f, vec3<T> local) {
  return f.t * local.x + f.b * local.y + f.n * local.z;
}

template <class T> inline vec3<T> to_local(const orthonormal_basis<T>& f, vec3<T> world) {
  return vec3<T>(glm::dot(world, f.t), glm::dot(world, f.b), glm::dot(world, f.n));
}

}  // namespace vplkit
