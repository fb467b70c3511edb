// SPDX-License-Identifier: MIT
// vplkit GLSL pack: local CDFs (docs/math.md section 4, paper section 5.2), N distributions, one
// per image region, each round drawing one VPL from every one; mirrors
// include/vplkit/estimators/local_estimator.hpp (T = float): the combinations
// (vplkit_local_balance, the default, and vplkit_local_average, as published), random numbers and
// arithmetic. The C++ `const Distribution* distributions, int n` becomes the hook ids
// first_distribution .. first_distribution + n - 1 (vpl_sampling_estimator.glsl declares the
// hooks; docs/glsl/estimators.md). As in C++ with its defaults, the range and one-shot forms come
// without and with (int vpl_mode, float depth_tolerance); vplkit_vpl_patch draws u0, u1, the jitter
// inside the drawn texel, after each sample's u (docs/math.md section 11).
#ifndef VPLKIT_ESTIMATORS_LOCAL_ESTIMATOR_GLSL
#define VPLKIT_ESTIMATORS_LOCAL_ESTIMATOR_GLSL

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

// C++ enum class local_combination { balance, average }.
const int vplkit_local_balance = 0;
const int vplkit_local_average = 1;

// sum_j pmf_j(t) over the N distributions: the (unnormalised) mixture density at t.
float vplkit_local_mixture_pmf_sum(uint first_distribution, int n_distributions, uint t) {
  float s = 0.0;
  for (int j = 0; j < n_distributions; ++j) s += vplkit_estimator_pmf(vplkit_estimator_distribution_pmf(first_distribution + uint(j), t));
  return s;
}

// Rounds [begin, end) of vplkit_estimate_local (estimator_state.glsl).
void vplkit_estimate_local_range(vplkit_gather_point gp, vplkit_dprsm_view view, uint first_distribution,
                                 int n_distributions, inout vplkit_estimator_state state, int begin, int end,
                                 vplkit_visibility visibility, float dmin, int combination, int vpl_mode,
                                 float depth_tolerance) {
  if (!vplkit_gather_point_valid(gp) || n_distributions <= 0) return;
  uint n_texels = uint(vplkit_dprsm_view_texel_count(view));
  for (int r = begin; r < end; ++r)
    for (int i = 0; i < n_distributions; ++i) {
      vplkit_discrete_sample s =
          vplkit_estimator_distribution_sample(first_distribution + uint(i), vplkit_rng_next_unit(state.rng));
      vec2 xi = vec2(0.0);
      if (vpl_mode == vplkit_vpl_patch) {
        xi.x = vplkit_rng_next_unit(state.rng);
        xi.y = vplkit_rng_next_unit(state.rng);
      }
      float pmf_i = vplkit_estimator_pmf(s.pmf);
      if (!(pmf_i > 0.0) || s.index >= n_texels) continue;
      vec3 c = vpl_mode == vplkit_vpl_patch
                   ? vplkit_vpl_patch_visible_contribution(gp, view, int(s.index), xi, visibility, dmin,
                                                           depth_tolerance)
                   : vplkit_vpl_visible_contribution(gp, view, int(s.index), visibility, dmin);
      if (!(c.x > 0.0 || c.y > 0.0 || c.z > 0.0)) continue;
      // balance: pmf_i(t) > 0 is one of the terms, so the divisor is > 0.
      float divisor = combination == vplkit_local_balance
                          ? vplkit_local_mixture_pmf_sum(first_distribution, n_distributions, s.index)
                          : pmf_i * float(n_distributions);
      state.sum += vplkit_estimator_finite_or_zero(vec3(vplkit_mis_div(c.x, divisor), vplkit_mis_div(c.y, divisor),
                                                        vplkit_mis_div(c.z, divisor)));
    }
}

void vplkit_estimate_local_range(vplkit_gather_point gp, vplkit_dprsm_view view, uint first_distribution,
                                 int n_distributions, inout vplkit_estimator_state state, int begin, int end,
                                 vplkit_visibility visibility, float dmin, int combination) {
  vplkit_estimate_local_range(gp, view, first_distribution, n_distributions, state, begin, end, visibility, dmin,
                              combination, vplkit_vpl_point, 0.0);
}

vec3 vplkit_estimate_local_finish(vplkit_estimator_state state, int n_rounds) {
  return n_rounds > 0 ? state.sum / float(n_rounds) : vec3(0.0);
}

vec3 vplkit_estimate_local(vplkit_gather_point gp, vplkit_dprsm_view view, uint first_distribution,
                           int n_distributions, inout vplkit_counter_rng rng, int n_rounds,
                           vplkit_visibility visibility, float dmin, int combination, int vpl_mode,
                           float depth_tolerance) {
  if (!vplkit_gather_point_valid(gp) || n_rounds <= 0 || n_distributions <= 0) return vec3(0.0);
  vplkit_estimator_state state = vplkit_make_estimator_state(rng);
  vplkit_estimate_local_range(gp, view, first_distribution, n_distributions, state, 0, n_rounds, visibility, dmin,
                              combination, vpl_mode, depth_tolerance);
  rng = state.rng;
  return vplkit_estimate_local_finish(state, n_rounds);
}

vec3 vplkit_estimate_local(vplkit_gather_point gp, vplkit_dprsm_view view, uint first_distribution,
                           int n_distributions, inout vplkit_counter_rng rng, int n_rounds,
                           vplkit_visibility visibility, float dmin, int combination) {
  return vplkit_estimate_local(gp, view, first_distribution, n_distributions, rng, n_rounds, visibility, dmin,
                               combination, vplkit_vpl_point, 0.0);
}

#endif  // VPLKIT_ESTIMATORS_LOCAL_ESTIMATOR_GLSL
