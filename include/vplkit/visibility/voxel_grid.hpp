// SPDX-License-Identifier: MIT
#pragma once
// Binary occupancy grid over an axis-aligned box (docs/math.md section 7).
//
// Layout (shared with the GPU, which fills and reads the same words):
//   voxel (x, y, z), 0 <= x < nx etc.; flat index  i = x + y * nx + z * nx * ny
//   word = i >> 5, bit = i & 31, occupied  <=>  (words[word] >> bit) & 1u
//   word count = ceil(nx * ny * nz / 32); unused bits of the last word are 0.
// Geometry: voxel_size = (bounds_max - bounds_min) / vec3(resolution) per axis (voxels need not be
// cubes); voxel (x, y, z) is the CLOSED box [bounds_min + i * voxel_size, bounds_min + (i + 1) *
// voxel_size]; the continuous voxel coordinate of a world point is (p - bounds_min) / voxel_size.
//
// voxel_grid<T> owns its words; voxel_grid_view<T> is a non-owning (bounds, resolution, words)
// triple that the DDA takes, so words read back from the GPU are usable directly.
#include <vplkit/core/error.hpp>
#include <vplkit/core/vector.hpp>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace vplkit {

// Largest resolution per axis, and largest voxel count (2^31: flat indices fit a signed int on
// both sides and the grid takes at most 256 MiB).
constexpr int voxel_grid_max_axis = 4096;
constexpr std::int64_t voxel_grid_max_voxels = std::int64_t(1) << 31;

template <class T>
struct voxel_grid_view {
  vec3<T> bounds_min;
  vec3<T> bounds_max;
  ivec3 resolution;
  const std::uint32_t* words;
};

inline std::size_t voxel_word_count(ivec3 resolution) {
  const std::size_t n = std::size_t(resolution.x) * std::size_t(resolution.y) * std::size_t(resolution.z);
  return (n + 31) / 32;
}

// Flat index of voxel v (no bounds check).
inline std::int64_t voxel_flat_index(ivec3 resolution, ivec3 v) {
  return std::int64_t(v.x) + std::int64_t(v.y) * resolution.x +
         std::int64_t(v.z) * resolution.x * std::int64_t(resolution.y);
}

inline bool voxel_in_grid(ivec3 resolution, ivec3 v) {
  return v.x >= 0 && v.y >= 0 && v.z >= 0 && v.x < resolution.x && v.y < resolution.y && v.z < resolution.z;
}

template <class T>
inline vec3<T> voxel_size(const voxel_grid_view<T>& g) {
  return (g.bounds_max - g.bounds_min) / vec3<T>(g.resolution);
}

// Largest voxel edge: the "one voxel" length used by offsets and tolerances.
template <class T>
inline T voxel_length(const voxel_grid_view<T>& g) {
  const vec3<T> s = voxel_size(g);
  return s.x > s.y ? (s.x > s.z ? s.x : s.z) : (s.y > s.z ? s.y : s.z);
}

// Occupancy of voxel v; false outside the grid.
template <class T>
inline bool voxel_test(const voxel_grid_view<T>& g, ivec3 v) {
  if (!voxel_in_grid(g.resolution, v)) return false;
  const std::int64_t i = voxel_flat_index(g.resolution, v);
  return ((g.words[std::size_t(i >> 5)] >> std::uint32_t(i & 31)) & 1u) != 0u;
}

// Continuous voxel coordinate of world point p (voxel v covers [v, v + 1) per axis).
template <class T>
inline vec3<T> world_to_voxel_coord(const voxel_grid_view<T>& g, vec3<T> p) {
  return (p - g.bounds_min) / voxel_size(g);
}

// floor(c) as an int, saturated to +-2^30 (NaN goes to -2^30) so that a far-away or non-finite
// point gives an index outside the grid instead of an undefined float-to-int conversion.
template <class T>
inline int voxel_floor_to_int(T c) {
  const T lim = T(1073741824);
  if (!(c > -lim)) return -1073741824;
  if (c >= lim) return 1073741824;
  return int(std::floor(c));
}

// Voxel containing p: floor of the continuous coordinate, NOT clamped (may lie outside the grid).
template <class T>
inline ivec3 world_to_voxel(const voxel_grid_view<T>& g, vec3<T> p) {
  const vec3<T> c = world_to_voxel_coord(g, p);
  return ivec3(voxel_floor_to_int(c.x), voxel_floor_to_int(c.y), voxel_floor_to_int(c.z));
}

// World position of the continuous voxel coordinate c (c = v gives the voxel's min corner).
template <class T>
inline vec3<T> voxel_to_world(const voxel_grid_view<T>& g, vec3<T> c) {
  return g.bounds_min + c * voxel_size(g);
}

template <class T>
inline vec3<T> voxel_center(const voxel_grid_view<T>& g, ivec3 v) {
  return voxel_to_world(g, vec3<T>(v) + vec3<T>(T(0.5)));
}

namespace detail {

template <class T>
inline bool voxel_vec3_finite(vec3<T> p) {
  return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z);
}

