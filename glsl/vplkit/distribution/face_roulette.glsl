// SPDX-License-Identifier: MIT
// vplkit GLSL pack: Russian roulette between the front and the back paraboloid (paper Alg. 1,
// docs/math.md section 3; mirrors include/vplkit/distribution/face_roulette.hpp, T = float).
//
// Front face with probability b_F = v_F / (v_F + v_B) (v = the sum of a face's weights), then
// inverse transform within that face's CDF: P(face, t) = w_t / (v_F + v_B), the same as one CDF
// over both faces. One u serves both decisions: u < b_F picks the front face and is rescaled to
// u * (1 / b_F), otherwise the back face gets (u - b_F) * (1 / b_B), b_B = 1 - b_F. The roulette
// probabilities and the reciprocals are constants of the roulette, so a sample uses only -, * and
// comparisons: with the values the C++ object reports, the GPU returns the C++ face, index and pmf
// bit for bit.
//
// ACCESSORS: those of discrete_cdf.glsl; the faces are told apart by their descriptors' ids (and
// may differ in size).
#ifndef VPLKIT_DISTRIBUTION_FACE_ROULETTE_GLSL
#define VPLKIT_DISTRIBUTION_FACE_ROULETTE_GLSL

#include "vplkit/distribution/discrete_cdf.glsl"
#include "vplkit/distribution/mixture_split.glsl"
#include "vplkit/distribution/weights.glsl"

const int vplkit_front_face = 0;  // d.z >= 0
const int vplkit_back_face = 1;

// C++ face_sample<float>: face 0 front / 1 back, index within the face's distribution, pmf of
// (face, index); {0, 0, 0} when the roulette is empty.
struct vplkit_face_sample {
  int face;
  uint index;
  float pmf;
};

// The C++ face_roulette<float> after construction: its two distributions, front_probability(),
// back_probability(), front_scale() and back_scale(). Fill it from those accessors (bit-exact
// parity), or with vplkit_make_face_roulette from the two totals.
struct vplkit_face_roulette {
  vplkit_discrete_cdf front;
  vplkit_discrete_cdf back;
  float b_front;
  float b_back;
  float front_scale;
  float back_scale;
};

// b_F from the two face totals; 0 when both are 0, and 0 below the smallest normal float (C++:
// flushed, the normal-range contract). The C++ divides in double and rounds once; GLSL is float
// only: both totals are scaled by the power of two that brings the larger into [1, 2), so the sum
// cannot overflow and the division has a divisor in [1, 4), inside the range where GLSL promises
// 2.5 ulp; b_F may still differ from the C++ value in its last bits. A total of +Inf (float
// weights summing past FLT_MAX) has lost its size: an infinite face takes b = 1 against a finite
// one and 0.5 against an infinite one, never NaN; the C++ uses its double sums there, so upload
// its b_F (and scales) for such faces.
float vplkit_face_roulette_front_probability(float v_front, float v_back) {
  if (isinf(v_front) || isinf(v_back)) return isinf(v_back) ? (isinf(v_front) ? 0.5 : 0.0) : 1.0;
  float f = vplkit_flush_denormal(v_front);
  float b = vplkit_flush_denormal(v_back);
  float m = max(f, b);
  if (!(m > 0.0)) return 0.0;
  int k = -vplkit_binary_exponent(m);
  f = vplkit_scale_by_exp2(f, k);
  b = vplkit_scale_by_exp2(b, k);
  return vplkit_flush_denormal(min(f / (f + b), 1.0));
}

bool vplkit_face_roulette_empty(vplkit_face_roulette r) {
  return vplkit_discrete_cdf_empty(r.front) && vplkit_discrete_cdf_empty(r.back);
}

// The C++ constructor, on the GPU (for faces built by cdf_build.comp): same logic, but b_F and the
// reciprocals come from GLSL float division (see above), so the face chosen for u within a few
// ulps of b_F, or the index for u near a bin edge, may differ from the C++ one. The roulette
// stays consistent with itself: its pmf uses the b_F its sampling uses.
vplkit_face_roulette vplkit_make_face_roulette(vplkit_discrete_cdf front,
                                               vplkit_discrete_cdf back) {
  vplkit_face_roulette r;
  r.front = front;
  r.back = back;
  r.b_front = vplkit_face_roulette_front_probability(front.total, back.total);
  r.b_back = vplkit_face_roulette_empty(r) ? 0.0 : 1.0 - r.b_front;
  r.front_scale = vplkit_reciprocal_or_zero(r.b_front);
  r.back_scale = vplkit_reciprocal_or_zero(r.b_back);
  return r;
}

// C++ face_probability(face).
float vplkit_face_roulette_face_probability(vplkit_face_roulette r, int face) {
  return face == vplkit_front_face ? r.b_front : face == vplkit_back_face ? r.b_back : 0.0;
}

// b_face * pmf within the face; 0 for a face other than 0 / 1 or an index out of range. A product
// below the smallest normal float becomes 2^-126 (vplkit_probability_product).
float vplkit_face_roulette_pmf(vplkit_face_roulette r, int face, uint index) {
  if (face == vplkit_front_face) {
    return vplkit_probability_product(r.b_front, vplkit_discrete_cdf_pmf(r.front, index));
  }
  if (face == vplkit_back_face) {
    return vplkit_probability_product(r.b_back, vplkit_discrete_cdf_pmf(r.back, index));
  }
  return 0.0;
}

vplkit_face_sample vplkit_face_roulette_sample(vplkit_face_roulette r, float u) {
  if (vplkit_face_roulette_empty(r)) return vplkit_face_sample(vplkit_front_face, 0u, 0.0);
  // The library's split of u (mixture_split.glsl) with eps = b_front: the front face is its
  // fallback side, the back face its learned side, the scales as the host rounded them.
  vplkit_mixture_choice c =
      vplkit_mixture_split_choose(vplkit_mixture_split(r.b_front, r.front_scale, r.back_scale), u);
  if (c.component == VPLKIT_MIXTURE_FALLBACK) {
    uint i = vplkit_discrete_cdf_sample(r.front, c.u).index;
    return vplkit_face_sample(vplkit_front_face, i, vplkit_face_roulette_pmf(r, vplkit_front_face, i));
  }
  // Here b_back > 0 (u < 1 and u >= b_front = 1 - b_back), so back_scale is set.
  uint i = vplkit_discrete_cdf_sample(r.back, c.u).index;
  return vplkit_face_sample(vplkit_back_face, i, vplkit_face_roulette_pmf(r, vplkit_back_face, i));
}

#endif  // VPLKIT_DISTRIBUTION_FACE_ROULETTE_GLSL
