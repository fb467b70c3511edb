// SPDX-License-Identifier: MIT
// vplkit GLSL pack: resampled importance sampling of VPLs (Talbot et al. 2005; docs/math.md
// section 13): M candidates from a distribution, weighed by p_hat / p with p_hat the luminance of
// the unshadowed contribution, one kept by a weighted reservoir, visibility for the kept one only,
// value f(y) W with W = weight_sum / p_hat(y); mirrors include/vplkit/estimators/ris_estimator.hpp
// (T = float), random numbers included: per candidate u (to the sample hook), with
// vplkit_vpl_patch u0 then u1 (the jitter), then one selection u per kept reservoir.
// HOOKS: the distribution hooks of vpl_sampling_estimator.glsl (declared identically here; define
// them once): vplkit_estimator_distribution_sample (called) and _pmf (not called by RIS).
// ACCESSORS: the DPRSM's, and those of the visibility the shader uses (vplkit_load_voxel_word).
// Keep k: vplkit_ris_resample_candidates fills k <= VPLKIT_RIS_MAX_KEPT reservoirs of a fixed
// array (a shader may lower the bound with #define before the include, to save registers).
#ifndef VPLKIT_ESTIMATORS_RIS_ESTIMATOR_GLSL
#define VPLKIT_ESTIMATORS_RIS_ESTIMATOR_GLSL

#include "vplkit/core/gather_point.glsl"
#include "vplkit/distribution/discrete_sample.glsl"
#include "vplkit/distribution/weighted_reservoir.glsl"
#include "vplkit/estimators/estimator_state.glsl"
#include "vplkit/estimators/ris_reservoir.glsl"
#include "vplkit/estimators/vpl_sum.glsl"
#include "vplkit/mis/heuristics.glsl"
#include "vplkit/sampling/rng.glsl"
#include "vplkit/visibility/visibility_callables.glsl"
#include "vplkit/vpl/dprsm_patch.glsl"
#include "vplkit/vpl/dprsm_view.glsl"
#include "vplkit/vpl/luminance.glsl"
#include "vplkit/vpl/vpl.glsl"

#ifndef VPLKIT_RIS_MAX_KEPT
#define VPLKIT_RIS_MAX_KEPT 8  // C++ ris_max_kept
#endif

vplkit_discrete_sample vplkit_estimator_distribution_sample(uint distribution, float u);
float vplkit_estimator_distribution_pmf(uint distribution, uint index);

// The VPL a sample stands for: the texel's (point) or its jittered patch point (patch); zero flux
// for a texel outside the view or a rejected patch point.
vplkit_vpl vplkit_ris_sample_vpl(vplkit_dprsm_view view, vplkit_ris_sample s, int vpl_mode, float depth_tolerance) {
  if (s.texel < 0 || s.texel >= vplkit_dprsm_view_texel_count(view)) return vplkit_vpl(vec3(0.0), vec3(0.0), vec3(0.0));
  if (vpl_mode == vplkit_vpl_patch) return vplkit_dprsm_patch_vpl(view, s.texel, s.xi, depth_tolerance).point;
  return vplkit_dprsm_view_vpl_at(view, s.texel);
}

// p_hat: the luminance of the unshadowed contribution at gp; 0 where not a usable weight.
float vplkit_ris_target(vplkit_gather_point gp, vplkit_vpl v, float dmin) {
  float p = vplkit_luminance(vplkit_vpl_contribution(gp, v, dmin));
  return vplkit_reservoir_weight_usable(p) ? p : 0.0;
}

