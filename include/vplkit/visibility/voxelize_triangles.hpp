// SPDX-License-Identifier: MIT
#pragma once
// CPU construction of a triangle_voxel_grid (triangle_voxel_grid.hpp): the conservative occupancy
// of voxelize.hpp, its rank, and in every occupied voxel the list of the triangles whose overlap
// test (the same test, the same margin) marked it. A voxel therefore lists a triangle exactly when
// the triangle marked it, and every point of a triangle lies in a voxel that lists it.
#include <vplkit/core/error.hpp>
#include <vplkit/core/vector.hpp>
#include <vplkit/visibility/triangle_voxel_grid.hpp>
#include <vplkit/visibility/voxel_grid.hpp>
#include <vplkit/visibility/voxelize.hpp>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace vplkit {

// The query record of triangle (a, b, c), computed in double and rounded once to T: the plane
// n . p = n . centroid with n = normalize((b - a) x (c - a)), and for each edge (a, b), (b, c),
// (c, a) the plane through it perpendicular to the triangle, normal n x edge normalised (it points
// into the triangle). A triangle whose cross product or an edge is zero or not finite is
// degenerate: all zero (it never blocks).
template <class T>
inline voxel_triangle<T> make_voxel_triangle(vec3<T> a, vec3<T> b, vec3<T> c) {
  const vec3<double> v[3] = {vec3<double>(a), vec3<double>(b), vec3<double>(c)};
  voxel_triangle<T> out{};
  vec3<double> n = glm::cross(v[1] - v[0], v[2] - v[0]);
  const double len = std::sqrt(glm::dot(n, n));
  if (!(len > 0.0) || !std::isfinite(len)) return out;
  n /= len;
  voxel_plane<double> edge[3];
  for (int i = 0; i < 3; ++i) {
    vec3<double> m = glm::cross(n, v[(i + 1) % 3] - v[i]);
    const double ml = std::sqrt(glm::dot(m, m));
    if (!(ml > 0.0) || !std::isfinite(ml)) return out;
    m /= ml;
    edge[i] = voxel_plane<double>{m, glm::dot(m, v[i])};
  }
  out.plane = voxel_plane<T>{vec3<T>(n), T(glm::dot(n, (v[0] + v[1] + v[2]) / 3.0))};
  for (int i = 0; i < 3; ++i) out.edge[i] = voxel_plane<T>{vec3<T>(edge[i].normal), T(edge[i].offset)};
  return out;
}

// The records of the index_count / 3 triangles, in order (validated like voxelize). The GPU
// builder takes these from the host, so both sides query the same numbers.
template <class T>
inline std::vector<voxel_triangle<T>> make_voxel_triangles(const vec3<T>* positions, std::size_t vertex_count,
                                                           const std::uint32_t* indices, std::size_t index_count) {
  validate_triangle_mesh(positions, vertex_count, indices, index_count, "make_voxel_triangles");
  std::vector<voxel_triangle<T>> out(index_count / 3);
  for (std::size_t t = 0; t < out.size(); ++t)
    out[t] = make_voxel_triangle(positions[indices[3 * t]], positions[indices[3 * t + 1]], positions[indices[3 * t + 2]]);
  return out;
}

// Builds the grid over [bounds_min, bounds_max] at `resolution` from the index_count / 3
// triangles (validated like voxelize, which builds the occupancy). Lists are in ascending triangle
// order. Memory: triangle_voxel_grid::memory_bytes().
template <class T>
inline triangle_voxel_grid<T> voxelize_triangles(vec3<T> bounds_min, vec3<T> bounds_max, ivec3 resolution,
                                                 const vec3<T>* positions, std::size_t vertex_count,
                                                 const std::uint32_t* indices, std::size_t index_count,
                                                 double margin_voxels = voxelize_default_margin) {
  // One overlap pass: the (voxel, triangle) pairs in triangle order, which also mark the occupancy
  // (exactly voxelize's: the same test on the same voxels, only without its skip of marked ones).
  voxel_grid<T> occ(bounds_min, bounds_max, resolution);
  validate_triangle_mesh(positions, vertex_count, indices, index_count, "voxelize_triangles");
  detail::check_voxelize_margin(margin_voxels, "voxelize_triangles");
  std::vector<voxel_triangle<T>> tris = make_voxel_triangles(positions, vertex_count, indices, index_count);
  const vec3<double> bmin(bounds_min);
  const vec3<double> size = (vec3<double>(bounds_max) - bmin) / vec3<double>(resolution);
  std::vector<std::pair<std::uint32_t, std::uint32_t>> pairs;  // (flat voxel index, triangle)
  for (std::size_t t = 0; t < index_count / 3; ++t) {
    vec3<double> v[3];
    detail::triangle_voxel_coords(positions, indices, t, bmin, size, v);
    detail::for_each_voxel_overlapping(
        resolution, v, margin_voxels, [](ivec3) { return false; },
        [&](ivec3 c) {
          occ.set(c);
          pairs.emplace_back(std::uint32_t(voxel_flat_index(resolution, c)), std::uint32_t(t));
        });
  }
  if (pairs.size() > std::size_t(0xFFFFFFFFu))
    throw invalid_input("voxelize_triangles: more than 2^32 (voxel, triangle) pairs");
  std::vector<std::uint32_t> rank = voxel_occupancy_rank(occ.data(), occ.word_count());
  // Flat index -> dense index, then a stable counting sort by voxel.
  const voxel_grid_view<T> g = occ.view();
  for (auto& p : pairs) {
    const std::uint32_t word = g.words[p.first >> 5], bit = p.first & 31u;
    p.first = rank[p.first >> 5] + std::uint32_t(voxel_bit_count(word & ((std::uint32_t(1) << bit) - 1u)));
  }
  const std::size_t occupied = std::size_t(occ.count());
  std::vector<std::uint32_t> offsets(occupied + 1, 0u);
  for (const auto& p : pairs) ++offsets[p.first + 1];
  for (std::size_t r = 0; r < occupied; ++r) offsets[r + 1] += offsets[r];
  std::vector<std::uint32_t> cursor(offsets.begin(), offsets.end() - 1);
  std::vector<std::uint32_t> entries(pairs.size());
  for (const auto& p : pairs) entries[cursor[p.first]++] = p.second;
  return triangle_voxel_grid<T>(std::move(occ), std::move(rank), std::move(offsets), std::move(entries),
                                std::move(tris));
}

}  // namespace vplkit
