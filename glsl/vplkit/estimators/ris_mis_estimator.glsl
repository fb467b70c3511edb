// SPDX-License-Identifier: MIT
// vplkit GLSL pack: resampled VPL sampling as the VPL strategy of MIS with cosine gathering
// (docs/math.md, "Resampled importance sampling of VPLs", "RIS with gathering"); mirrors
// include/vplkit/estimators/ris_mis_estimator.hpp (T = float), whose header states the estimator:
// n1 gathering directions (vplkit_mis_gathering_sample, solid_angle mode) and N RIS samples, each
// kept of M candidates from `distribution` by the target lum(h), h = n2 pmf f / (n1 p1 + n2 p2)
// without visibility (the balance weight of estimate_mis's VPL strategy times f over the texel's
// density), one visibility query for the kept sample. The weights count each RIS sample as
// max(1, M/2) VPL samples: n2 = vplkit_ris_mis_vpl_samples(N, M). Unclamped: gathering takes the
// near field, h stays bounded there, and nothing needs compensating.
// Random numbers, as the C++: step j < max(n1, N) draws, if j < N, the M candidates of one
// reservoir (per candidate u, with vplkit_vpl_patch u0 then u1, then the selection u), then, if
// j < n1, u0 and u1 for the direction. n_candidates <= 0 counts as N = 0; an invalid gather point
// gives 0 and draws nothing. Never NaN or Inf: every quotient goes through vplkit_mis_div or
// vplkit_balance_combined behind a guard, every value through vplkit_estimator_finite_or_zero.
// HOOKS: the distribution hooks of mis_estimator.glsl (declared identically there; define them
// once): vplkit_estimator_distribution_sample (the candidates) and _pmf (a reused sample's h and
// the gathering hits' p2). The pmf the sample hook returns must be the pmf hook's for its index.
// Visibility and tracing: the structs of visibility_callables.glsl.
// ACCESSORS: the DPRSM's, and those of the visibility and tracer the shader uses.
#ifndef VPLKIT_ESTIMATORS_RIS_MIS_ESTIMATOR_GLSL
#define VPLKIT_ESTIMATORS_RIS_MIS_ESTIMATOR_GLSL

#include "vplkit/core/gather_point.glsl"
#include "vplkit/distribution/discrete_sample.glsl"
#include "vplkit/distribution/weighted_reservoir.glsl"
#include "vplkit/estimators/estimator_state.glsl"
#include "vplkit/estimators/mis_estimator.glsl"
#include "vplkit/estimators/ris_reservoir.glsl"
#include "vplkit/estimators/vpl_sum.glsl"
#include "vplkit/mis/heuristics.glsl"
#include "vplkit/sampling/cosine_hemisphere.glsl"
#include "vplkit/sampling/orthonormal_basis.glsl"
#include "vplkit/sampling/rng.glsl"
#include "vplkit/visibility/visibility_callables.glsl"
#include "vplkit/vpl/dprsm_patch.glsl"
#include "vplkit/vpl/dprsm_view.glsl"
#include "vplkit/vpl/luminance.glsl"
#include "vplkit/vpl/vpl.glsl"

vplkit_discrete_sample vplkit_estimator_distribution_sample(uint distribution, float u);
float vplkit_estimator_distribution_pmf(uint distribution, uint index);

// n2 of the balance weights for n_ris RIS samples of n_candidates candidates each:
// n_ris max(1, M/2); 0 where either count is not positive. The C++ value bit for bit (integers
// and halves, exact in float below 2^24).
float vplkit_ris_mis_vpl_samples(int n_ris, int n_candidates) {
  if (n_ris <= 0 || n_candidates <= 0) return 0.0;
  return float(n_ris) * (float(n_candidates > 2 ? n_candidates : 2) * 0.5);
}

