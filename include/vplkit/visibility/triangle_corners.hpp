// SPDX-License-Identifier: MIT
#pragma once
// Shading normals for the hits of a triangle voxel grid (triangle_voxel_grid.hpp). The grid keeps
// each triangle as four planes, enough to decide visibility and place a hit, not to shade it: on a
// smoothed mesh the radiance a gathering ray brings back depends on the hit's shading normal
// (dprsm_hit_radiance), and with the plane normal alone the far side of a smoothed edge is lit as
// its flat face (+2 % of Sponza's one-bounce light). A host that has the corners passes them here,
// in the grid's triangle order, and triangle_voxel_tracer hands back the interpolated normal, as an
// exact ray tracer over the same mesh does.
#include <vplkit/core/vector.hpp>

#include <cmath>
#include <cstddef>
#include <cstdint>

namespace vplkit {

template <class T>
struct triangle_corner_view {
  const vec3<T>* positions = nullptr;  // 3 per triangle: the corners, in the grid's triangle order
  const vec3<T>* normals = nullptr;    // 3 per triangle: the corners' shading normals (any length)
  std::size_t triangle_count = 0;
  bool has_normals() const { return positions != nullptr && normals != nullptr && triangle_count > 0; }
};

// The shading normal at p (a point on triangle t, or within rounding of it): the corners' normals
// weighted by p's barycentric coordinates (clamped to the triangle), unit. Zero, which ray_hit reads
// as "none", when the view has no normals, t is out of range, the triangle is degenerate or the
// weighted normals cancel or overflow.
template <class T>
inline vec3<T> triangle_corner_shading_normal(const triangle_corner_view<T>& c, std::uint32_t t, vec3<T> p) {
  if (!c.has_normals() || std::size_t(t) >= c.triangle_count) return vec3<T>(T(0));
  const vec3<T>* q = c.positions + 3 * std::size_t(t);
  const vec3<T>* n = c.normals + 3 * std::size_t(t);
  const vec3<T> e1 = q[1] - q[0], e2 = q[2] - q[0], d = p - q[0];
  const T d11 = glm::dot(e1, e1), d12 = glm::dot(e1, e2), d22 = glm::dot(e2, e2);
  const T det = d11 * d22 - d12 * d12;
  if (!(det > T(0)) || !std::isfinite(det)) return vec3<T>(T(0));
  const T r1 = glm::dot(d, e1), r2 = glm::dot(d, e2);
  T u = (d22 * r1 - d12 * r2) / det, v = (d11 * r2 - d12 * r1) / det;
  // A hit found within the grid's slack of an edge may lie a hair outside: clamp to the triangle.
  u = std::fmin(std::fmax(u, T(0)), T(1));
  v = std::fmin(std::fmax(v, T(0)), T(1) - u);
  const vec3<T> s = (T(1) - u - v) * n[0] + u * n[1] + v * n[2];
  const T len = std::sqrt(glm::dot(s, s));
  if (!(len > T(0)) || !std::isfinite(len)) return vec3<T>(T(0));
  return s / len;
}

}  // namespace vplkit
