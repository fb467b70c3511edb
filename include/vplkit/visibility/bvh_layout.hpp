// SPDX-License-Identifier: MIT
#pragma once
// The flat arrays of a bounding volume hierarchy over triangles, laid out exactly as the GLSL pack
// reads them (glsl/vplkit/visibility/bvh_layout.glsl). For T = float, one bvh_node is the std430
// struct { vec3 bounds_min; uint first; vec3 bounds_max; uint count; } (32 bytes) and one
// bvh_triangle is { vec3 v0; uint id; vec3 v1; uint unused1; vec3 v2; uint unused2; } (48 bytes):
// a std430 vec3 takes 12 bytes at a 16-byte boundary and the uint after it fills the 4 bytes left,
// which is where glm's 12-byte vec3 puts it too. The static_asserts below pin the C++ half, and
// parity_bvh_test reads every field of every node and triangle back from the GPU, bit for bit.
//
// Tree: node 0 is the root. An inner node has count == 0 and its two children at `first` and
// `first + 1` (always adjacent, so a traversal can test both boxes at once). A leaf has
// 1 <= count <= bvh_max_leaf_size and holds triangles [first, first + count) of the triangle array,
// which the builder reorders so that every leaf's triangles are contiguous; bvh_triangle::id is
// the triangle's index in the caller's input. An empty hierarchy has no nodes and no triangles.
//
// Bounds: every node's box is the exact (float min / max, no rounding) box of its triangles'
// vertices, so it contains its children's boxes and its triangles.
#include <vplkit/core/vector.hpp>

#include <cstddef>
#include <cstdint>
#include <type_traits>

namespace vplkit {

// Deepest leaf depth + 1 (the root has depth 0). A traversal keeps at most one deferred node per
// level on its stack, so a stack of bvh_max_depth entries never overflows. The builder meets the
// limit for any input (see bvh_build.hpp).
constexpr int bvh_max_depth = 32;
// Largest number of triangles in one leaf (the leaf loop's bound in GLSL).
constexpr int bvh_max_leaf_size = 16;
// Largest triangle count: 2n - 1 nodes must fit a uint32 index.
constexpr std::size_t bvh_max_triangles = std::size_t(1) << 30;

template <class T>
struct bvh_node {
  vec3<T> bounds_min;
  std::uint32_t first;  // inner: index of the first child (the second is first + 1); leaf: first triangle
  vec3<T> bounds_max;
  std::uint32_t count;  // inner: 0; leaf: number of triangles (1 .. bvh_max_leaf_size)
};

template <class T>
struct bvh_triangle {
  vec3<T> v0;
  std::uint32_t id;  // the triangle's index in the builder's input
  vec3<T> v1;
  std::uint32_t unused1;  // 0 (std430 padding, kept defined so equal inputs give equal bytes)
  vec3<T> v2;
  std::uint32_t unused2;  // 0
};

static_assert(sizeof(vec3<float>) == 12, "glm vec3<float> must be 3 packed floats");
static_assert(std::is_standard_layout<bvh_node<float>>::value && std::is_trivially_copyable<bvh_node<float>>::value,
              "bvh_node<float> is uploaded as bytes");
static_assert(sizeof(bvh_node<float>) == 32, "bvh_node<float> must match the std430 struct vplkit_bvh_node");
static_assert(offsetof(bvh_node<float>, bounds_min) == 0 && offsetof(bvh_node<float>, first) == 12 &&
                  offsetof(bvh_node<float>, bounds_max) == 16 && offsetof(bvh_node<float>, count) == 28,
              "bvh_node<float> offsets must match std430 (vec3 at 0, uint at 12, vec3 at 16, uint at 28)");
static_assert(std::is_standard_layout<bvh_triangle<float>>::value &&
                  std::is_trivially_copyable<bvh_triangle<float>>::value,
              "bvh_triangle<float> is uploaded as bytes");
static_assert(sizeof(bvh_triangle<float>) == 48, "bvh_triangle<float> must match the std430 struct vplkit_bvh_triangle");
static_assert(offsetof(bvh_triangle<float>, v0) == 0 && offsetof(bvh_triangle<float>, id) == 12 &&
                  offsetof(bvh_triangle<float>, v1) == 16 && offsetof(bvh_triangle<float>, unused1) == 28 &&
                  offsetof(bvh_triangle<float>, v2) == 32 && offsetof(bvh_triangle<float>, unused2) == 44,
              "bvh_triangle<float> offsets must match std430");

// Non-owning view of the two arrays; what the traversal takes (and, for T = float, what a renderer
// uploads as two std430 buffers). Make one with bvh<T>::view() or make_bvh_view (which validates).
template <class T>
struct bvh_view {
  const bvh_node<T>* nodes = nullptr;
  std::size_t node_count = 0;
  const bvh_triangle<T>* triangles = nullptr;
  std::size_t triangle_count = 0;
};

}  // namespace vplkit
