// SPDX-License-Identifier: MIT
// vplkit GLSL pack: shading normals for the hits of a triangle voxel grid (mirrors
// include/vplkit/visibility/triangle_corners.hpp, T = float, statement for statement).
//
//   vplkit_triangle_corner_shading_normal(t, triangle_count, p): the corners' normals of triangle t
//     weighted by p's barycentric coordinates (clamped to the triangle), unit; vec3(0) ("none")
//     for t out of range, a degenerate triangle, or normals that cancel.
//
// ACCESSORS (the host's corners, 3 per triangle in the grid's triangle order, i = 3 t + k):
//   vec3 vplkit_load_triangle_corner_position(uint i);
//   vec3 vplkit_load_triangle_corner_normal(uint i);
//
// Parity: the barycentrics are `precise` in the C++ order; the division and the square root are
// the GPU's (within the spec's ulps), so the normal agrees to a few ulps, not bit for bit.
#ifndef VPLKIT_VISIBILITY_TRIANGLE_CORNERS_GLSL
#define VPLKIT_VISIBILITY_TRIANGLE_CORNERS_GLSL

#include "vplkit/visibility/voxel_grid.glsl"

vec3 vplkit_load_triangle_corner_position(uint i);
vec3 vplkit_load_triangle_corner_normal(uint i);

vec3 vplkit_triangle_corner_shading_normal(uint t, uint triangle_count, vec3 p) {
  if (t >= triangle_count) return vec3(0.0);
  vec3 q0 = vplkit_load_triangle_corner_position(3u * t);
  vec3 q1 = vplkit_load_triangle_corner_position(3u * t + 1u);
  vec3 q2 = vplkit_load_triangle_corner_position(3u * t + 2u);
  precise vec3 e1 = q1 - q0;
  precise vec3 e2 = q2 - q0;
  precise vec3 d = p - q0;
  precise float d11 = vplkit_voxel_dot(e1, e1);
  precise float d12 = vplkit_voxel_dot(e1, e2);
  precise float d22 = vplkit_voxel_dot(e2, e2);
  precise float det = d11 * d22 - d12 * d12;
  if (!(det > 0.0) || !vplkit_voxel_isfinite(det)) return vec3(0.0);
  precise float r1 = vplkit_voxel_dot(d, e1);
  precise float r2 = vplkit_voxel_dot(d, e2);
  precise float u = (d22 * r1 - d12 * r2) / det;
  precise float v = (d11 * r2 - d12 * r1) / det;
  // A hit found within the grid's slack of an edge may lie a hair outside: clamp to the triangle.
  u = min(max(u, 0.0), 1.0);
  v = min(max(v, 0.0), 1.0 - u);
  precise vec3 s = (1.0 - u - v) * vplkit_load_triangle_corner_normal(3u * t) +
                   u * vplkit_load_triangle_corner_normal(3u * t + 1u) + v * vplkit_load_triangle_corner_normal(3u * t + 2u);
  precise float len = sqrt(vplkit_voxel_dot(s, s));
  if (!(len > 0.0) || !vplkit_voxel_isfinite(len)) return vec3(0.0);
  return s / len;
}

#endif  // VPLKIT_VISIBILITY_TRIANGLE_CORNERS_GLSL
