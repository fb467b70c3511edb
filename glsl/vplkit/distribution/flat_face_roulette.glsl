// SPDX-License-Identifier: MIT
// vplkit GLSL pack: a face roulette seen as one distribution over the flat DPRSM index
// (face * R * R + index within the face), so that the estimators' distribution hooks can serve the
// paper's Alg. 1 / 3 like any other distribution; mirrors
// include/vplkit/distribution/flat_face_roulette.hpp (T = float).
//
//   flat_face_roulette<float>(roulette, R)  <-> vplkit_make_flat_face_roulette(roulette, R)
//   .size() / .empty() / .pmf(flat) / .sample(u) <-> vplkit_flat_face_roulette_size / _empty /
//                                                    _pmf / _sample
// The face CDFs must have R * R entries each. Integer index arithmetic only: on top of
// distribution/face_roulette.glsl (bit-exact with the C++ roulette when the host uploads the C++
// object's probabilities and scales) the flat index and pmf are exact too.
//
// ACCESSORS: those of distribution/discrete_cdf.glsl (vplkit_load_cdf, vplkit_load_guide).
#ifndef VPLKIT_DISTRIBUTION_FLAT_FACE_ROULETTE_GLSL
#define VPLKIT_DISTRIBUTION_FLAT_FACE_ROULETTE_GLSL

#include "vplkit/distribution/discrete_sample.glsl"
#include "vplkit/distribution/face_roulette.glsl"

struct vplkit_flat_face_roulette {
  vplkit_face_roulette roulette;
  uint face_size;  // R * R
};

vplkit_flat_face_roulette vplkit_make_flat_face_roulette(vplkit_face_roulette roulette, int resolution) {
  return vplkit_flat_face_roulette(roulette, uint(resolution) * uint(resolution));
}

uint vplkit_flat_face_roulette_size(vplkit_flat_face_roulette f) {
  return 2u * f.face_size;
}

bool vplkit_flat_face_roulette_empty(vplkit_flat_face_roulette f) {
  return vplkit_face_roulette_empty(f.roulette);
}

// b_face * pmf within the face: w_t / (v_F + v_B).
float vplkit_flat_face_roulette_pmf(vplkit_flat_face_roulette f, uint flat_index) {
  if (f.face_size == 0u) return 0.0;
  return vplkit_face_roulette_pmf(f.roulette, int(flat_index / f.face_size), flat_index % f.face_size);
}

// The paper's Alg. 1 with one u; the index is flattened.
vplkit_discrete_sample vplkit_flat_face_roulette_sample(vplkit_flat_face_roulette f, float u) {
  vplkit_face_sample s = vplkit_face_roulette_sample(f.roulette, u);
  return vplkit_discrete_sample(uint(s.face) * f.face_size + s.index, s.pmf);
}

#endif  // VPLKIT_DISTRIBUTION_FLAT_FACE_ROULETTE_GLSL