// One candidate: its draw (u, and u0, u1 with vplkit_vpl_patch), its sample and target; returns
// its weight p_hat / p (0 for an empty draw, an index outside the view, a zero target).
float vplkit_ris_candidate(vplkit_gather_point gp, vplkit_dprsm_view view, uint distribution,
                           inout vplkit_counter_rng rng, float dmin, int vpl_mode, float depth_tolerance,
                           out vplkit_ris_sample s, out float target) {
  s = vplkit_make_ris_sample();
  target = 0.0;
  float u = vplkit_rng_next_unit(rng);
  if (vpl_mode == vplkit_vpl_patch) {
    s.xi.x = vplkit_rng_next_unit(rng);
    s.xi.y = vplkit_rng_next_unit(rng);
  }
  vplkit_discrete_sample d = vplkit_estimator_distribution_sample(distribution, u);
  if (!(d.pmf > 0.0) || d.index >= uint(vplkit_dprsm_view_texel_count(view))) return 0.0;
  s.texel = int(d.index);
  target = vplkit_ris_target(gp, vplkit_ris_sample_vpl(view, s, vpl_mode, depth_tolerance), dmin);
  return vplkit_mis_div(target, d.pmf);  // an overflow is not a usable weight: the reservoir skips it
}

// n_candidates candidates from `distribution`, one kept in each of reservoirs[0 .. n_kept)
// (n_kept clamped to VPLKIT_RIS_MAX_KEPT); each gets confidence M and the same weight_sum.
void vplkit_ris_resample_candidates(vplkit_gather_point gp, vplkit_dprsm_view view, uint distribution,
                                    inout vplkit_counter_rng rng, int n_candidates,
                                    inout vplkit_ris_reservoir reservoirs[VPLKIT_RIS_MAX_KEPT], int n_kept, float dmin,
                                    int vpl_mode, float depth_tolerance) {
  int k = min(n_kept, VPLKIT_RIS_MAX_KEPT);
  for (int j = 0; j < k; ++j) reservoirs[j] = vplkit_make_ris_reservoir();
  if (!vplkit_gather_point_valid(gp) || n_candidates <= 0 || k <= 0) return;
  vplkit_weighted_reservoir res[VPLKIT_RIS_MAX_KEPT];
  for (int j = 0; j < k; ++j) res[j] = vplkit_make_weighted_reservoir();
  for (int i = 0; i < n_candidates; ++i) {
    vplkit_ris_sample s;
    float target;
    float w = vplkit_ris_candidate(gp, view, distribution, rng, dmin, vpl_mode, depth_tolerance, s, target);
    for (int j = 0; j < k; ++j)
      if (vplkit_reservoir_update(res[j], uint(i), w, vplkit_rng_next_unit(rng))) {
        reservoirs[j].kept = s;
        reservoirs[j].target = target;
      }
  }
  float m = float(n_candidates);
  for (int j = 0; j < k; ++j) {
    reservoirs[j].confidence = m;
    if (!vplkit_reservoir_empty_of(res[j])) reservoirs[j].weight_sum = res[j].weight_sum / m;
  }
}

// One reservoir from n_candidates candidates: vplkit_ris_resample_candidates with k = 1, written
// without the arrays (a GPU keeps them in registers only when their indices are constant).
vplkit_ris_reservoir vplkit_ris_resample(vplkit_gather_point gp, vplkit_dprsm_view view, uint distribution,
                                         inout vplkit_counter_rng rng, int n_candidates, float dmin, int vpl_mode,
                                         float depth_tolerance) {
  vplkit_ris_reservoir r = vplkit_make_ris_reservoir();
  if (!vplkit_gather_point_valid(gp) || n_candidates <= 0) return r;
  vplkit_weighted_reservoir res = vplkit_make_weighted_reservoir();
  for (int i = 0; i < n_candidates; ++i) {
    vplkit_ris_sample s;
    float target;
    float w = vplkit_ris_candidate(gp, view, distribution, rng, dmin, vpl_mode, depth_tolerance, s, target);
    if (vplkit_reservoir_update(res, uint(i), w, vplkit_rng_next_unit(rng))) {
      r.kept = s;
      r.target = target;
    }
  }
  float m = float(n_candidates);
  r.confidence = m;
  if (!vplkit_reservoir_empty_of(res)) r.weight_sum = res.weight_sum / m;
  return r;
}