// h(t, xi) without visibility for the sample s of a texel drawn with probability pmf; v receives
// the point it stands for (for the visibility query). 0 (and v without flux) where the sample is
// empty or outside the view, pmf or n2 is not positive, the point cannot light x, or (n1 > 0) the
// patch moved the point to the texel centre.
vec3 vplkit_ris_mis_unshadowed(vplkit_gather_point gp, vplkit_dprsm_view view, vplkit_ris_sample s, float pmf,
                               float n1, float n2, int vpl_mode, float depth_tolerance, out vplkit_vpl v) {
  v = vplkit_vpl(vec3(0.0), vec3(0.0), vec3(0.0));
  if (!(pmf > 0.0) || !(n2 > 0.0) || s.texel < 0 || s.texel >= vplkit_dprsm_view_texel_count(view)) return vec3(0.0);
  float area;
  if (vpl_mode == vplkit_vpl_patch) {
    vplkit_dprsm_patch_sample p = vplkit_dprsm_patch_vpl(view, s.texel, s.xi, depth_tolerance);
    if (p.at_centre && n1 > 0.0) return vec3(0.0);
    v = p.point;
    area = vplkit_vpl_patch_area(p.solid_angle, p.distance, p.cos_alpha);
  } else {
    v = vplkit_dprsm_view_vpl_at(view, s.texel);
    area = vplkit_mis_texel_patch_area(view, s.texel);
  }
  return vplkit_estimator_finite_or_zero(vplkit_mis_vpl_unshadowed(gp, view, s.texel, v, pmf, area, n1, n2) *
                                         (n2 * pmf));
}

// A candidate's draw: its sample (texel -1 where the draw is empty or its index lies outside the
// view) and the pmf it was drawn with (0 then).
struct vplkit_ris_mis_draw {
  vplkit_ris_sample s;
  float pmf;
};

// The first half of a candidate: samples the distribution with u; xi is the jitter (u0, u1 with
// vplkit_vpl_patch, else 0).
vplkit_ris_mis_draw vplkit_ris_mis_draw_candidate(vplkit_dprsm_view view, uint distribution, float u, vec2 xi) {
  vplkit_ris_mis_draw c = vplkit_ris_mis_draw(vplkit_ris_sample(-1, xi), 0.0);
  vplkit_discrete_sample d = vplkit_estimator_distribution_sample(distribution, u);
  float pmf = vplkit_estimator_pmf(d.pmf);  // a denormal pmf counts as 0 (vpl_sum.glsl)
  if (!(pmf > 0.0) || d.index >= uint(vplkit_dprsm_view_texel_count(view))) return c;
  c.s.texel = int(d.index);
  c.pmf = pmf;
  return c;
}

// What the shade of a reservoir needs of its kept sample, made while the candidate was weighed: h
// and the point's position and normal for the visibility query (vplkit_ris_mis_shade_kept).
struct vplkit_ris_mis_kept {
  vec3 h;
  vec3 position;
  vec3 normal;
};

vplkit_ris_mis_kept vplkit_make_ris_mis_kept() {
  return vplkit_ris_mis_kept(vec3(0.0), vec3(0.0), vec3(0.0));
}

// One candidate: draws u (and with vplkit_vpl_patch u0, u1), sets its sample s and its target
// lum(h), and returns its resampling weight target / pmf (0 where the target is 0 or the draw is
// empty; a weight that overflows is not usable and the reservoir skips it). kept receives h and
// the point (h 0 where the weight is).
float vplkit_ris_mis_candidate(vplkit_gather_point gp, vplkit_dprsm_view view, uint distribution,
                               inout vplkit_counter_rng rng, float n1, float n2, int vpl_mode, float depth_tolerance,
                               out vplkit_ris_sample s, out float target, out vplkit_ris_mis_kept kept) {
  target = 0.0;
  kept = vplkit_make_ris_mis_kept();
  float u = vplkit_rng_next_unit(rng);
  vec2 xi = vec2(0.0);
  if (vpl_mode == vplkit_vpl_patch) {
    xi.x = vplkit_rng_next_unit(rng);
    xi.y = vplkit_rng_next_unit(rng);
  }
  vplkit_ris_mis_draw c = vplkit_ris_mis_draw_candidate(view, distribution, u, xi);
  s = c.s;
  if (s.texel < 0) return 0.0;
  float pmf = c.pmf;
  vplkit_vpl v;
  vec3 h = vplkit_ris_mis_unshadowed(gp, view, s, pmf, n1, n2, vpl_mode, depth_tolerance, v);
  float p = vplkit_luminance(h);
  if (!vplkit_reservoir_weight_usable(p)) return 0.0;
  target = p;
  kept = vplkit_ris_mis_kept(h, v.position, v.normal);
  return vplkit_mis_div(p, pmf);  // an overflow is not a usable weight: the reservoir skips it
}

