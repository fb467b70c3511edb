// SPDX-License-Identifier: MIT
#pragma once
// Hole-aware 3x3 median fill (docs/math.md section 4): the gathering pass of the GBG builder leaves
// texels that no ray reached at exactly 0 ("holes"); each fillable hole takes the median of its
// non-hole 3x3 neighbours.
//
// Median convention (the GLSL mirror must reproduce it exactly): with k non-hole neighbours
// (1 <= k <= 8) sorted ascending as s[0] <= ... <= s[k-1], the fill value is the LOWER median
// s[(k - 1) / 2] (integer division). For odd k that is the ordinary median; for even k it is the
// smaller of the two middle values. It is always one of the neighbours' own values, bit for bit:
// no arithmetic, so no rounding, no overflow, and CPU and GPU agree exactly whatever sort they use
// (a sorted sequence of values is unique). The sort below is an insertion sort over at most 8
// values so that vplkit_median_fill_texel in GLSL reads line for line like it.
//
// Hole test: value == 0 (so -0.0 is a hole too). Neighbours are the 8 surrounding texels that lie
// inside the image (fewer at borders and corners); a neighbour counts when it is not a hole,
// whether or not it is itself fillable. A hole with no non-hole neighbour, or one that is not
// fillable, is written as +0. Non-holes are copied unchanged. The fill is one pass (Jacobi): it
// reads only `in`, so filled values never feed other fills and the result does not depend on the
// visiting order (and the GPU can run one invocation per texel).
#include <vplkit/core/error.hpp>
#include <vplkit/paraboloid/texel_grid.hpp>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <limits>
#include <string>

namespace vplkit {

// Sorts v[0 .. count) ascending in place; count <= 8. Insertion sort: bounded, branch-light, and
// the same statements in GLSL (vplkit_sort_small).
template <class T>
inline void sort_small(T* v, int count) {
  for (int i = 1; i < count; ++i) {
    const T key = v[i];
    int j = i - 1;
    while (j >= 0 && v[j] > key) {
      v[j + 1] = v[j];
      --j;
    }
    v[j + 1] = key;
  }
}

// Output value of texel (x, y) of a width x height row-major image. Pure per-texel function: the
// GLSL compute shader calls its mirror once per invocation. Assumes validated input (see
// median_fill); never throws.
template <class T, class Fillable>
inline T median_fill_texel(const T* in, int width, int height, int x, int y, Fillable&& fillable) {
  const T centre = in[std::size_t(y) * std::size_t(width) + std::size_t(x)];
  if (centre != T(0)) return centre;
  if (!fillable(x, y)) return T(0);
  T v[8];
  int k = 0;
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dx = -1; dx <= 1; ++dx) {
      const int nx = x + dx, ny = y + dy;
      if ((dx == 0 && dy == 0) || nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
      const T w = in[std::size_t(ny) * std::size_t(width) + std::size_t(nx)];
      if (w != T(0)) {
        v[k] = w;
        ++k;
      }
    }
  }
  if (k == 0) return T(0);
  sort_small(v, k);
  return v[(k - 1) / 2];
}

