// SPDX-License-Identifier: MIT
#pragma once
// A voxel grid whose occupied voxels list the triangles that overlap them, so that visibility is
// decided by the triangles themselves, not by their voxels (docs/math.md section 7.2). Queries:
// triangle_voxel_query.hpp; CPU construction: voxelize_triangles.hpp; GPU construction:
// glsl/vplkit/visibility/voxelize.comp (occupancy, count and fill modes) and prefix_sum.comp.
//
// Layout (shared with the GPU, which fills and reads the same arrays):
// - occupancy: the conservative binary voxel_grid of voxelize.hpp, unchanged (same margin);
// - rank[w]: the number of occupied voxels in words 0 .. w-1 (one uint32 per occupancy word). An
//   occupied voxel with flat index i has the dense index
//     r = rank[i >> 5] + bitCount(words[i >> 5] & ((1u << (i & 31)) - 1u));
// - offsets[r], r = 0 .. occupied: voxel r's list is entries[offsets[r] .. offsets[r + 1]);
// - entries: triangle indices (into triangles). A voxel lists every triangle whose overlap test
//   (voxelize's, with its margin) marked it, in ascending order when built on the CPU, in any
//   order when built on the GPU (no query depends on the order);
// - triangles[t]: voxel_triangle, four planes (normal, offset) in world coordinates: the
//   triangle's plane, then its three edges' inward planes (within the triangle's plane, through
//   the edge, normal pointing into the triangle). A degenerate triangle has all four zero and
//   never blocks. 64 bytes for T = float (four std430 vec4 on the GPU);
// - bricks: the occupancy's brick level (voxel_bricks.hpp), which the queries' marches use to jump
//   over empty bricks (same answers, fewer steps). Derived from the occupancy, not an input;
// - planes[r], r = 0 .. occupied - 1: the plane that every triangle voxel r lists lies in, when
//   they all have the same plane bit for bit (normal and offset equal as numbers), else the mark
//   voxel_planes_several (normal 0, offset 1; also for a voxel that lists nothing; no triangle's
//   plane looks like it: a degenerate one's is all zero). The near-surface test
//   (triangle_voxel_near.hpp) then asks one plane per voxel instead of one per listed triangle,
//   with the same answers (the same plane's numbers). Most occupied voxels hold one flat piece of
//   surface (a wall, a floor, a quad's two triangles); creases, corners and curved geometry are
//   several. Derived from the lists, not an input. 16 bytes per occupied voxel for T = float (one
//   std430 vec4 on the GPU).
#include <vplkit/core/error.hpp>
#include <vplkit/core/vector.hpp>
#include <vplkit/visibility/voxel_bricks.hpp>
#include <vplkit/visibility/voxel_grid.hpp>
#include <vplkit/visibility/voxel_rank.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace vplkit {

template <class T>
struct voxel_plane {
  vec3<T> normal;  // unit (zero for a degenerate triangle)
  T offset;        // normal . p = offset on the plane
};

template <class T>
struct voxel_triangle {
  voxel_plane<T> plane;    // the triangle's plane
  voxel_plane<T> edge[3];  // p is inside iff edge[i].normal . p - edge[i].offset >= 0 for i = 0, 1, 2
};
static_assert(sizeof(voxel_triangle<float>) == 64, "voxel_triangle<float> is four std430 vec4");
static_assert(sizeof(voxel_plane<float>) == 16, "voxel_plane<float> is one std430 vec4");

// The "several planes" mark of planes[r] (see the layout above) and its test.
template <class T>
inline voxel_plane<T> voxel_planes_several() {
  return voxel_plane<T>{vec3<T>(T(0)), T(1)};
}
template <class T>
inline bool voxel_plane_is_several(const voxel_plane<T>& p) {
  return p.offset != T(0) && p.normal.x == T(0) && p.normal.y == T(0) && p.normal.z == T(0);
}

// planes[r] for r = 0 .. occupied - 1 from the lists (entries already checked against triangles).
template <class T>
inline std::vector<voxel_plane<T>> voxel_shared_planes(const std::vector<std::uint32_t>& offsets,
                                                       const std::vector<std::uint32_t>& entries,
                                                       const std::vector<voxel_triangle<T>>& triangles) {
  const std::size_t occupied = offsets.empty() ? 0 : offsets.size() - 1;
  std::vector<voxel_plane<T>> planes(occupied, voxel_planes_several<T>());
  for (std::size_t r = 0; r < occupied; ++r) {
    if (offsets[r] >= offsets[r + 1]) continue;
    const voxel_plane<T>& first = triangles[entries[offsets[r]]].plane;
    bool shared = true;
    for (std::uint32_t e = offsets[r] + 1; shared && e < offsets[r + 1]; ++e) {
      const voxel_plane<T>& p = triangles[entries[e]].plane;
      shared = p.normal.x == first.normal.x && p.normal.y == first.normal.y && p.normal.z == first.normal.z &&
               p.offset == first.offset;
    }
    if (shared) planes[r] = first;
  }
  return planes;
}

