// SPDX-License-Identifier: MIT
#pragma once
// Triangle / axis-aligned box overlap by the separating axis theorem (Akenine-Moeller, "Fast 3D
// triangle-box overlap testing", JGT 2001): the box and the triangle are disjoint iff their
// projections are disjoint on one of 13 axes: the 3 box normals (the triangle's bounding box
// against the box), the triangle normal, and the 9 cross products (box axis x triangle edge).
//
// Closed sets: touching counts as overlap (a triangle lying exactly on a box face, or meeting the
// box at one point, overlaps it). An axis separates only if the projections are STRICTLY apart.
//
// Degenerate triangles (collinear vertices, repeated vertices, zero area) are handled by the same
// code, exactly in exact arithmetic: a zero axis (the normal of a zero-area triangle, the cross
// product of a zero-length edge or of an edge parallel to a box axis) projects everything to 0 and
// can never separate, and the remaining axes are still complete for what is left: for a segment,
// the box normals and (box axis x segment direction) are all the separating axes of segment vs
// box; for a point, the box normals alone. So a degenerate triangle overlaps the box iff the
// segment/point it reduces to does.
//
// Rounding: every axis projects all three vertices (the original code projects only two for some
// axes because the third coincides in exact arithmetic); taking min/max over all three makes a
// rounding error lean towards "overlap". Callers that need strict conservativeness (voxelisation)
// inflate the half size a little; see voxelize.hpp. Non-finite input gives `true` (no comparison
// with NaN separates); validate before calling.
#include <vplkit/core/vector.hpp>

#include <cmath>

namespace vplkit {

namespace detail {

// Does `axis` separate the triangle (vertices relative to the box centre) from the box of half
// size h? Projections of the box: [-r, r], r = sum_i h_i |axis_i|.
template <class T>
inline bool sat_axis_separates(vec3<T> axis, vec3<T> v0, vec3<T> v1, vec3<T> v2, vec3<T> h) {
  const T p0 = glm::dot(axis, v0), p1 = glm::dot(axis, v1), p2 = glm::dot(axis, v2);
  const T lo = p0 < p1 ? (p0 < p2 ? p0 : p2) : (p1 < p2 ? p1 : p2);
  const T hi = p0 > p1 ? (p0 > p2 ? p0 : p2) : (p1 > p2 ? p1 : p2);
  const T r = h.x * std::abs(axis.x) + h.y * std::abs(axis.y) + h.z * std::abs(axis.z);
  return lo > r || hi < -r;
}

}  // namespace detail

// Does triangle (a, b, c) overlap the closed box centred at box_center with half extents
// box_half (each >= 0)?
template <class T>
inline bool triangle_box_overlap(vec3<T> box_center, vec3<T> box_half, vec3<T> a, vec3<T> b, vec3<T> c) {
  // Work relative to the box centre: smaller magnitudes, smaller rounding.
  const vec3<T> v0 = a - box_center, v1 = b - box_center, v2 = c - box_center;
  const vec3<T> h = box_half;

  // 1. Box normals: the triangle's bounding box against the box (cheapest, rejects most).
  for (int i = 0; i < 3; ++i) {
    const T lo = v0[i] < v1[i] ? (v0[i] < v2[i] ? v0[i] : v2[i]) : (v1[i] < v2[i] ? v1[i] : v2[i]);
    const T hi = v0[i] > v1[i] ? (v0[i] > v2[i] ? v0[i] : v2[i]) : (v1[i] > v2[i] ? v1[i] : v2[i]);
    if (lo > h[i] || hi < -h[i]) return false;
  }

  const vec3<T> e0 = v1 - v0, e1 = v2 - v1, e2 = v0 - v2;

  // 2. Triangle normal (zero for a degenerate triangle: then it cannot separate).
  if (detail::sat_axis_separates(glm::cross(e0, e1), v0, v1, v2, h)) return false;

  // 3. Box axis x edge, 9 axes: unit_x x e = (0, -e.z, e.y), unit_y x e = (e.z, 0, -e.x),
  //    unit_z x e = (-e.y, e.x, 0).
  const vec3<T> edges[3] = {e0, e1, e2};
  for (int k = 0; k < 3; ++k) {
    const vec3<T> e = edges[k];
    if (detail::sat_axis_separates(vec3<T>(T(0), -e.z, e.y), v0, v1, v2, h)) return false;
    if (detail::sat_axis_separates(vec3<T>(e.z, T(0), -e.x), v0, v1, v2, h)) return false;
    if (detail::sat_axis_separates(vec3<T>(-e.y, e.x, T(0)), v0, v1, v2, h)) return false;
  }
  return true;
}

}  // namespace vplkit
