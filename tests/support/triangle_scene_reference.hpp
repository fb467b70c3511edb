// SPDX-License-Identifier: MIT
#pragma once
// Brute-force exact visibility over a triangle list, in double, independent of the library's
// records: the yardstick of the triangle voxel tests (unit, hard cases, parity).
//   segment_blocked: does the segment x -> y cross a triangle (grown by `grow` within its plane)
//     strictly, ignoring triangles whose plane passes within `end_tol` of x or y (the end rule of
//     triangle_voxel_query.hpp)?
//   first_hit: the smallest t > 0 at which o + t d (d unit) meets a triangle (same growth, planes
//     within end_tol of o ignored); +inf when none.
// A query is a near-tie when the answers with (end_tol - delta, grow + delta) and
// (end_tol + delta, grow - delta) differ: then a few ulps can flip the library's answer.
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

namespace vplkit_test {

using d3 = glm::dvec3;

struct ref_triangle {
  d3 v[3];
};

// Triangles of an indexed mesh.
template <class V>
std::vector<ref_triangle> ref_triangles(const std::vector<V>& positions, const std::vector<std::uint32_t>& indices) {
  std::vector<ref_triangle> out;
  for (std::size_t t = 0; t + 2 < indices.size(); t += 3)
    out.push_back(ref_triangle{{d3(positions[indices[t]]), d3(positions[indices[t + 1]]), d3(positions[indices[t + 2]])}});
  return out;
}

// Unit normal and offset, or false for a degenerate triangle.
inline bool ref_plane(const ref_triangle& t, d3& n, double& c) {
  n = glm::cross(t.v[1] - t.v[0], t.v[2] - t.v[0]);
  const double len = glm::length(n);
  if (!(len > 0.0)) return false;
  n /= len;
  c = glm::dot(n, t.v[0]);
  return true;
}

// Is p (in the triangle's plane) within `grow` of the triangle (distance to each edge line, on
// the inner side or at most grow outside)?
inline bool ref_inside(const ref_triangle& t, const d3& n, const d3& p, double grow) {
  for (int i = 0; i < 3; ++i) {
    const d3 e = t.v[(i + 1) % 3] - t.v[i];
    const d3 m = glm::normalize(glm::cross(n, e));
    if (glm::dot(m, p - t.v[i]) < -grow) return false;
  }
  return true;
}

inline bool segment_blocked(const std::vector<ref_triangle>& tris, const d3& x, const d3& y, double end_tol,
                            double grow) {
  for (const ref_triangle& t : tris) {
    d3 n;
    double c;
    if (!ref_plane(t, n, c)) continue;
    const double d0 = glm::dot(n, x) - c, d1 = glm::dot(n, y) - c;
    if (!(std::abs(d0) > end_tol) || !(std::abs(d1) > end_tol) || (d0 > 0.0) == (d1 > 0.0)) continue;
    if (ref_inside(t, n, x + (d0 / (d0 - d1)) * (y - x), grow)) return true;
  }
  return false;
}

inline double first_hit(const std::vector<ref_triangle>& tris, const d3& o, const d3& d, double end_tol, double grow) {
  double best = std::numeric_limits<double>::infinity();
  for (const ref_triangle& t : tris) {
    d3 n;
    double c;
    if (!ref_plane(t, n, c)) continue;
    const double d0 = glm::dot(n, o) - c, den = glm::dot(n, d);
    if (!(std::abs(d0) > end_tol) || den == 0.0) continue;
    const double s = -d0 / den;
    if (s > 0.0 && s < best && ref_inside(t, n, o + s * d, grow)) best = s;
  }
  return best;
}

// The segment's answer is settled when moving end_tol and grow by delta cannot change it.
inline bool segment_near_tie(const std::vector<ref_triangle>& tris, const d3& x, const d3& y, double end_tol,
                             double grow, double delta) {
  return segment_blocked(tris, x, y, end_tol - delta, grow + delta) !=
         segment_blocked(tris, x, y, end_tol + delta, std::max(0.0, grow - delta));
}

// A random point of triangle t (uniform barycentrics).
template <class Rng>
d3 point_on(const ref_triangle& t, Rng& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double a = u(rng), b = u(rng);
  if (a + b > 1.0) {
    a = 1.0 - a;
    b = 1.0 - b;
  }
  return t.v[0] + a * (t.v[1] - t.v[0]) + b * (t.v[2] - t.v[0]);
}

}  // namespace vplkit_test
