// SPDX-License-Identifier: MIT
// vplkit GLSL pack: stratified (jittered-grid) choice of gather pixels inside a rectangle of the
// image, the subset S of the global CDF and the S_i of the local CDF (docs/math.md section 4);
// mirrors the per-stratum part of include/vplkit/builders/gather_subset.hpp (T = float). The kernel
// gather_subset.comp runs one invocation per stratum.
//
//   pixel_rect                  <-> vplkit_pixel_rect
//   gather_subset_grid_shape    <-> vplkit_gather_subset_grid_shape (computed by the host with the
//                                   C++ gather_subset_grid: it needs 64-bit integer products)
//   gather_subset_stratum / gather_subset_jitter / gather_subset_pick <-> vplkit_ prefixed
// Integer arithmetic and one float product per coordinate (u * float(extent), correctly rounded
// in GLSL as in IEEE), so the GPU picks exactly the C++ pixels: same seed, same streams
// make_counter_rng(seed, stream_offset + k), same draws (2a for x, 2a + 1 for y of attempt a).
//
// ACCESSOR: vplkit_gather_point vplkit_load_gather_point(int pixel) (core/gather_point.glsl),
// for the validity of the picked pixel.
#ifndef VPLKIT_BUILDERS_GATHER_SUBSET_GLSL
#define VPLKIT_BUILDERS_GATHER_SUBSET_GLSL

#include "vplkit/core/gather_point.glsl"
#include "vplkit/sampling/rng.glsl"

// Half-open pixel rectangle [x0, x0 + width) x [y0, y0 + height).
struct vplkit_pixel_rect {
  int x0;
  int y0;
  int width;
  int height;
};

bool vplkit_pixel_rect_contains(vplkit_pixel_rect r, int x, int y) {
  return x >= r.x0 && y >= r.y0 && x < r.x0 + r.width && y < r.y0 + r.height;
}

struct vplkit_gather_subset_grid_shape {
  int count;         // number of strata
  int columns;       // cells per row in all rows but the last
  int rows;
  int last_columns;  // cells in the last row, 1..columns
};

const int vplkit_gather_subset_default_attempts = 4;

// Cell of stratum k (0 <= k < g.count). Every product fits in int for images up to 32768 pixels
// on a side.
vplkit_pixel_rect vplkit_gather_subset_stratum(vplkit_pixel_rect rect, vplkit_gather_subset_grid_shape g, int k) {
  int row = k / g.columns;
  int n_cols = row == g.rows - 1 ? g.last_columns : g.columns;
  int col = k - row * g.columns;
  int xa = col * rect.width / n_cols, xb = (col + 1) * rect.width / n_cols;
  int ya = row * rect.height / g.rows, yb = (row + 1) * rect.height / g.rows;
  return vplkit_pixel_rect(rect.x0 + xa, rect.y0 + ya, xb - xa, yb - ya);
}

// Offset in [0, extent) from a unit float u in [0, 1); the clamp catches u * extent rounding up.
int vplkit_gather_subset_jitter(float u, int extent) {
  int o = int(u * float(extent));
  return o < extent - 1 ? o : extent - 1;
}

// Pixel index (y * gbuffer.width + x) chosen for stratum k, or -1 when all max_attempts picks were
// background (the stratum is dropped).
int vplkit_gather_subset_pick(vplkit_gbuffer_view gbuffer, vplkit_pixel_rect rect, vplkit_gather_subset_grid_shape g,
                              int k, uint seed, uint stream_offset, int max_attempts) {
  vplkit_pixel_rect cell = vplkit_gather_subset_stratum(rect, g, k);
  vplkit_counter_rng rng = vplkit_make_counter_rng(seed, stream_offset + uint(k));
  for (int a = 0; a < max_attempts; ++a) {
    float ux = vplkit_rng_next_float(rng);
    float uy = vplkit_rng_next_float(rng);
    int x = cell.x0 + vplkit_gather_subset_jitter(ux, cell.width);
    int y = cell.y0 + vplkit_gather_subset_jitter(uy, cell.height);
    int index = y * gbuffer.width + x;
    if (vplkit_gather_point_valid(vplkit_load_gather_point(index))) return index;
  }
  return -1;
}

#endif  // VPLKIT_BUILDERS_GATHER_SUBSET_GLSL
