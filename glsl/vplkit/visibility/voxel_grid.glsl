// SPDX-License-Identifier: MIT
// vplkit GLSL pack: binary occupancy grid over an axis-aligned box (mirrors
// include/vplkit/visibility/voxel_grid.hpp, T = float).
//
// Layout (identical to the C++ voxel_grid, so one buffer serves both sides):
//   voxel (x, y, z), 0 <= x < nx etc.; flat index  i = x + y * nx + z * nx * ny  (uint)
//   word = i >> 5, bit = i & 31, occupied  <=>  (word >> bit) & 1u
//   word count = ceil(nx * ny * nz / 32); unused bits of the last word are 0.
// Geometry: voxel_size = (bounds_max - bounds_min) / vec3(resolution); voxel v is the CLOSED box
// [bounds_min + v * voxel_size, bounds_min + (v + 1) * voxel_size].
//
// ACCESSOR (the including shader defines it; it chooses the buffer and its binding):
//   uint vplkit_load_voxel_word(uint word_index);
//     word `word_index` of the grid's bit array, e.g.
//       layout(std430, binding = 3) readonly buffer Voxels { uint voxel_words[]; };
//       uint vplkit_load_voxel_word(uint i) { return voxel_words[i]; }
//
// Arithmetic that decides integer results (voxel indices) is `precise` and written out as the C++
// evaluates it (glm::dot is (x*x' + y*y') + z*z'; GLSL dot()/length() may fuse or reorder), so an
// implementation with IEEE add/mul/div/sqrt reproduces the C++ float results bit for bit.
#ifndef VPLKIT_VISIBILITY_VOXEL_GRID_GLSL
#define VPLKIT_VISIBILITY_VOXEL_GRID_GLSL

#include "vplkit/core/normal_range.glsl"

// Mirrors voxel_grid_view<float> without the word pointer (the accessor stands for it).
struct vplkit_voxel_grid {
  vec3 bounds_min;
  vec3 bounds_max;
  ivec3 resolution;
};

uint vplkit_load_voxel_word(uint word_index);

// Largest resolution per axis and largest voxel count (2^31), as in the C++ (validation is the
// host's job; listed so the host can check against the same numbers).
const int vplkit_voxel_grid_max_axis = 4096;

// Finite test on the bits: immune to drivers that assume no NaN/Inf under fast math.
bool vplkit_voxel_isfinite(float x) { return vplkit_is_finite(x); }

bool vplkit_voxel_vec3_finite(vec3 p) {
  return vplkit_voxel_isfinite(p.x) && vplkit_voxel_isfinite(p.y) && vplkit_voxel_isfinite(p.z);
}

// glm::dot order, unfused.
float vplkit_voxel_dot(vec3 a, vec3 b) {
  precise float r = a.x * b.x + a.y * b.y + a.z * b.z;
  return r;
}

uint vplkit_voxel_word_count(ivec3 resolution) {
  uint n = uint(resolution.x) * uint(resolution.y) * uint(resolution.z);
  return (n + 31u) / 32u;
}

// Flat index of voxel v (no bounds check). uint: up to 2^31 voxels (the C++ returns int64).
uint vplkit_voxel_flat_index(ivec3 resolution, ivec3 v) {
  return uint(v.x) + uint(v.y) * uint(resolution.x) + uint(v.z) * uint(resolution.x) * uint(resolution.y);
}

bool vplkit_voxel_in_grid(ivec3 resolution, ivec3 v) {
  return v.x >= 0 && v.y >= 0 && v.z >= 0 && v.x < resolution.x && v.y < resolution.y && v.z < resolution.z;
}

vec3 vplkit_voxel_size(vplkit_voxel_grid g) {
  precise vec3 s = (g.bounds_max - g.bounds_min) / vec3(g.resolution);
  return s;
}

// Largest voxel edge: the "one voxel" length used by offsets and tolerances.
float vplkit_voxel_length(vplkit_voxel_grid g) {
  vec3 s = vplkit_voxel_size(g);
  return s.x > s.y ? (s.x > s.z ? s.x : s.z) : (s.y > s.z ? s.y : s.z);
}

// Occupancy of voxel v; false outside the grid.
bool vplkit_voxel_test(vplkit_voxel_grid g, ivec3 v) {
  if (!vplkit_voxel_in_grid(g.resolution, v)) return false;
  uint i = vplkit_voxel_flat_index(g.resolution, v);
  return ((vplkit_load_voxel_word(i >> 5u) >> (i & 31u)) & 1u) != 0u;
}

// Continuous voxel coordinate of world point p (voxel v covers [v, v + 1) per axis).
vec3 vplkit_world_to_voxel_coord(vplkit_voxel_grid g, vec3 p) {
  precise vec3 c = (p - g.bounds_min) / vplkit_voxel_size(g);
  return c;
}

// floor(c) as an int, saturated to +-2^30 (NaN goes to -2^30): far-away or non-finite points give
// an index outside the grid instead of an undefined float-to-int conversion.
int vplkit_voxel_floor_to_int(float c) {
  const float lim = 1073741824.0;
  // NaN by its bits (some drivers fold NaN comparisons); +-Inf compare normally below.
  if (vplkit_is_nan(c)) return -1073741824;
  if (!(c > -lim)) return -1073741824;
  if (c >= lim) return 1073741824;
  return int(floor(c));
}

// Voxel containing p: floor of the continuous coordinate, NOT clamped (may lie outside the grid).
ivec3 vplkit_world_to_voxel(vplkit_voxel_grid g, vec3 p) {
  vec3 c = vplkit_world_to_voxel_coord(g, p);
  return ivec3(vplkit_voxel_floor_to_int(c.x), vplkit_voxel_floor_to_int(c.y), vplkit_voxel_floor_to_int(c.z));
}

// World position of the continuous voxel coordinate c (c = v gives the voxel's min corner).
vec3 vplkit_voxel_to_world(vplkit_voxel_grid g, vec3 c) {
  precise vec3 p = g.bounds_min + c * vplkit_voxel_size(g);
  return p;
}

vec3 vplkit_voxel_center(vplkit_voxel_grid g, ivec3 v) {
  return vplkit_voxel_to_world(g, vec3(v) + vec3(0.5));
}

#endif  // VPLKIT_VISIBILITY_VOXEL_GRID_GLSL