template <class T>
inline void check_voxel_grid_shape(vec3<T> bmin, vec3<T> bmax, ivec3 res, const char* who) {
  for (int a = 0; a < 3; ++a) {
    if (!std::isfinite(bmin[a]) || !std::isfinite(bmax[a]) || !(bmin[a] < bmax[a]) ||
        !std::isfinite(bmax[a] - bmin[a]))
      throw invalid_input(std::string(who) + ": bounds must be finite with min < max on every axis (axis " +
                          std::to_string(a) + ": min " + std::to_string(bmin[a]) + ", max " +
                          std::to_string(bmax[a]) + ")");
    if (res[a] <= 0 || res[a] > voxel_grid_max_axis)
      throw invalid_input(std::string(who) + ": resolution on axis " + std::to_string(a) + " is " +
                          std::to_string(res[a]) + ", must be in [1, " + std::to_string(voxel_grid_max_axis) + "]");
  }
  if (std::int64_t(res.x) * res.y * res.z > voxel_grid_max_voxels)
    throw invalid_input(std::string(who) + ": " + std::to_string(res.x) + " x " + std::to_string(res.y) + " x " +
                        std::to_string(res.z) + " voxels exceed the limit of 2^31");
}

}  // namespace detail

// A view over words the caller owns (e.g. read back from the GPU), checked once here.
template <class T>
inline voxel_grid_view<T> make_voxel_grid_view(vec3<T> bounds_min, vec3<T> bounds_max, ivec3 resolution,
                                               const std::uint32_t* words, std::size_t word_count) {
  detail::check_voxel_grid_shape(bounds_min, bounds_max, resolution, "make_voxel_grid_view");
  if (words == nullptr) throw invalid_input("make_voxel_grid_view: null words");
  if (word_count < voxel_word_count(resolution))
    throw invalid_input("make_voxel_grid_view: " + std::to_string(word_count) + " words given, " +
                        std::to_string(voxel_word_count(resolution)) + " needed");
  return voxel_grid_view<T>{bounds_min, bounds_max, resolution, words};
}

template <class T>
class voxel_grid {
public:
  // An empty grid (every voxel free).
  voxel_grid(vec3<T> bounds_min, vec3<T> bounds_max, ivec3 resolution)
      : min_(bounds_min), max_(bounds_max), res_(resolution) {
    detail::check_voxel_grid_shape(min_, max_, res_, "voxel_grid");
    words_.assign(voxel_word_count(res_), 0u);
  }

  // Adopts words in the layout above (e.g. read back from the GPU). Bits past the last voxel are
  // cleared so that count() and equality do not see them.
  voxel_grid(vec3<T> bounds_min, vec3<T> bounds_max, ivec3 resolution, std::vector<std::uint32_t> words)
      : min_(bounds_min), max_(bounds_max), res_(resolution), words_(std::move(words)) {
    detail::check_voxel_grid_shape(min_, max_, res_, "voxel_grid");
    if (words_.size() != voxel_word_count(res_))
      throw invalid_input("voxel_grid: " + std::to_string(words_.size()) + " words given, " +
                          std::to_string(voxel_word_count(res_)) + " needed");
    const std::int64_t n = std::int64_t(res_.x) * res_.y * res_.z;
    if ((n & 31) != 0) words_.back() &= (std::uint32_t(1) << std::uint32_t(n & 31)) - 1u;
  }

  vec3<T> bounds_min() const { return min_; }
  vec3<T> bounds_max() const { return max_; }
  ivec3 resolution() const { return res_; }
  std::int64_t voxel_count() const { return std::int64_t(res_.x) * res_.y * res_.z; }
  vec3<T> voxel_size() const { return vplkit::voxel_size(view()); }
  T voxel_length() const { return vplkit::voxel_length(view()); }

  const std::vector<std::uint32_t>& words() const { return words_; }
  const std::uint32_t* data() const { return words_.data(); }
  std::size_t word_count() const { return words_.size(); }
  voxel_grid_view<T> view() const { return voxel_grid_view<T>{min_, max_, res_, words_.data()}; }

  bool contains(ivec3 v) const { return voxel_in_grid(res_, v); }
  // test() of a voxel outside the grid is false; set()/clear() of one throw.
  bool test(ivec3 v) const { return voxel_test(view(), v); }
  void set(ivec3 v) { word_of(v, "set") |= bit_of(v); }
  void clear(ivec3 v) { word_of(v, "clear") &= ~bit_of(v); }
  void clear_all() { words_.assign(words_.size(), 0u); }

  // Number of occupied voxels.
  std::int64_t count() const {
    std::int64_t c = 0;
    for (std::uint32_t w : words_)
      for (; w != 0u; w &= w - 1u) ++c;
    return c;
  }

  vec3<T> world_to_voxel_coord(vec3<T> p) const { return vplkit::world_to_voxel_coord(view(), p); }
  ivec3 world_to_voxel(vec3<T> p) const { return vplkit::world_to_voxel(view(), p); }
  vec3<T> voxel_to_world(vec3<T> c) const { return vplkit::voxel_to_world(view(), c); }
  vec3<T> voxel_center(ivec3 v) const { return vplkit::voxel_center(view(), v); }

private:
  std::uint32_t& word_of(ivec3 v, const char* who) {
    if (!contains(v))
      throw invalid_input(std::string("voxel_grid::") + who + ": voxel (" + std::to_string(v.x) + ", " +
                          std::to_string(v.y) + ", " + std::to_string(v.z) + ") is outside the " +
                          std::to_string(res_.x) + " x " + std::to_string(res_.y) + " x " +
                          std::to_string(res_.z) + " grid");
    return words_[std::size_t(voxel_flat_index(res_, v) >> 5)];
  }
  std::uint32_t bit_of(ivec3 v) const {
    return std::uint32_t(1) << std::uint32_t(voxel_flat_index(res_, v) & 31);
  }

  vec3<T> min_, max_;
  ivec3 res_;
  std::vector<std::uint32_t> words_;
};

}  // namespace vplkit
