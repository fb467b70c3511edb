// SPDX-License-Identifier: MIT
#pragma once
// What the resampled estimators keep (docs/math.md section 13): a sample (a texel and its patch
// jitter) and a reservoir holding one with its weights. Plain types with no behaviour beyond their
// accessors, so a buffer record (glsl/vplkit/estimators/ris_params.h) converts to and from them and
// a shader that only moves reservoirs needs none of the estimators' accessors.
#include <vplkit/core/vector.hpp>

#include <limits>

namespace vplkit {

// A texel and, for vpl_mode::patch, the jitter of its point (dprsm_patch_vpl); texel -1: none.
template <class T>
struct ris_sample {
  int texel = -1;
  vec2<T> xi{T(0)};
};

template <class T>
inline bool ris_same_sample(const ris_sample<T>& a, const ris_sample<T>& b) {
  return a.texel == b.texel && a.xi.x == b.xi.x && a.xi.y == b.xi.y;
}

// What a gather point keeps of its candidates (or, after spatial reuse, of its and its
// neighbours' reservoirs). W = weight_sum / target is the kept sample's unbiased contribution
// weight: E[f(y) W] = the integral of f over {p_hat > 0} for every f.
template <class T>
struct ris_reservoir {
  ris_sample<T> kept{};    // the kept sample y (texel -1: none)
  T weight_sum = T(0);     // (1/M) sum of p_hat / p over the candidates; after reuse sum_i m_i p_hat W_i
  T target = T(0);         // p_hat of the kept sample at the owner's gather point
  T confidence = T(0);     // M: the candidates behind the reservoir (summed over a reuse's inputs)
};

template <class T>
inline bool ris_reservoir_has_sample(const ris_reservoir<T>& r) {
  return r.kept.texel >= 0 && r.target > T(0) && r.weight_sum > T(0);
}

// W = weight_sum / target, 0 for a reservoir without a sample (and where the quotient overflows).
template <class T>
inline T ris_contribution_weight(const ris_reservoir<T>& r) {
  if (!ris_reservoir_has_sample(r)) return T(0);
  const T w = r.weight_sum / r.target;
  return w <= std::numeric_limits<T>::max() ? w : T(0);
}

}  // namespace vplkit