float vplkit_ris_mis_candidate(vplkit_gather_point gp, vplkit_dprsm_view view, uint distribution,
                               inout vplkit_counter_rng rng, float n1, float n2, int vpl_mode, float depth_tolerance,
                               out vplkit_ris_sample s, out float target) {
  vplkit_ris_mis_kept kept;
  return vplkit_ris_mis_candidate(gp, view, distribution, rng, n1, n2, vpl_mode, depth_tolerance, s, target, kept);
}

// One reservoir of n_candidates candidates with the target lum(h) (vplkit_ris_resample's layout and
// normalisation: weight_sum = (1/M) sum w_i, confidence M), and in `kept` the kept sample's h and
// point (vplkit_ris_mis_shade_kept). Empty for an invalid gather point, n_candidates <= 0 or
// n2 <= 0 (no numbers drawn then).
vplkit_ris_reservoir vplkit_ris_mis_resample(vplkit_gather_point gp, vplkit_dprsm_view view, uint distribution,
                                             inout vplkit_counter_rng rng, int n_candidates, float n1, float n2,
                                             int vpl_mode, float depth_tolerance, out vplkit_ris_mis_kept kept) {
  vplkit_ris_reservoir r = vplkit_make_ris_reservoir();
  kept = vplkit_make_ris_mis_kept();
  if (!vplkit_gather_point_valid(gp) || n_candidates <= 0 || !(n2 > 0.0)) return r;
  vplkit_weighted_reservoir res = vplkit_make_weighted_reservoir();
  for (int i = 0; i < n_candidates; ++i) {
    vplkit_ris_sample s;
    float target;
    vplkit_ris_mis_kept made;
    float w =
        vplkit_ris_mis_candidate(gp, view, distribution, rng, n1, n2, vpl_mode, depth_tolerance, s, target, made);
    if (vplkit_reservoir_update(res, uint(i), w, vplkit_rng_next_unit(rng))) {
      r.kept = s;
      r.target = target;
      kept = made;
    }
  }
  float m = float(n_candidates);
  r.confidence = m;
  if (!vplkit_reservoir_empty_of(res)) r.weight_sum = res.weight_sum / m;
  return r;
}

vplkit_ris_reservoir vplkit_ris_mis_resample(vplkit_gather_point gp, vplkit_dprsm_view view, uint distribution,
                                             inout vplkit_counter_rng rng, int n_candidates, float n1, float n2,
                                             int vpl_mode, float depth_tolerance) {
  vplkit_ris_mis_kept kept;
  return vplkit_ris_mis_resample(gp, view, distribution, rng, n_candidates, n1, n2, vpl_mode, depth_tolerance, kept);
}

// h(y) V(x, y) W for the reservoir's sample y, W = weight_sum / target: one RIS estimate of the
// integral of w2 f (V queried only where h is not 0). h uses the pmf hook of `distribution`, the
// distribution the candidates came from. 0 for an invalid gather point or an empty reservoir.
vec3 vplkit_ris_mis_shade(vplkit_gather_point gp, vplkit_dprsm_view view, uint distribution, vplkit_ris_reservoir r,
                          vplkit_visibility visibility, float n1, float n2, int vpl_mode, float depth_tolerance) {
  if (!vplkit_gather_point_valid(gp) || !vplkit_ris_reservoir_has_sample(r)) return vec3(0.0);
  if (r.kept.texel >= vplkit_dprsm_view_texel_count(view)) return vec3(0.0);
  float pmf = vplkit_estimator_pmf(vplkit_estimator_distribution_pmf(distribution, uint(r.kept.texel)));
  vplkit_vpl v;
  vec3 h = vplkit_ris_mis_unshadowed(gp, view, r.kept, pmf, n1, n2, vpl_mode, depth_tolerance, v);
  if (!(h.x > 0.0 || h.y > 0.0 || h.z > 0.0)) return vec3(0.0);
  if (!vplkit_visibility_test(visibility, gp.position, gp.normal, v.position, v.normal)) return vec3(0.0);
  return vplkit_estimator_finite_or_zero(h * vplkit_mis_div(r.weight_sum, r.target));
}

