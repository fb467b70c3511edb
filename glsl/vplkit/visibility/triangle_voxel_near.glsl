// SPDX-License-Identifier: MIT
// vplkit GLSL pack: is another surface near a point? Mirrors
// include/vplkit/visibility/triangle_voxel_near.hpp (T = float): conservative, false only when every
// triangle listed by the voxels around x within reach lies in a plane through x (within
// plane_tolerance) or farther than reach; true also when the box is wider than
// vplkit_voxel_near_max_side voxels or x, reach are not finite. The clamp compensation asks it
// before tracing (estimators/clamp_compensation.glsl). ACCESSORS: those of triangle_voxel_grid.glsl.
// The plane distances are `precise` and in the C++ order (vplkit_voxel_dot: glm::dot's). As in the
// C++, the box's rows along x are read from the one or two occupancy words that hold them.
//
// With #define VPLKIT_VOXEL_NEAR_PLANES before the first include, the shader also defines the
// ACCESSOR
//   vec4 vplkit_load_voxel_near_plane(uint occupied_index);  // the grid's planes[r]
// e.g. layout(std430, binding = 15) readonly buffer Planes { vec4 planes[]; };
//      vec4 vplkit_load_voxel_near_plane(uint r) { return planes[r]; }
// (a buffer of C++ voxel_plane<float> as it is, triangle_voxel_grid.hpp's planes), and the test
// asks one plane per voxel whose triangles share one, as the C++ with planes does. Without it
// every listed triangle is asked; the answers are the same either way.
#ifndef VPLKIT_VISIBILITY_TRIANGLE_VOXEL_NEAR_GLSL
#define VPLKIT_VISIBILITY_TRIANGLE_VOXEL_NEAR_GLSL

#include "vplkit/visibility/triangle_voxel_grid.glsl"
#include "vplkit/visibility/voxel_grid.glsl"

const int vplkit_voxel_near_max_side = 8;

#ifdef VPLKIT_VOXEL_NEAR_PLANES
vec4 vplkit_load_voxel_near_plane(uint occupied_index);

// The "several planes" mark (normal 0, offset 1): scan the voxel's triangles.
bool vplkit_voxel_plane_is_several(vec4 p) {
  return p.w != 0.0 && p.x == 0.0 && p.y == 0.0 && p.z == 0.0;
}
#endif

// Is the plane farther than plane_tolerance from x and not farther than reach? (NaN: no.)
bool vplkit_voxel_near_plane_within(vec4 plane, vec3 x, float reach, float plane_tolerance) {
  precise float s = abs(vplkit_voxel_dot(plane.xyz, x) - plane.w);
  return s > plane_tolerance && s <= reach;
}

// Bits lo .. hi of a word (0 <= lo <= hi <= 31).
uint vplkit_voxel_near_bit_range(uint lo, uint hi) {
  uint upto = hi == 31u ? 0xFFFFFFFFu : (1u << (hi + 1u)) - 1u;
  return upto & ~((1u << lo) - 1u);
}

// Does occupied voxel r hold a surface other than x's planes within reach? (C++:
// detail::voxel_near_voxel_within.)
bool vplkit_voxel_near_voxel_within(uint r, vec3 x, float reach, float plane_tolerance) {
#ifdef VPLKIT_VOXEL_NEAR_PLANES
  vec4 shared_plane = vplkit_load_voxel_near_plane(r);
  if (!vplkit_voxel_plane_is_several(shared_plane))  // one plane for the voxel
    return vplkit_voxel_near_plane_within(shared_plane, x, reach, plane_tolerance);
#endif
  uint end = vplkit_load_voxel_offset(r + 1u);
  for (uint e = vplkit_load_voxel_offset(r); e < end; ++e)
    if (vplkit_voxel_near_plane_within(vplkit_load_voxel_triangle(4u * vplkit_load_voxel_entry(e)), x, reach,
                                       plane_tolerance))
      return true;
  return false;
}

// The occupied voxels among bits lo .. hi of occupancy word w.
bool vplkit_voxel_near_word_within(uint w, uint lo, uint hi, vec3 x, float reach, float plane_tolerance) {
  uint word = vplkit_load_voxel_word(w);
  uint bits = word & vplkit_voxel_near_bit_range(lo, hi);
  uint base = bits != 0u ? vplkit_load_voxel_rank(w) : 0u;
  for (int k = 0; k < 32 && bits != 0u; ++k) {  // at most 8 bits are set (a row of the box)
    int b = findLSB(bits);
    if (vplkit_voxel_near_voxel_within(base + uint(bitCount(word & ((1u << uint(b)) - 1u))), x, reach, plane_tolerance))
      return true;
    bits &= bits - 1u;
  }
  return false;
}

bool vplkit_triangle_voxel_surface_within(vplkit_voxel_grid g, vec3 x, float reach, float plane_tolerance) {
  if (!vplkit_voxel_vec3_finite(x) || !(reach >= 0.0) || !(reach <= 3.4028234663852886e38) ||
      !(plane_tolerance >= 0.0))
    return true;
  float slack = 1e-3;
  precise vec3 c = vplkit_world_to_voxel_coord(g, x);
  precise vec3 r = reach / vplkit_voxel_size(g);
  precise vec3 lo = c - r - vec3(slack);
  precise vec3 hi = c + r + vec3(slack);
  ivec3 a = ivec3(vplkit_voxel_floor_to_int(lo.x), vplkit_voxel_floor_to_int(lo.y), vplkit_voxel_floor_to_int(lo.z));
  ivec3 b = ivec3(vplkit_voxel_floor_to_int(hi.x), vplkit_voxel_floor_to_int(hi.y), vplkit_voxel_floor_to_int(hi.z));
  if (b.x - a.x >= vplkit_voxel_near_max_side || b.y - a.y >= vplkit_voxel_near_max_side ||
      b.z - a.z >= vplkit_voxel_near_max_side)
    return true;
  // The box's rows along x, each from its one or two occupancy words (C++: the same walk).
  a = max(a, ivec3(0));
  b = min(b, g.resolution - ivec3(1));
  if (a.x > b.x) return false;
  for (int z = a.z; z <= b.z; ++z)
    for (int y = a.y; y <= b.y; ++y) {
      uint row = vplkit_voxel_flat_index(g.resolution, ivec3(0, y, z));
      uint i0 = row + uint(a.x), i1 = row + uint(b.x);
      for (uint w = i0 >> 5u; w <= i1 >> 5u; ++w)  // one word, or two
        if (vplkit_voxel_near_word_within(w, w == i0 >> 5u ? (i0 & 31u) : 0u, w == i1 >> 5u ? (i1 & 31u) : 31u, x,
                                          reach, plane_tolerance))
          return true;
    }
  return false;
}

#endif  // VPLKIT_VISIBILITY_TRIANGLE_VOXEL_NEAR_GLSL
