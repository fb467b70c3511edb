// SPDX-License-Identifier: MIT
#pragma once
// Stratified (jittered-grid) choice of gather pixels inside a rectangle of the image: the subset S
// of the global CDF (Ritschel et al. 2011) and the S_i of the local CDF (docs/math.md section 4).
//
// Strata: `count` cells that tile the rectangle exactly. Rows: `rows`; every row but the last has
// `columns` cells, the last row has `last_columns` = count - (rows - 1) * columns (1..columns) wider
// cells. A row or column boundary k of n over an extent e sits at floor(k * e / n) (integer
// arithmetic), so with n <= e every cell holds at least one pixel. columns ~ sqrt(count * w / h)
// keeps the cells about square. count is first clamped to the rectangle's pixel count (count >=
// w * h gives every pixel once).
//
// Jitter, and background pixels: stratum k draws from its own counter_rng stream
// make_counter_rng(seed, stream_offset + k). Attempt a (0 <= a < max_attempts) consumes draws 2a
// (x) and 2a + 1 (y) and picks the pixel
//     x = cell.x0 + min(int(u_x * float(cell.width)), cell.width - 1)      (likewise y)
// in float arithmetic whatever T is, so that a GPU invocation per stratum picks the same pixel.
// A background pixel (gather_point_valid false) is rejected and the stratum tries again; when all
// max_attempts picks are background the stratum is DROPPED (no pixel). Accepted picks are uniform
// over the stratum's valid pixels, so a partly covered stratum is still sampled without bias; a
// stratum that is mostly background may be dropped (probability (background fraction)^max_attempts),
// and the subset then holds fewer than `count` pixels. A stratum with no valid pixel always drops.
#include <vplkit/core/error.hpp>
#include <vplkit/core/gather_point.hpp>
#include <vplkit/sampling/rng.hpp>

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace vplkit {

// Half-open pixel rectangle [x0, x0 + width) x [y0, y0 + height).
struct pixel_rect {
  int x0 = 0;
  int y0 = 0;
  int width = 0;
  int height = 0;
};

inline bool pixel_rect_contains(const pixel_rect& r, int x, int y) {
  return x >= r.x0 && y >= r.y0 && x < r.x0 + r.width && y < r.y0 + r.height;
}

// Shape of the stratum grid of gather_subset_grid (see the header comment).
struct gather_subset_grid_shape {
  int count = 0;         // number of strata (count clamped to the rectangle's pixel count)
  int columns = 0;       // cells per row in all rows but the last
  int rows = 0;
  int last_columns = 0;  // cells in the last row, 1..columns
};

inline constexpr int gather_subset_default_attempts = 4;

// Assumes rect.width, rect.height >= 1 and count >= 0 (validated by the callers below).
inline gather_subset_grid_shape gather_subset_grid(const pixel_rect& rect, int count) {
  gather_subset_grid_shape g;
  const long long pixels = (long long)rect.width * (long long)rect.height;
  g.count = (long long)count < pixels ? count : int(pixels);
  if (g.count <= 0) return g;
  // columns = round(sqrt(count * w / h)), clamped to [1, w], decided in integers (the floating
  // sqrt only gives the start; the fix-ups make c the exact floor of sqrt(count * w / h)), so the
  // shape does not depend on libm. The host computes the shape once and hands it to a GPU pass.
  const long long cw = (long long)g.count * (long long)rect.width;
  const long long h = rect.height;
  long long c = (long long)std::sqrt(double(cw) / double(h));
  while (c > 0 && c * c * h > cw) --c;
  while ((c + 1) * (c + 1) * h <= cw) ++c;
  // round to nearest: c + 1 when (c + 1/2)^2 h <= cw, i.e. (2c + 1)^2 h <= 4 cw
  if ((2 * c + 1) * (2 * c + 1) * h <= 4 * cw) ++c;
  int columns = int(c < 1 ? 1 : (c > rect.width ? rect.width : c));
  int rows = (g.count + columns - 1) / columns;
  if (rows > rect.height) {  // flat rectangles: as many columns as h rows need, then the rows
    columns = (g.count + rect.height - 1) / rect.height;  // <= width: count <= width * height
    rows = (g.count + columns - 1) / columns;             // <= height, and the last row non-empty
  }
  g.columns = columns;
  g.rows = rows;
  g.last_columns = g.count - (rows - 1) * columns;
  return g;
}

// Cell of stratum k (0 <= k < g.count) of the grid over rect. Integer arithmetic only; every
// product fits in int for images up to 32768 pixels on a side (k * extent <= 2^30).
inline pixel_rect gather_subset_stratum(const pixel_rect& rect, const gather_subset_grid_shape& g,
                                        int k) {
  const int row = k / g.columns;
  const int n_cols = row == g.rows - 1 ? g.last_columns : g.columns;
  const int col = k - row * g.columns;
  const int xa = col * rect.width / n_cols, xb = (col + 1) * rect.width / n_cols;
  const int ya = row * rect.height / g.rows, yb = (row + 1) * rect.height / g.rows;
  return pixel_rect{rect.x0 + xa, rect.y0 + ya, xb - xa, yb - ya};
}

// Offset in [0, extent) from a unit float u in [0, 1): float arithmetic on both CPU and GPU (the
// product is correctly rounded in IEEE and GLSL alike); the clamp catches u * extent rounding up
// to extent.
inline int gather_subset_jitter(float u, int extent) {
  const int o = int(u * float(extent));
  return o < extent - 1 ? o : extent - 1;
}

// Pixel index (y * gbuffer.width + x) chosen for stratum k, or -1 when the stratum is dropped.
// The per-invocation function a GPU mirror runs; assumes validated inputs, never throws.
template <class T>
inline int gather_subset_pick(const gbuffer_view<T>& gbuffer, const pixel_rect& rect,
                              const gather_subset_grid_shape& g, int k, std::uint32_t seed,
                              std::uint32_t stream_offset, int max_attempts) {
  const pixel_rect cell = gather_subset_stratum(rect, g, k);
  counter_rng rng = make_counter_rng(seed, stream_offset + std::uint32_t(k));
  for (int a = 0; a < max_attempts; ++a) {
    const float ux = rng_next_float(rng);
    const float uy = rng_next_float(rng);
    const int x = cell.x0 + gather_subset_jitter(ux, cell.width);
    const int y = cell.y0 + gather_subset_jitter(uy, cell.height);
    const int index = y * gbuffer.width + x;
    if (gather_point_valid(gbuffer.at(index))) return index;
  }
  return -1;
}

namespace detail {
template <class T>
inline void check_gather_subset_args(const gbuffer_view<T>& gbuffer, const pixel_rect& rect,
                                     int count, int max_attempts, const char* who) {
  gbuffer.validate();
  if (rect.width <= 0 || rect.height <= 0 || rect.x0 < 0 || rect.y0 < 0 ||
      rect.x0 + rect.width > gbuffer.width || rect.y0 + rect.height > gbuffer.height)
    throw invalid_input(std::string(who) + ": rectangle (x0 " + std::to_string(rect.x0) + ", y0 " +
                        std::to_string(rect.y0) + ", " + std::to_string(rect.width) + " x " +
                        std::to_string(rect.height) + ") is empty or not inside the " +
                        std::to_string(gbuffer.width) + " x " + std::to_string(gbuffer.height) +
                        " image");
  if (count < 0)
    throw invalid_input(std::string(who) + ": count " + std::to_string(count) + " is negative");
  if (max_attempts < 1)
    throw invalid_input(std::string(who) + ": max_attempts " + std::to_string(max_attempts) +
                        " must be >= 1");
}
}  // namespace detail

// Up to `count` distinct valid gather pixels of `rect`, one per stratum, in stratum order (row by
// row), as flat pixel indices y * gbuffer.width + x. Dropped strata leave no entry (see above).
// Deterministic in (gbuffer validity mask, rect, count, seed, stream_offset, max_attempts).
// Throws invalid_input for a bad G-buffer view, a rectangle not inside the image, count < 0 or
// max_attempts < 1. Cost: at most count * max_attempts G-buffer reads.
template <class T>
inline std::vector<int> stratified_gather_subset(const gbuffer_view<T>& gbuffer,
                                                 const pixel_rect& rect, int count,
                                                 std::uint32_t seed,
                                                 std::uint32_t stream_offset = 0,
                                                 int max_attempts = gather_subset_default_attempts) {
  detail::check_gather_subset_args(gbuffer, rect, count, max_attempts, "stratified_gather_subset");
  const gather_subset_grid_shape g = gather_subset_grid(rect, count);
  std::vector<int> out;
  out.reserve(std::size_t(g.count));
  for (int k = 0; k < g.count; ++k) {
    const int index = gather_subset_pick(gbuffer, rect, g, k, seed, stream_offset, max_attempts);
    if (index >= 0) out.push_back(index);
  }
  return out;
}

// The whole image as a rectangle.
template <class T>
inline pixel_rect full_image_rect(const gbuffer_view<T>& gbuffer) {
  return pixel_rect{0, 0, gbuffer.width, gbuffer.height};
}

}  // namespace vplkit