// vplkit_ris_mis_shade for the reservoir that vplkit_ris_mis_resample made at gp, from the h and
// point it kept: the same value, without evaluating h again (the sample hook's pmf is the pmf
// hook's for its index). Not for a reservoir after spatial reuse: vplkit_ris_mis_shade.
vec3 vplkit_ris_mis_shade_kept(vplkit_gather_point gp, vplkit_ris_reservoir r, vplkit_ris_mis_kept kept,
                               vplkit_visibility visibility) {
  if (!vplkit_gather_point_valid(gp) || !vplkit_ris_reservoir_has_sample(r)) return vec3(0.0);
  vec3 h = kept.h;
  if (!(h.x > 0.0 || h.y > 0.0 || h.z > 0.0)) return vec3(0.0);
  if (!vplkit_visibility_test(visibility, gp.position, gp.normal, kept.position, kept.normal)) return vec3(0.0);
  return vplkit_estimator_finite_or_zero(h * vplkit_mis_div(r.weight_sum, r.target));
}

// Steps [begin, end) of vplkit_estimate_ris_mis (estimator_state.glsl); the steps run to
// max(n_dirs, n_ris). Negative counts count as 0; n_candidates <= 0 makes n_ris 0. The weights take
// n2 = vplkit_ris_mis_vpl_samples(n_ris, n_candidates); each RIS value is divided by n_ris.
void vplkit_estimate_ris_mis_range(vplkit_gather_point gp, vplkit_dprsm_view view, uint distribution,
                                   inout vplkit_estimator_state state, int begin, int end, int n_dirs, int n_ris,
                                   int n_candidates, vplkit_voxel_tracer tracer, vplkit_visibility visibility,
                                   float depth_tolerance, int vpl_mode) {
  if (!vplkit_gather_point_valid(gp)) return;
  if (n_dirs < 0) n_dirs = 0;
  if (n_ris < 0 || n_candidates <= 0) n_ris = 0;
  float n1 = float(n_dirs), n2 = vplkit_ris_mis_vpl_samples(n_ris, n_candidates);
  vplkit_orthonormal_basis frame = vplkit_make_orthonormal_basis(vplkit_gather_point_shading_normal(gp));
  for (int j = begin; j < end; ++j) {
    if (j < n_ris) {
      vplkit_ris_mis_kept kept;
      vplkit_ris_reservoir r = vplkit_ris_mis_resample(gp, view, distribution, state.rng, n_candidates, n1, n2,
                                                       vpl_mode, depth_tolerance, kept);
      state.sum += vplkit_ris_mis_shade_kept(gp, r, kept, visibility) / float(n_ris);
    }
    if (j < n_dirs) {
      float u0 = vplkit_rng_next_unit(state.rng);
      float u1 = vplkit_rng_next_unit(state.rng);
      state.sum += vplkit_mis_gathering_sample(gp, view, distribution, frame,
                                               vplkit_sample_cosine_hemisphere(vec2(u0, u1)), tracer,
                                               depth_tolerance, n1, n2, vplkit_mis_solid_angle, vpl_mode);
    }
  }
}

// The 1/n_i are inside the terms (as vplkit_estimate_mis_finish's solid_angle mode).
vec3 vplkit_estimate_ris_mis_finish(vplkit_estimator_state state) {
  return state.sum;
}

// F of the C++ header at gp: n_dirs gathering directions and n_ris RIS samples of n_candidates
// candidates each from `distribution`; n_dirs + n_ris visibility queries, n_ris n_candidates
// candidate evaluations.
vec3 vplkit_estimate_ris_mis(vplkit_gather_point gp, vplkit_dprsm_view view, uint distribution,
                             inout vplkit_counter_rng rng, int n_dirs, int n_ris, int n_candidates,
                             vplkit_voxel_tracer tracer, vplkit_visibility visibility, float depth_tolerance,
                             int vpl_mode) {
  if (!vplkit_gather_point_valid(gp)) return vec3(0.0);
  if (n_dirs < 0) n_dirs = 0;
  if (n_ris < 0 || n_candidates <= 0) n_ris = 0;
  if (n_dirs == 0 && n_ris == 0) return vec3(0.0);
  vplkit_estimator_state state = vplkit_make_estimator_state(rng);
  vplkit_estimate_ris_mis_range(gp, view, distribution, state, 0, n_dirs > n_ris ? n_dirs : n_ris, n_dirs, n_ris,
                                n_candidates, tracer, visibility, depth_tolerance, vpl_mode);
  rng = state.rng;
  return vplkit_estimate_ris_mis_finish(state);
}

#endif  // VPLKIT_ESTIMATORS_RIS_MIS_ESTIMATOR_GLSL
