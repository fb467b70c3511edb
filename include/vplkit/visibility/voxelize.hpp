// SPDX-License-Identifier: MIT
#pragma once
// Conservative CPU voxelisation (docs/math.md section 7): every voxel whose closed box overlaps a
// triangle is marked. Only the voxels of the triangle's bounding box are tested.
//
// Numerical care:
// - Vertices are converted once to continuous voxel coordinates in double, c = (p - bounds_min) /
//   voxel_size (the grid's own convention), whatever T is. Voxel (i, j, k) is then the box centred
//   at (i, j, k) + 0.5 with half size 0.5, both exact, and a vertex shared by two triangles has one
//   converted value: neighbouring triangles see the same edge, so no crack opens between them.
// - The boxes are inflated by `margin_voxels` (default 1e-4 voxel): a voxel closer than that to a
//   triangle is marked too. This keeps rounding, in the SAT and in a float DDA marching the grid
//   later, from slipping a ray through a shell at an edge or a corner; it never removes a voxel.
//   margin_voxels = 0 gives the exact closed-box test.
// - Geometry outside the bounds is ignored (only voxels inside the grid are marked).
// - A triangle exactly on a voxel face marks the voxels on both sides (closed boxes).
#include <vplkit/core/error.hpp>
#include <vplkit/core/vector.hpp>
#include <vplkit/visibility/triangle_box_overlap.hpp>
#include <vplkit/visibility/voxel_grid.hpp>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>

