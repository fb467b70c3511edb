// SPDX-License-Identifier: MIT
// vplkit GLSL pack: the triangle voxel grid (mirrors include/vplkit/visibility/triangle_voxel_grid.hpp,
// T = float): occupied voxels list the triangles that overlap them.
//
// Layout (identical to the C++ triangle_voxel_grid, so one set of buffers serves both sides):
//   occupancy words: voxel_grid.glsl (accessor vplkit_load_voxel_word);
//   rank[w]: occupied voxels in words 0 .. w-1; an occupied voxel with flat index i has the dense
//     index r = rank[i >> 5] + bitCount(words[i >> 5] & ((1u << (i & 31)) - 1u));
//   offsets[r], r = 0 .. occupied: voxel r lists entries[offsets[r] .. offsets[r + 1]);
//   entries: triangle indices; triangles: four vec4 per triangle, (normal, offset) of its plane,
//     then of its three edges' inward planes (all zero for a degenerate triangle).
//
// ACCESSORS (the including shader defines them; it chooses the buffers and their bindings):
//   uint vplkit_load_voxel_word(uint word_index);     // voxel_grid.glsl
//   uint vplkit_load_voxel_rank(uint word_index);     // voxel_rank.glsl
//   uint vplkit_load_voxel_offset(uint index);        // offsets[index], index <= occupied
//   uint vplkit_load_voxel_entry(uint index);         // entries[index]
//   vec4 vplkit_load_voxel_triangle(uint index);      // triangles as vec4: 4 * triangle + row
// e.g. layout(std430, binding = 7) readonly buffer Rank { uint rank[]; };
//      uint vplkit_load_voxel_rank(uint i) { return rank[i]; }
// A buffer of C++ voxel_triangle<float> is a vec4 array as it is (64 bytes per triangle).
#ifndef VPLKIT_VISIBILITY_TRIANGLE_VOXEL_GRID_GLSL
#define VPLKIT_VISIBILITY_TRIANGLE_VOXEL_GRID_GLSL

#include "vplkit/visibility/voxel_grid.glsl"
#include "vplkit/visibility/voxel_rank.glsl"

uint vplkit_load_voxel_offset(uint index);
uint vplkit_load_voxel_entry(uint index);
vec4 vplkit_load_voxel_triangle(uint index);

// Mirrors voxel_triangle<float>: plane.xyz = normal, plane.w = offset; likewise edge[i].
struct vplkit_voxel_triangle {
  vec4 plane;
  vec4 edge[3];
};

vplkit_voxel_triangle vplkit_voxel_triangle_at(uint triangle) {
  uint b = 4u * triangle;
  vec4 e[3] = vec4[3](vplkit_load_voxel_triangle(b + 1u), vplkit_load_voxel_triangle(b + 2u),
                      vplkit_load_voxel_triangle(b + 3u));
  return vplkit_voxel_triangle(vplkit_load_voxel_triangle(b), e);
}

// Is p (on the triangle's plane) inside the triangle grown by `slack` (world units)? Written
// without a loop: llvmpipe counts every loop iteration against its per-invocation budget.
bool vplkit_voxel_triangle_contains(vplkit_voxel_triangle tri, vec3 p, float slack) {
  precise float s0 = vplkit_voxel_dot(tri.edge[0].xyz, p) - tri.edge[0].w;
  precise float s1 = vplkit_voxel_dot(tri.edge[1].xyz, p) - tri.edge[1].w;
  precise float s2 = vplkit_voxel_dot(tri.edge[2].xyz, p) - tri.edge[2].w;
  return s0 >= -slack && s1 >= -slack && s2 >= -slack;
}

// vplkit_voxel_triangle_contains(vplkit_voxel_triangle_at(triangle), p, slack), loading only the
// three edge planes: the queries read a triangle's plane first and its edges only for a crossing.
bool vplkit_voxel_triangle_contains_at(uint triangle, vec3 p, float slack) {
  uint b = 4u * triangle;
  vec4 e0 = vplkit_load_voxel_triangle(b + 1u);
  vec4 e1 = vplkit_load_voxel_triangle(b + 2u);
  vec4 e2 = vplkit_load_voxel_triangle(b + 3u);
  precise float s0 = vplkit_voxel_dot(e0.xyz, p) - e0.w;
  precise float s1 = vplkit_voxel_dot(e1.xyz, p) - e1.w;
  precise float s2 = vplkit_voxel_dot(e2.xyz, p) - e2.w;
  return s0 >= -slack && s1 >= -slack && s2 >= -slack;
}

#endif  // VPLKIT_VISIBILITY_TRIANGLE_VOXEL_GRID_GLSL
