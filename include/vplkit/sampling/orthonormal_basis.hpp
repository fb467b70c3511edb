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
// The input is normalised first by unit_or_zero (an exact power-of-two scaling, so tiny or huge
// components neither underflow nor overflow; components below the smallest normal T count as 0).
// A zero or non-finite input has no direction; it gets the canonical frame (x, y, z) rather than
// NaN (documented fallback, no exception: this runs per sample).
#include <vplkit/core/normal_range.hpp>
#include <vplkit/core/unit_or_zero.hpp>
#include <vplkit/core/vector.hpp>

#include <cmath>
#include <limits>

namespace vplkit {

template <class T> struct orthonormal_basis {
  vec3<T> t;  // tangent
  vec3<T> b;  // bitangent
  vec3<T> n;  // normal (unit)
};

// Unit vector along n; (0,0,1) when n is zero, NaN or infinite, or has no component of at least
// the smallest normal T (unit_or_zero: the normal-range contract, docs/math.md, "GPU arithmetic model").
template <class T> inline vec3<T> onb_normalize(vec3<T> n) {
  const vec3<T> u = unit_or_zero(n);
  return (u.x == T(0) && u.y == T(0) && u.z == T(0)) ? vec3<T>(T(0), T(0), T(1)) : u;
}

// The products that can fall below the smallest normal T are flushed (a GPU may flush them), so
// the frame is the same with and without denormals.
template <class T> inline orthonormal_basis<T> make_orthonormal_basis(vec3<T> normal) {
  const vec3<T> n = onb_normalize(normal);
  const T s = n.z >= T(0) ? T(1) : T(-1);
  const T a = T(-1) / (s + n.z);
  const T c = flush_denormal(n.x * n.y * a);
  orthonormal_basis<T> f;
  f.t = vec3<T>(T(1) + flush_denormal(s * n.x * n.x * a), s * c, -s * n.x);
  f.b = vec3<T>(c, s + flush_denormal(n.y * n.y * a), -n.y);
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
