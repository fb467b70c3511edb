// vplkit GLSL pack: hole-aware 3x3 median fill (DESIGN 3.4; mirrors
// include/vplkit/image/median_fill.hpp, T = float).
//
// Per texel (one invocation per texel; the fill reads only the input, so it is one Jacobi pass and
// the visiting order does not matter):
//  - hole: value == 0.0 (-0.0 too);
//  - a non-hole is returned unchanged (same bits);
//  - a hole that is not fillable, or whose 3x3 window (clipped to the image) holds no non-hole,
//    gives +0.0;
//  - otherwise the LOWER median of the k non-hole neighbours: sorted ascending s[0..k-1], the value
//    s[(k - 1) / 2]. It is always one neighbour's own value, so CPU and GPU agree bit for bit.
// A neighbour counts whenever it is not a hole, fillable or not.
//
// ACCESSOR (the including shader defines it; it chooses the buffer / image and the layout):
//   float vplkit_load_weight(int face, int x, int y);
//     the unfilled input value of texel (x, y) of image `face`, 0 <= x < width, 0 <= y < height.
//     The fill only asks for texels inside the image, and only within one `face`: for a DPRSM
//     weight array of 2 R R floats that is weights[face * R * R + y * R + x] (the window never
//     crosses from one face to the other). `face` is passed through untouched, so a single image
//     may ignore it.
// The C++ `fillable(x, y)` callable becomes the bool argument `fillable` (evaluated by the caller;
// for a DPRSM: the texel is valid, centre in the unit disk; see median_fill.comp).
//
// Denormals: the hole test compares with 0. An implementation that flushes denormal inputs to zero
// treats a denormal weight as a hole where the C++ does not (llvmpipe keeps denormals).
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