// f(y) W for the reservoir's sample at gp (its target must be p_hat(y) at gp); visibility only for
// a non-zero contribution.
vec3 vplkit_ris_shade(vplkit_gather_point gp, vplkit_dprsm_view view, vplkit_ris_reservoir r,
                      vplkit_visibility visibility, float dmin, int vpl_mode, float depth_tolerance) {
  if (!vplkit_gather_point_valid(gp) || !vplkit_ris_reservoir_has_sample(r)) return vec3(0.0);
  vplkit_vpl v = vplkit_ris_sample_vpl(view, r.kept, vpl_mode, depth_tolerance);
  vec3 c = vplkit_vpl_contribution(gp, v, dmin);
  if (!(c.x > 0.0 || c.y > 0.0 || c.z > 0.0)) return vec3(0.0);
  if (!vplkit_visibility_test(visibility, gp.position, gp.normal, v.position, v.normal)) return vec3(0.0);
  return vplkit_estimator_finite_or_zero(c * vplkit_mis_div(r.weight_sum, r.target));
}

// The mean of vplkit_ris_shade over reservoirs[0 .. n_kept); a repeated sample (same sample and
// weights) is shaded once.
vec3 vplkit_ris_shade_kept(vplkit_gather_point gp, vplkit_dprsm_view view,
                           vplkit_ris_reservoir reservoirs[VPLKIT_RIS_MAX_KEPT], int n_kept,
                           vplkit_visibility visibility, float dmin, int vpl_mode, float depth_tolerance) {
  int k = min(n_kept, VPLKIT_RIS_MAX_KEPT);
  if (k <= 0) return vec3(0.0);
  vec3 value[VPLKIT_RIS_MAX_KEPT];
  vec3 sum = vec3(0.0);
  for (int j = 0; j < k; ++j) {
    int same = -1;
    for (int i = 0; i < j && same < 0; ++i)
      if (vplkit_ris_same_sample(reservoirs[i].kept, reservoirs[j].kept) &&
          reservoirs[i].weight_sum == reservoirs[j].weight_sum && reservoirs[i].target == reservoirs[j].target)
        same = i;
    value[j] = same >= 0 ? value[same] : vplkit_ris_shade(gp, view, reservoirs[j], visibility, dmin, vpl_mode,
                                                          depth_tolerance);
    sum += value[j];
  }
  return sum / float(k);
}

// Samples [begin, end) of vplkit_estimate_ris.
void vplkit_estimate_ris_range(vplkit_gather_point gp, vplkit_dprsm_view view, uint distribution,
                               inout vplkit_estimator_state state, int begin, int end, int n_candidates,
                               vplkit_visibility visibility, float dmin, int vpl_mode, float depth_tolerance) {
  if (!vplkit_gather_point_valid(gp) || n_candidates <= 0) return;
  for (int k = begin; k < end; ++k) {
    vplkit_ris_reservoir r = vplkit_ris_resample(gp, view, distribution, state.rng, n_candidates, dmin, vpl_mode,
                                                 depth_tolerance);
    state.sum += vplkit_ris_shade(gp, view, r, visibility, dmin, vpl_mode, depth_tolerance);
  }
}

vec3 vplkit_estimate_ris_finish(vplkit_estimator_state state, int n_samples) {
  return n_samples > 0 ? state.sum / float(n_samples) : vec3(0.0);
}

vec3 vplkit_estimate_ris(vplkit_gather_point gp, vplkit_dprsm_view view, uint distribution,
                         inout vplkit_counter_rng rng, int n_samples, int n_candidates, vplkit_visibility visibility,
                         float dmin, int vpl_mode, float depth_tolerance) {
  if (!vplkit_gather_point_valid(gp) || n_samples <= 0 || n_candidates <= 0) return vec3(0.0);
  vplkit_estimator_state state = vplkit_make_estimator_state(rng);
  vplkit_estimate_ris_range(gp, view, distribution, state, 0, n_samples, n_candidates, visibility, dmin, vpl_mode,
                            depth_tolerance);
  rng = state.rng;
  return vplkit_estimate_ris_finish(state, n_samples);
}

#endif  // VPLKIT_ESTIMATORS_RIS_ESTIMATOR_GLSL