template <class T>
struct triangle_voxel_view {
  voxel_grid_view<T> grid;              // the occupancy
  const std::uint32_t* rank;            // voxel_word_count(grid.resolution) entries
  const std::uint32_t* offsets;         // occupied + 1 entries
  const std::uint32_t* entries;         // offsets[occupied] entries
  const voxel_triangle<T>* triangles;   // triangle_count entries
  std::size_t occupied;                 // occupied voxels
  std::size_t triangle_count;
  // voxel_brick_words of the occupancy (voxel_brick_word_count(grid.resolution) words), or null:
  // the marches then step through empty bricks voxel by voxel (the same answers).
  const std::uint32_t* bricks = nullptr;
  // planes (occupied entries), or null: the near-surface test then scans every voxel's triangles
  // (the same answers).
  const voxel_plane<T>* planes = nullptr;

  std::size_t entry_count() const { return offsets[occupied]; }
  // The longest list (a bound for loop budgets: a ray tests at most this many triangles per voxel).
  std::uint32_t max_entries_per_voxel() const {
    std::uint32_t m = 0;
    for (std::size_t r = 0; r < occupied; ++r) m = std::max(m, offsets[r + 1] - offsets[r]);
    return m;
  }
};

template <class T>
class triangle_voxel_grid {
public:
  // Adopts the arrays of the layout above (from voxelize_triangles, or read back from the GPU)
  // after checking them: rank equal to the occupancy's prefix sums, offsets non-decreasing from 0
  // to entries.size(), one more than the occupied voxels, every entry a triangle index.
  triangle_voxel_grid(voxel_grid<T> occupancy, std::vector<std::uint32_t> rank, std::vector<std::uint32_t> offsets,
                      std::vector<std::uint32_t> entries, std::vector<voxel_triangle<T>> triangles)
      : occ_(std::move(occupancy)), rank_(std::move(rank)), offsets_(std::move(offsets)), entries_(std::move(entries)),
        tris_(std::move(triangles)), bricks_(voxel_brick_words(occ_.view())) {
    if (rank_ != voxel_occupancy_rank(occ_.data(), occ_.word_count()))
      throw invalid_input("triangle_voxel_grid: rank does not match the occupancy's prefix sums");
    const std::size_t occupied = std::size_t(occ_.count());
    if (offsets_.size() != occupied + 1)
      throw invalid_input("triangle_voxel_grid: " + std::to_string(offsets_.size()) + " offsets given, " +
                          std::to_string(occupied + 1) + " needed (occupied voxels + 1)");
    if (offsets_.front() != 0u || offsets_.back() != entries_.size())
      throw invalid_input("triangle_voxel_grid: offsets must run from 0 to the entry count " +
                          std::to_string(entries_.size()));
    for (std::size_t r = 0; r < occupied; ++r)
      if (offsets_[r] > offsets_[r + 1])
        throw invalid_input("triangle_voxel_grid: offsets decrease at occupied voxel " + std::to_string(r));
    for (std::size_t i = 0; i < entries_.size(); ++i)
      if (entries_[i] >= tris_.size())
        throw invalid_input("triangle_voxel_grid: entry " + std::to_string(i) + " is triangle " +
                            std::to_string(entries_[i]) + " of " + std::to_string(tris_.size()));
    planes_ = voxel_shared_planes(offsets_, entries_, tris_);
  }

  const voxel_grid<T>& occupancy() const { return occ_; }
  const std::vector<std::uint32_t>& rank() const { return rank_; }
  const std::vector<std::uint32_t>& offsets() const { return offsets_; }
  const std::vector<std::uint32_t>& entries() const { return entries_; }
  const std::vector<voxel_triangle<T>>& triangles() const { return tris_; }
  const std::vector<std::uint32_t>& bricks() const { return bricks_; }
  const std::vector<voxel_plane<T>>& planes() const { return planes_; }
  std::int64_t occupied_count() const { return std::int64_t(offsets_.size()) - 1; }
  triangle_voxel_view<T> view() const {
    return triangle_voxel_view<T>{occ_.view(),         rank_.data(), offsets_.data(), entries_.data(), tris_.data(),
                                  offsets_.size() - 1, tris_.size(),  bricks_.data(),  planes_.data()};
  }
  std::uint32_t max_entries_per_voxel() const { return view().max_entries_per_voxel(); }

  // Bytes of the seven arrays (occupancy words, rank, offsets, entries, triangles, bricks, planes).
  std::size_t memory_bytes() const {
    return 4 * (occ_.word_count() + rank_.size() + offsets_.size() + entries_.size() + bricks_.size()) +
           sizeof(voxel_triangle<T>) * tris_.size() + sizeof(voxel_plane<T>) * planes_.size();
  }

private:
  voxel_grid<T> occ_;
  std::vector<std::uint32_t> rank_;
  std::vector<std::uint32_t> offsets_;
  std::vector<std::uint32_t> entries_;
  std::vector<voxel_triangle<T>> tris_;
  std::vector<std::uint32_t> bricks_;
  std::vector<voxel_plane<T>> planes_;
};

}  // namespace vplkit
