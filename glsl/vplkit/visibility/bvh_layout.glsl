// SPDX-License-Identifier: MIT
// vplkit GLSL pack: the flat arrays of a BVH over triangles, as the host builds them (mirrors
// include/vplkit/visibility/bvh_layout.hpp, T = float; build with vplkit::build_bvh<float> and
// upload bvh<float>::nodes() and triangles() as they are).
//
// std430 layout (the C++ static_asserts pin the same offsets; parity_bvh_test reads every field
// back bit for bit):
//   vplkit_bvh_node     { vec3 bounds_min; uint first; vec3 bounds_max; uint count; }   32 bytes
//   vplkit_bvh_triangle { vec3 v0; uint id; vec3 v1; uint unused1; vec3 v2; uint unused2; }  48 bytes
// Node 0 is the root. Inner node: count == 0, children `first` and `first + 1`. Leaf:
// 1 <= count <= vplkit_bvh_max_leaf_size triangles [first, first + count). `id` is the
// triangle's index in the host's input. Depth <= vplkit_bvh_max_depth (the traversal's stack).
//
// ACCESSORS (the including shader defines both; it chooses the buffers and their bindings):
//   vplkit_bvh_node vplkit_load_bvh_node(uint index);
//   vplkit_bvh_triangle vplkit_load_bvh_triangle(uint slot);
// e.g.
//   layout(std430, binding = 4) readonly buffer BvhNodes { vplkit_bvh_node bvh_nodes[]; };
//   layout(std430, binding = 5) readonly buffer BvhTriangles { vplkit_bvh_triangle bvh_triangles[]; };
//   vplkit_bvh_node vplkit_load_bvh_node(uint i) { return bvh_nodes[i]; }
//   vplkit_bvh_triangle vplkit_load_bvh_triangle(uint i) { return bvh_triangles[i]; }
// (include this file before declaring the buffers: they use its structs). An empty hierarchy
// (node_count 0) reads nothing, but Mesa still wants both functions defined: bind a one-element
// dummy buffer.
#ifndef VPLKIT_VISIBILITY_BVH_LAYOUT_GLSL
#define VPLKIT_VISIBILITY_BVH_LAYOUT_GLSL

const int vplkit_bvh_max_depth = 32;      // deepest leaf depth + 1; the traversal stack's size
const int vplkit_bvh_max_leaf_size = 16;  // most triangles in one leaf

struct vplkit_bvh_node {
  vec3 bounds_min;
  uint first;  // inner: first child (the second is first + 1); leaf: first triangle slot
  vec3 bounds_max;
  uint count;  // inner: 0; leaf: number of triangles
};

struct vplkit_bvh_triangle {
  vec3 v0;
  uint id;  // the triangle's index in the host's input
  vec3 v1;
  uint unused1;
  vec3 v2;
  uint unused2;
};

// Mirrors bvh_view<float> without the pointers (the accessors stand for them).
struct vplkit_bvh {
  uint node_count;  // 0: empty, every query misses
};

vplkit_bvh_node vplkit_load_bvh_node(uint index);
vplkit_bvh_triangle vplkit_load_bvh_triangle(uint slot);

#endif  // VPLKIT_VISIBILITY_BVH_LAYOUT_GLSL
