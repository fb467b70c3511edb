// SPDX-License-Identifier: MIT
#pragma once
// Empty-space skipping for the voxel march: a coarse occupancy level over bricks of
// voxel_brick_edge^3 voxels (a brick is occupied when any of its voxels is), and the walk's exit
// from an empty brick in one move (dda_walk_leave_brick).
//
// Layout (shared with the GPU, glsl/vplkit/visibility/voxel_bricks.glsl):
//   brick resolution = ceil(resolution / voxel_brick_edge) per axis; brick (bx, by, bz) holds the
//   voxels v with v / voxel_brick_edge = (bx, by, bz) (partial bricks at the grid's max faces);
//   flat index j = bx + by * rx + bz * rx * ry, word j >> 5, bit j & 31, as voxel_grid's words.
// 4^3 voxels per brick: 32^3 bits (4 KiB) for a 128^3 grid, small enough to stay in the caches
// that serve the march.
//
// EXACTNESS. dda_walk_leave_brick leaves the walk in the state that repeated dda_walk_next would
// reach when it first enters a voxel outside the brick (same voxel, same t, same t_next, bit for
// bit), or ends it where dda_walk_next would have ended it inside the brick. Why: every crossing
// distance is the pure function t(a, k) = (bounds_min[a] + k * size[a] - origin[a]) / d[a] of the
// plane (the walk recomputes it from the plane, it never accumulates), non-decreasing along the
// walk on each axis (each operation is monotonic), and dda_walk_next takes the smallest head, x
// before y before z on ties: a merge of three sorted lists, so it crosses the planes in the order
// of the key (t, axis). The walk leaves the brick through the exit face with the smallest key;
// before that it crosses exactly the planes with a smaller key, which this function counts on
// each other axis. Since a march tests only occupied voxels, one that jumps over empty bricks
// visits the same occupied voxels in the same states as one that steps through them: every
// answer is unchanged, bit for bit.
#include <vplkit/core/vector.hpp>
#include <vplkit/visibility/dda.hpp>
#include <vplkit/visibility/voxel_grid.hpp>
#include <vplkit/visibility/voxel_rank.hpp>

#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