namespace vplkit {

constexpr double voxelize_default_margin = 1e-4;

// Checks every triangle before anything is marked, so a bad mesh leaves the grid untouched.
// Throws invalid_input naming the first bad triangle (index out of range, non-finite vertex).
template <class T>
inline void validate_triangle_mesh(const vec3<T>* positions, std::size_t vertex_count,
                                   const std::uint32_t* indices, std::size_t index_count, const char* who) {
  if (index_count % 3 != 0)
    throw invalid_input(std::string(who) + ": index_count " + std::to_string(index_count) +
                        " is not a multiple of 3");
  if (index_count > 0 && indices == nullptr) throw invalid_input(std::string(who) + ": null indices");
  if (vertex_count > 0 && positions == nullptr) throw invalid_input(std::string(who) + ": null positions");
  for (std::size_t t = 0; t < index_count / 3; ++t) {
    for (int k = 0; k < 3; ++k) {
      const std::uint32_t i = indices[3 * t + std::size_t(k)];
      if (std::size_t(i) >= vertex_count)
        throw invalid_input(std::string(who) + ": triangle " + std::to_string(t) + " uses vertex index " +
                            std::to_string(i) + " but vertex_count is " + std::to_string(vertex_count));
      if (!detail::voxel_vec3_finite(positions[i]))
        throw invalid_input(std::string(who) + ": triangle " + std::to_string(t) + " has a non-finite vertex (index " +
                            std::to_string(i) + ")");
    }
  }
}

namespace detail {

// Calls visit(voxel) for every voxel of a `res` grid whose closed box, inflated by margin_voxels,
// overlaps the triangle v[0..2] given in continuous voxel coordinates (double). skip(voxel) ==
// true spares a voxel the SAT (voxelize: already marked). The one loop both CPU voxelisers share.
template <class Skip, class Visit>
inline void for_each_voxel_overlapping(ivec3 res, const vec3<double> v[3], double margin_voxels, Skip&& skip,
                                       Visit&& visit) {
  const vec3<double> half(0.5 + margin_voxels);
  // Voxel i (closed [i, i+1], inflated by the margin) can touch [lo, hi] only if
  // i - margin <= hi and i + 1 + margin >= lo.
  ivec3 first, last;
  for (int a = 0; a < 3; ++a) {
    const double lo = std::fmin(v[0][a], std::fmin(v[1][a], v[2][a]));
    const double hi = std::fmax(v[0][a], std::fmax(v[1][a], v[2][a]));
    const int f = voxel_floor_to_int(std::ceil(lo - margin_voxels) - 1.0);
    const int l = voxel_floor_to_int(hi + margin_voxels);
    first[a] = f < 0 ? 0 : f;
    last[a] = l > res[a] - 1 ? res[a] - 1 : l;
    if (first[a] > last[a]) return;
  }
  for (int z = first.z; z <= last.z; ++z)
    for (int y = first.y; y <= last.y; ++y)
      for (int x = first.x; x <= last.x; ++x) {
        const ivec3 c(x, y, z);
        if (skip(c)) continue;
        if (triangle_box_overlap(vec3<double>(c) + vec3<double>(0.5), half, v[0], v[1], v[2])) visit(c);
      }
}

// Triangle t's vertices in continuous voxel coordinates of the grid (bmin, size), in double.
template <class T>
inline void triangle_voxel_coords(const vec3<T>* positions, const std::uint32_t* indices, std::size_t t,
                                  vec3<double> bmin, vec3<double> size, vec3<double> v[3]) {
  for (int k = 0; k < 3; ++k) v[k] = (vec3<double>(positions[indices[3 * t + std::size_t(k)]]) - bmin) / size;
}

inline void check_voxelize_margin(double margin_voxels, const char* who) {
  if (!(margin_voxels >= 0.0) || !(margin_voxels < 0.5))
    throw invalid_input(std::string(who) + ": margin_voxels must be in [0, 0.5), got " + std::to_string(margin_voxels));
}

}  // namespace detail

// Marks (ORs into `grid`) every voxel overlapping one of the index_count / 3 triangles.
template <class T>
inline void voxelize(voxel_grid<T>& grid, const vec3<T>* positions, std::size_t vertex_count,
                     const std::uint32_t* indices, std::size_t index_count,
                     double margin_voxels = voxelize_default_margin) {
  validate_triangle_mesh(positions, vertex_count, indices, index_count, "voxelize");
  detail::check_voxelize_margin(margin_voxels, "voxelize");
  // Unreachable after the validation (it throws on null arrays), but GCC's -O3 array-bounds
  // analysis cannot see that through it and warns at a call with a literal nullptr.
  if (positions == nullptr || indices == nullptr) return;
  const vec3<double> bmin(grid.bounds_min());
  const ivec3 res = grid.resolution();
  const vec3<double> size = (vec3<double>(grid.bounds_max()) - bmin) / vec3<double>(res);
  for (std::size_t t = 0; t < index_count / 3; ++t) {
    vec3<double> v[3];
    detail::triangle_voxel_coords(positions, indices, t, bmin, size, v);
    detail::for_each_voxel_overlapping(
        res, v, margin_voxels, [&](ivec3 c) { return grid.test(c); }, [&](ivec3 c) { grid.set(c); });
  }
}

template <class T>
struct voxel_bounds {
  vec3<T> min;
  vec3<T> max;
};

// Bounds for a scene's voxel grid: the vertices' bounding box, each side pushed out by
// padding * (largest extent), then (cube = true) grown to a cube about its centre, so a cubic
// resolution gives cubic voxels. An axis with no extent (a flat or single-point scene) gets
// half-width 0.5 * largest extent (0.5 if everything is one point). Throws on an empty or
// non-finite vertex list or a negative / non-finite padding.
template <class T>
inline voxel_bounds<T> fit_voxel_bounds(const vec3<T>* positions, std::size_t vertex_count, T padding = T(0.01),
                                        bool cube = true) {
  if (vertex_count == 0 || positions == nullptr) throw invalid_input("fit_voxel_bounds: no vertices");
  if (!(padding >= T(0)) || !std::isfinite(padding))
    throw invalid_input("fit_voxel_bounds: padding must be finite and >= 0");
  vec3<T> lo = positions[0], hi = positions[0];
  for (std::size_t i = 0; i < vertex_count; ++i) {
    if (!detail::voxel_vec3_finite(positions[i]))
      throw invalid_input("fit_voxel_bounds: vertex " + std::to_string(i) + " is not finite");
    lo = glm::min(lo, positions[i]);
    hi = glm::max(hi, positions[i]);
  }
  const vec3<T> ext = hi - lo;
  const T largest = std::fmax(ext.x, std::fmax(ext.y, ext.z));
  const T pad = padding * largest;
  lo -= vec3<T>(pad);
  hi += vec3<T>(pad);
  for (int a = 0; a < 3; ++a) {
    if (!(hi[a] > lo[a])) {
      const T c = T(0.5) * (lo[a] + hi[a]);
      const T h = largest > T(0) ? T(0.5) * largest : T(0.5);
      lo[a] = c - h;
      hi[a] = c + h;
    }
  }
  if (cube) {
    const vec3<T> c = T(0.5) * (lo + hi);
    const vec3<T> e = hi - lo;
    const T h = T(0.5) * std::fmax(e.x, std::fmax(e.y, e.z));
    // Never cut off geometry by rounding c -/+ h.
    lo = glm::min(lo, c - vec3<T>(h));
    hi = glm::max(hi, c + vec3<T>(h));
  }
  return voxel_bounds<T>{lo, hi};
}

}  // namespace vplkit
