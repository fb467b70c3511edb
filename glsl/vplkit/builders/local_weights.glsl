// SPDX-License-Identifier: MIT
// vplkit GLSL pack: the region grid of the local CDFs (paper 5.2, docs/math.md section 4): which of
// the rx x ry regions a pixel belongs to, and each region's rectangle; mirrors the integer part of
// include/vplkit/builders/local_weights.hpp. A renderer's estimator kernel uses
// vplkit_region_of_pixel to pick the pixel's own region; the weights of region i are
// global_weights.comp over the subset S_i (region-major layout: weights[i * 2 R^2 + t]).
//   image_regions{width, height, rx, ry} <-> vplkit_image_regions (validated by the host: the C++
//                                            constructor throws unless 1 <= rx <= width etc.)
// Integer arithmetic only, identical to the C++ for images up to 32768 pixels on a side.
// No accessor.
#ifndef VPLKIT_BUILDERS_LOCAL_WEIGHTS_GLSL
#define VPLKIT_BUILDERS_LOCAL_WEIGHTS_GLSL

#include "vplkit/builders/gather_subset.glsl"

// Column (or row) of pixel coordinate p in [0, extent) cut into n parts at floor(k * extent / n).
int vplkit_region_band_of(int p, int extent, int n) {
  return ((p + 1) * n - 1) / extent;
}

// Region index (row-major) of pixel (x, y) of a width x height image cut into rx x ry regions.
int vplkit_region_of_pixel(int x, int y, int width, int height, int rx, int ry) {
  return vplkit_region_band_of(y, height, ry) * rx + vplkit_region_band_of(x, width, rx);
}

struct vplkit_image_regions {
  int width;
  int height;
  int rx;  // regions across
  int ry;  // regions down
};

int vplkit_image_regions_count(vplkit_image_regions r) {
  return r.rx * r.ry;
}

int vplkit_image_regions_region_of_pixel(vplkit_image_regions r, int x, int y) {
  return vplkit_region_of_pixel(x, y, r.width, r.height, r.rx, r.ry);
}

// Pixel rectangle of region i (0 <= i < count).
vplkit_pixel_rect vplkit_image_regions_region_rect(vplkit_image_regions r, int i) {
  int row = i / r.rx, c = i - (i / r.rx) * r.rx;
  int xa = c * r.width / r.rx, xb = (c + 1) * r.width / r.rx;
  int ya = row * r.height / r.ry, yb = (row + 1) * r.height / r.ry;
  return vplkit_pixel_rect(xa, ya, xb - xa, yb - ya);
}

#endif  // VPLKIT_BUILDERS_LOCAL_WEIGHTS_GLSL
