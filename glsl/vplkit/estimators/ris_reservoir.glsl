// SPDX-License-Identifier: MIT
// vplkit GLSL pack: what the resampled estimators keep (docs/math.md section 13), a sample (a
// texel and its patch jitter) and a reservoir holding one with its weights; mirrors
// include/vplkit/estimators/ris_reservoir.hpp (T = float). No accessors: a kernel that only moves
// reservoirs (ris_params.h's buffer record) includes this file alone.
#ifndef VPLKIT_ESTIMATORS_RIS_RESERVOIR_GLSL
#define VPLKIT_ESTIMATORS_RIS_RESERVOIR_GLSL

#include "vplkit/core/constants.glsl"
#include "vplkit/mis/heuristics.glsl"

// A texel and, for vplkit_vpl_patch, the jitter of its point; texel -1: none.
struct vplkit_ris_sample {
  int texel;
  vec2 xi;
};

vplkit_ris_sample vplkit_make_ris_sample() {
  return vplkit_ris_sample(-1, vec2(0.0));
}

bool vplkit_ris_same_sample(vplkit_ris_sample a, vplkit_ris_sample b) {
  return a.texel == b.texel && a.xi.x == b.xi.x && a.xi.y == b.xi.y;
}

// W = weight_sum / target is the kept sample's unbiased contribution weight.
struct vplkit_ris_reservoir {
  vplkit_ris_sample kept;  // the kept sample y (texel -1: none)
  float weight_sum;        // (1/M) sum of p_hat / p; after reuse sum_i m_i p_hat W_i
  float target;            // p_hat of the kept sample at the owner's gather point
  float confidence;        // M: the candidates behind the reservoir
};

vplkit_ris_reservoir vplkit_make_ris_reservoir() {
  return vplkit_ris_reservoir(vplkit_make_ris_sample(), 0.0, 0.0, 0.0);
}

bool vplkit_ris_reservoir_has_sample(vplkit_ris_reservoir r) {
  return r.kept.texel >= 0 && r.target > 0.0 && r.weight_sum > 0.0;
}

// W = weight_sum / target; 0 without a sample or where the quotient overflows (vplkit_mis_div:
// any target, denormal too, divides as in C++ up to GLSL's 2.5 ulp).
float vplkit_ris_contribution_weight(vplkit_ris_reservoir r) {
  if (!vplkit_ris_reservoir_has_sample(r)) return 0.0;
  float w = vplkit_mis_div(r.weight_sum, r.target);
  return w <= vplkit_FLT_MAX ? w : 0.0;
}

#endif  // VPLKIT_ESTIMATORS_RIS_RESERVOIR_GLSL