namespace detail {

// [a, a+n) and [b, b+m) overlap? std::less gives a total order even for unrelated pointers, where
// the built-in < would be unspecified.
template <class T>
inline bool median_fill_ranges_overlap(const T* a, std::size_t n, const T* b, std::size_t m) {
  const std::less<const T*> lt;
  return lt(a, b + m) && lt(b, a + n);
}

inline std::size_t median_fill_image_size(int width, int height, std::size_t faces, const char* who) {
  if (width <= 0 || height <= 0)
    throw invalid_input(std::string(who) + ": image size must be positive, got " +
                        std::to_string(width) + " x " + std::to_string(height));
  const std::size_t n = std::size_t(width) * std::size_t(height);
  if (n > std::numeric_limits<std::size_t>::max() / faces)
    throw invalid_input(std::string(who) + ": image size overflows size_t");
  return n * faces;
}

// Rejects NaN/Inf (the median's comparisons would be meaningless and the fill would spread them).
// face < 0: a lone image (no face named in the message).
template <class T>
inline void median_fill_check_finite(const T* in, int width, int height, int face, const char* who) {
  const std::size_t base = std::size_t(face < 0 ? 0 : face) * std::size_t(width) * std::size_t(height);
  for (int y = 0; y < height; ++y) {
    for (int x = 0; x < width; ++x) {
      const T v = in[base + std::size_t(y) * std::size_t(width) + std::size_t(x)];
      if (!std::isfinite(v)) {
        const std::string where = face >= 0 ? "face " + std::to_string(face) + " " : std::string();
        throw invalid_input(std::string(who) + ": " + where + "texel (x=" + std::to_string(x) +
                            ", y=" + std::to_string(y) + ") is " + (std::isnan(v) ? "NaN" : "infinite"));
      }
    }
  }
}

template <class T, class Fillable>
inline void median_fill_unchecked(const T* in, T* out, int width, int height, Fillable& fillable) {
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      out[std::size_t(y) * std::size_t(width) + std::size_t(x)] =
          median_fill_texel(in, width, height, x, y, fillable);
}

}  // namespace detail

// Fills the holes of one width x height row-major image (e.g. one DPRSM face) into `out`.
// fillable(x, y) -> bool says whether texel (x, y) may be filled (texels outside the paraboloid
// disk must stay 0). `in` and `out` must not overlap (the fill reads unfilled neighbours only).
// Throws invalid_input for null pointers, non-positive sizes, overlapping buffers, and a NaN or
// infinite texel (naming it).
template <class T, class Fillable>
inline void median_fill(const T* in, T* out, int width, int height, Fillable fillable) {
  static_assert(std::numeric_limits<T>::is_iec559, "median_fill: T must be float or double");
  const std::size_t n = detail::median_fill_image_size(width, height, 1, "median_fill");
  if (in == nullptr || out == nullptr) throw invalid_input("median_fill: null image pointer");
  if (detail::median_fill_ranges_overlap<T>(in, n, out, n))
    throw invalid_input("median_fill: `in` and `out` overlap (the fill cannot run in place)");
  detail::median_fill_check_finite(in, width, height, -1, "median_fill");
  detail::median_fill_unchecked(in, out, width, height, fillable);
}

// Fills both faces of a DPRSM weight array: 2 * R * R values, flat index face * R * R + y * R + x.
// Each face is filled on its own (the 3x3 window never crosses from one face to the other), and
// only valid texels (texel_is_valid: centre in the closed unit disk, decided exactly in integers)
// are fillable. Throws like median_fill, naming the face of a NaN/infinite texel, and for
// R > paraboloid_max_resolution.
template <class T>
inline void median_fill_dprsm(const T* in, T* out, int R) {
  static_assert(std::numeric_limits<T>::is_iec559, "median_fill_dprsm: T must be float or double");
  const std::size_t n = detail::median_fill_image_size(R, R, 2, "median_fill_dprsm");
  if (R > paraboloid_max_resolution)
    throw invalid_input("median_fill_dprsm: R = " + std::to_string(R) + " exceeds paraboloid_max_resolution");
  if (in == nullptr || out == nullptr) throw invalid_input("median_fill_dprsm: null image pointer");
  if (detail::median_fill_ranges_overlap<T>(in, n, out, n))
    throw invalid_input("median_fill_dprsm: `in` and `out` overlap (the fill cannot run in place)");
  for (int face = 0; face < 2; ++face) detail::median_fill_check_finite(in, R, R, face, "median_fill_dprsm");
  const std::size_t face_size = std::size_t(R) * std::size_t(R);
  auto in_disk = [R](int x, int y) { return texel_is_valid(x, y, R); };
  for (int face = 0; face < 2; ++face)
    detail::median_fill_unchecked(in + std::size_t(face) * face_size, out + std::size_t(face) * face_size,
                                  R, R, in_disk);
}

}  // namespace vplkit