namespace vplkit {

// Voxels per brick edge (a power of two; the same constant in the GLSL pack).
constexpr int voxel_brick_edge = 4;

inline ivec3 voxel_brick_resolution(ivec3 resolution) {
  return ivec3((resolution.x + voxel_brick_edge - 1) / voxel_brick_edge,
               (resolution.y + voxel_brick_edge - 1) / voxel_brick_edge,
               (resolution.z + voxel_brick_edge - 1) / voxel_brick_edge);
}

// The brick occupancy words of a grid of `resolution` (what voxel_brick_words returns).
inline std::size_t voxel_brick_word_count(ivec3 resolution) {
  return voxel_word_count(voxel_brick_resolution(resolution));
}

// The brick occupancy of grid g: one pass over its occupied voxels.
template <class T>
inline std::vector<std::uint32_t> voxel_brick_words(const voxel_grid_view<T>& g) {
  const ivec3 r = g.resolution;
  const ivec3 br = voxel_brick_resolution(r);
  std::vector<std::uint32_t> bricks(voxel_word_count(br), 0u);
  const std::size_t words = voxel_word_count(r);
  const std::int64_t plane = std::int64_t(r.x) * r.y;
  for (std::size_t w = 0; w < words; ++w) {
    std::uint32_t bits = g.words[w];
    while (bits != 0u) {
      const int b = voxel_bit_count((bits & (0u - bits)) - 1u);  // lowest set bit
      bits &= bits - 1u;
      const std::int64_t i = std::int64_t(w) * 32 + b;
      const ivec3 v(int(i % r.x), int((i / r.x) % r.y), int(i / plane));
      const std::int64_t j = voxel_flat_index(br, v / voxel_brick_edge);
      bricks[std::size_t(j >> 5)] |= 1u << std::uint32_t(j & 31);
    }
  }
  return bricks;
}

// Is the brick of voxel v (inside the grid) occupied? `bricks`: voxel_brick_words of the grid.
inline bool voxel_brick_occupied(ivec3 resolution, const std::uint32_t* bricks, ivec3 v) {
  const std::int64_t j = voxel_flat_index(voxel_brick_resolution(resolution), v / voxel_brick_edge);
  return ((bricks[std::size_t(j >> 5)] >> std::uint32_t(j & 31)) & 1u) != 0u;
}

// The walk's crossing distance of plane k on axis a (dda_walk_begin's and dda_walk_next's
// expression, operation for operation).
template <class T>
inline T dda_walk_plane_t(const voxel_grid_view<T>& g, const dda_walk<T>& w, int a, int k) {
  return (g.bounds_min[a] + T(k) * w.size[a] - w.origin[a]) / w.d[a];
}

// (t, axis) < (t_exit, axis_exit): does the walk cross plane t on `axis` before the exit event?
template <class T>
inline bool dda_crosses_before(T t, int axis, T t_exit, int axis_exit) {
  return t < t_exit || (t == t_exit && axis < axis_exit);
}

// Moves a running walk out of the brick of its current voxel (see EXACTNESS above): the caller has
// found that brick empty, so no voxel in it needs a test. Returns w.running.
template <class T>
inline bool dda_walk_leave_brick(const voxel_grid_view<T>& g, dda_walk<T>& w) {
  // The exit face on each axis: the brick's far face along the step (the grid's max face for a
  // partial brick); leaving the brick there either enters the next brick or leaves the grid.
  vec3<T> t_exit(std::numeric_limits<T>::max());
  ivec3 exit_plane(0);
  for (int a = 0; a < 3; ++a) {
    if (w.step[a] == 0) continue;  // t_exit stays t_next's value for step 0
    const int lo = (w.voxel[a] / voxel_brick_edge) * voxel_brick_edge;
    const int hi = lo + voxel_brick_edge < g.resolution[a] ? lo + voxel_brick_edge : g.resolution[a];
    const int k = w.step[a] > 0 ? hi : lo;
    const int next = w.step[a] > 0 ? w.voxel[a] + 1 : w.voxel[a];  // the plane of t_next[a]
    exit_plane[a] = k;
    t_exit[a] = k == next ? w.t_next[a] : dda_walk_plane_t(g, w, a, k);
  }
  const int e = (t_exit.x <= t_exit.y && t_exit.x <= t_exit.z) ? 0 : (t_exit.y <= t_exit.z ? 1 : 2);
  // Every crossing before the exit event lies at or before t_exit[e]: only the exit event can end
  // the walk (dda_walk_next's tests, in its order).
  if (w.step[e] == 0 || t_exit[e] > w.t_max) {
    w.running = false;
    return false;
  }
  // The other axes: the planes crossed before the exit event (fewer than a brick edge each).
  for (int a = 0; a < 3; ++a) {
    if (a == e || w.step[a] == 0) continue;
    for (int n = 1; n < voxel_brick_edge && dda_crosses_before(w.t_next[a], a, t_exit[e], e); ++n) {
      w.voxel[a] += w.step[a];
      w.t_next[a] = dda_walk_plane_t(g, w, a, w.step[a] > 0 ? w.voxel[a] + 1 : w.voxel[a]);
    }
  }
  w.voxel[e] = w.step[e] > 0 ? exit_plane[e] : exit_plane[e] - 1;
  if (w.voxel[e] < 0 || w.voxel[e] >= g.resolution[e]) {
    w.running = false;
    return false;
  }
  w.t = t_exit[e] > w.t ? t_exit[e] : w.t;
  w.t_next[e] = dda_walk_plane_t(g, w, e, w.step[e] > 0 ? w.voxel[e] + 1 : w.voxel[e]);
  return true;
}

}  // namespace vplkit
