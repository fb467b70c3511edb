// SPDX-License-Identifier: MIT
// vplkit GLSL pack: streaming weighted reservoir sampling, keep one (Chao 1982; the selection step
// of RIS and ReSTIR; docs/math.md section 13); mirrors
// include/vplkit/distribution/weighted_reservoir.hpp (T = float).
//
// After items with weights w_1..w_n the kept item is i with probability w_i / sum_j w_j. Item i
// replaces the kept one when u_i * S_i < w_i (S_i the running sum): one correctly rounded product
// and one comparison, so the GPU keeps the item the C++ keeps for the same weights and u. Keep k
// (with replacement): feed the same items to k reservoirs with their own u. Weights that are not
// finite and > 0, or that would carry the sum past FLT_MAX, are ignored. The sum is `precise`: no
// compiler may fuse it with the product that computed w (the C++ rounds the two separately).
#ifndef VPLKIT_DISTRIBUTION_WEIGHTED_RESERVOIR_GLSL
#define VPLKIT_DISTRIBUTION_WEIGHTED_RESERVOIR_GLSL

#include "vplkit/core/constants.glsl"

const uint vplkit_reservoir_empty = 0xffffffffu;

struct vplkit_weighted_reservoir {
  uint index;         // the kept item, or vplkit_reservoir_empty
  float weight_sum;   // sum of the usable weights seen so far
  float weight;       // the kept item's weight (0 while empty)
};

vplkit_weighted_reservoir vplkit_make_weighted_reservoir() {
  return vplkit_weighted_reservoir(vplkit_reservoir_empty, 0.0, 0.0);
}

// Finite and > 0 (NaN fails both comparisons).
bool vplkit_reservoir_weight_usable(float w) {
  return w > 0.0 && w <= vplkit_FLT_MAX;
}

bool vplkit_reservoir_empty_of(vplkit_weighted_reservoir r) {
  return r.index == vplkit_reservoir_empty;
}

// Offers item `index` with weight w and u in [0, 1) (NaN and negative read as 0, >= 1 as the
// largest float below 1); true when the item is kept.
bool vplkit_reservoir_update(inout vplkit_weighted_reservoir r, uint index, float w, float u) {
  if (!vplkit_reservoir_weight_usable(w)) return false;
  precise float sum = r.weight_sum + w;
  if (!(sum <= vplkit_FLT_MAX)) return false;
  r.weight_sum = sum;
  float uc = !(u >= 0.0) ? 0.0 : (u < 1.0 ? u : vplkit_ONE_MINUS_EPSILON);
  precise float scaled = uc * sum;
  if (scaled < w || vplkit_reservoir_empty_of(r)) {
    r.index = index;
    r.weight = w;
    return true;
  }
  return false;
}

#endif  // VPLKIT_DISTRIBUTION_WEIGHTED_RESERVOIR_GLSL
