// SPDX-License-Identifier: MIT
// vplkit GLSL pack: VPL sampling by inverse transform (docs/math.md section 3),
// L^(x) = (1/N) sum_k L_{t_k}(x) V / p(t_k), t_k ~ p; mirrors
// include/vplkit/estimators/vpl_sampling_estimator.hpp (T = float), random numbers included.
// HOOKS (the shader defines them once; the local and MIS estimators declare the same two): the
// distribution is an id, sampled and evaluated by
//   vplkit_discrete_sample vplkit_estimator_distribution_sample(uint distribution, float u);
//   float vplkit_estimator_distribution_pmf(uint distribution, uint index);
// usually one line each over the distribution pack (docs/glsl/estimators.md, "Distributions: two
// hooks"). ACCESSORS: the DPRSM's and vplkit_load_voxel_word. A drawn pmf below FLT_MIN counts as
// 0 (vplkit_estimator_pmf, the normal-range contract of docs/math.md, "GPU arithmetic model"), as in C++.
// VPL MODE: the range and one-shot forms come twice, as in C++ with its defaults: without the last
// two arguments (vplkit_vpl_point, the paper's point VPLs) and with (int vpl_mode, float
// depth_tolerance); vplkit_vpl_patch draws two more numbers per sample, u0 then u1, the jitter
// inside the drawn texel (docs/math.md section 11).
#ifndef VPLKIT_ESTIMATORS_VPL_SAMPLING_ESTIMATOR_GLSL
#define VPLKIT_ESTIMATORS_VPL_SAMPLING_ESTIMATOR_GLSL

#include "vplkit/core/gather_point.glsl"
#include "vplkit/distribution/discrete_sample.glsl"
#include "vplkit/estimators/estimator_state.glsl"
#include "vplkit/estimators/vpl_sum.glsl"
#include "vplkit/mis/heuristics.glsl"
#include "vplkit/sampling/rng.glsl"
#include "vplkit/visibility/visibility_callables.glsl"
#include "vplkit/vpl/dprsm_patch.glsl"
#include "vplkit/vpl/dprsm_view.glsl"

vplkit_discrete_sample vplkit_estimator_distribution_sample(uint distribution, float u);
float vplkit_estimator_distribution_pmf(uint distribution, uint index);

// c / p per component, p > 0 (vplkit_mis_div: GLSL specifies x / y only for |y| in [2^-126, 2^126]).
vec3 vplkit_estimator_div(vec3 c, float p) {
  return vec3(vplkit_mis_div(c.x, p), vplkit_mis_div(c.y, p), vplkit_mis_div(c.z, p));
}

// One sample's value L_t V / p(t) for the draw u (0 when pmf is 0 or t is out of range).
vec3 vplkit_vpl_sampling_sample(vplkit_gather_point gp, vplkit_dprsm_view view, uint distribution, float u,
                                vplkit_visibility visibility, float dmin) {
  vplkit_discrete_sample s = vplkit_estimator_distribution_sample(distribution, u);
  float pmf = vplkit_estimator_pmf(s.pmf);
  if (!(pmf > 0.0) || s.index >= uint(vplkit_dprsm_view_texel_count(view))) return vec3(0.0);
  vec3 c = vplkit_vpl_visible_contribution(gp, view, int(s.index), visibility, dmin);
  // A denormal pmf can overflow the quotient: such a draw has negligible probability, and an Inf
  // would poison the image, so it adds 0.
  return vplkit_estimator_finite_or_zero(vplkit_estimator_div(c, pmf));
}

// The patch-sampled sample: L(y) V / p(t) at the point y of the drawn texel that xi selects.
vec3 vplkit_vpl_sampling_patch_sample(vplkit_gather_point gp, vplkit_dprsm_view view, uint distribution, float u,
                                      vec2 xi, vplkit_visibility visibility, float dmin, float depth_tolerance) {
  vplkit_discrete_sample s = vplkit_estimator_distribution_sample(distribution, u);
  float pmf = vplkit_estimator_pmf(s.pmf);
  if (!(pmf > 0.0) || s.index >= uint(vplkit_dprsm_view_texel_count(view))) return vec3(0.0);
  vec3 c = vplkit_vpl_patch_visible_contribution(gp, view, int(s.index), xi, visibility, dmin, depth_tolerance);
  return vplkit_estimator_finite_or_zero(vplkit_estimator_div(c, pmf));
}

// Samples [begin, end) of vplkit_estimate_vpl_sampling (estimator_state.glsl).
void vplkit_estimate_vpl_sampling_range(vplkit_gather_point gp, vplkit_dprsm_view view, uint distribution,
                                        inout vplkit_estimator_state state, int begin, int end,
                                        vplkit_visibility visibility, float dmin, int vpl_mode,
                                        float depth_tolerance) {
  if (!vplkit_gather_point_valid(gp)) return;
  for (int k = begin; k < end; ++k) {
    float u = vplkit_rng_next_unit(state.rng);
    if (vpl_mode == vplkit_vpl_patch) {
      float u0 = vplkit_rng_next_unit(state.rng);
      float u1 = vplkit_rng_next_unit(state.rng);
      state.sum += vplkit_vpl_sampling_patch_sample(gp, view, distribution, u, vec2(u0, u1), visibility, dmin,
                                                    depth_tolerance);
    } else {
      state.sum += vplkit_vpl_sampling_sample(gp, view, distribution, u, visibility, dmin);
    }
  }
}

void vplkit_estimate_vpl_sampling_range(vplkit_gather_point gp, vplkit_dprsm_view view, uint distribution,
                                        inout vplkit_estimator_state state, int begin, int end,
                                        vplkit_visibility visibility, float dmin) {
  vplkit_estimate_vpl_sampling_range(gp, view, distribution, state, begin, end, visibility, dmin, vplkit_vpl_point,
                                     0.0);
}

vec3 vplkit_estimate_vpl_sampling_finish(vplkit_estimator_state state, int n_samples) {
  return n_samples > 0 ? state.sum / float(n_samples) : vec3(0.0);
}

vec3 vplkit_estimate_vpl_sampling(vplkit_gather_point gp, vplkit_dprsm_view view, uint distribution,
                                  inout vplkit_counter_rng rng, int n_samples, vplkit_visibility visibility,
                                  float dmin, int vpl_mode, float depth_tolerance) {
  if (!vplkit_gather_point_valid(gp) || n_samples <= 0) return vec3(0.0);
  vplkit_estimator_state state = vplkit_make_estimator_state(rng);
  vplkit_estimate_vpl_sampling_range(gp, view, distribution, state, 0, n_samples, visibility, dmin, vpl_mode,
                                     depth_tolerance);
  rng = state.rng;
  return vplkit_estimate_vpl_sampling_finish(state, n_samples);
}

vec3 vplkit_estimate_vpl_sampling(vplkit_gather_point gp, vplkit_dprsm_view view, uint distribution,
                                  inout vplkit_counter_rng rng, int n_samples, vplkit_visibility visibility,
                                  float dmin) {
  return vplkit_estimate_vpl_sampling(gp, view, distribution, rng, n_samples, visibility, dmin, vplkit_vpl_point,
                                      0.0);
}

#endif  // VPLKIT_ESTIMATORS_VPL_SAMPLING_ESTIMATOR_GLSL
