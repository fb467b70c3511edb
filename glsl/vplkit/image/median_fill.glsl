// SPDX-License-Identifier: MIT
// vplkit GLSL pack: hole-aware 3x3 median fill, per texel (docs/math.md section 4); mirrors
// include/vplkit/image/median_fill.hpp (T = float): a hole (value 0) that is fillable gets the
// lower median of the non-hole values of its 3x3 window (clipped to the image), always one
// neighbour's own value, so CPU and GPU agree bit for bit; everything else keeps its bits (an
// unfillable or isolated hole gives +0). One Jacobi pass: only the input is read.
// ACCESSOR: float vplkit_load_weight(int face, int x, int y), the unfilled input of texel (x, y) of
// image `face` (never crossing faces). The C++ fillable(x, y) callable becomes the bool argument
// `fillable`. A device that flushes denormals treats a denormal weight as a hole.
// docs/glsl/image.md.
#ifndef VPLKIT_IMAGE_MEDIAN_FILL_GLSL
#define VPLKIT_IMAGE_MEDIAN_FILL_GLSL

float vplkit_load_weight(int face, int x, int y);

// Sorts v[0 .. count) ascending in place; count <= 8. The C++ insertion sort, statement for
// statement (any correct sort gives the same result: a sorted sequence of values is unique).
void vplkit_sort_small(inout float v[8], int count) {
  for (int i = 1; i < count; ++i) {
    float key = v[i];
    int j = i - 1;
    while (j >= 0 && v[j] > key) {
      v[j + 1] = v[j];
      --j;
    }
    v[j + 1] = key;
  }
}

// Output value of texel (x, y) of the width x height image `face`.
float vplkit_median_fill_texel(int face, int width, int height, int x, int y, bool fillable) {
  float centre = vplkit_load_weight(face, x, y);
  if (centre != 0.0) return centre;
  if (!fillable) return 0.0;
  float v[8] = float[8](0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
  int k = 0;
  for (int dy = -1; dy <= 1; ++dy) {
    for (int dx = -1; dx <= 1; ++dx) {
      int nx = x + dx;
      int ny = y + dy;
      if ((dx == 0 && dy == 0) || nx < 0 || ny < 0 || nx >= width || ny >= height) continue;
      float w = vplkit_load_weight(face, nx, ny);
      if (w != 0.0) {
        v[k] = w;
        ++k;
      }
    }
  }
  if (k == 0) return 0.0;
  vplkit_sort_small(v, k);
  return v[(k - 1) / 2];
}

#endif  // VPLKIT_IMAGE_MEDIAN_FILL_GLSL
