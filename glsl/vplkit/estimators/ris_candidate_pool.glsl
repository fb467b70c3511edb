// SPDX-License-Identifier: MIT
// vplkit GLSL pack: presampled candidates for ris-mis (docs/math.md, "Presampled candidates");
// mirrors include/vplkit/estimators/ris_candidate_pool.hpp (T = float), whose header states why the
// estimate stays unbiased. Once per frame a pool of P entries (vplkit_ris_pool_entry,
// ris_pool_entry.glsl) is drawn from the candidate distribution (vplkit_ris_pool_draw_entry for
// i < P, in any order), each holding what weighing it at a gather point needs; a gather point's
// candidate is then an entry drawn uniformly from the pool, weighed by ris_mis_estimator.glsl's h
// on the entry's stored parts. The estimate and its MIS weights are vplkit_estimate_ris_mis's.
// Random numbers, as the C++: entry i of a pool filled with seed s takes the stream (s, i): u, then
// with vplkit_vpl_patch xi0 and xi1. A candidate from the pool takes u (the entry
// vplkit_ris_pool_index(u, P)) and then its selection u: 2 M numbers per reservoir in both VPL
// modes. A pool is an id for the accessor (the C++ pointer): a host with one pool per candidate
// distribution (the local source's regions) maps (pool, index) to its buffer.
// ACCESSOR: vplkit_ris_pool_entry vplkit_load_ris_pool_entry(uint pool, uint index), entry
// index < pool_size of pool `pool` (with ris_pool_params.h:
// `return vplkit_ris_pool_entry_from_record(records[pool * P + index]);`).
// HOOKS: those of ris_mis_estimator.glsl (the distribution's sample hook fills the pool, its pmf
// hook gives the gathering hits' p2). The pool must have been drawn from the distribution whose id
// the estimate gets.
#ifndef VPLKIT_ESTIMATORS_RIS_CANDIDATE_POOL_GLSL
#define VPLKIT_ESTIMATORS_RIS_CANDIDATE_POOL_GLSL

#include "vplkit/core/gather_point.glsl"
#include "vplkit/core/normal_range.glsl"
#include "vplkit/core/unit_or_zero.glsl"
#include "vplkit/distribution/weighted_reservoir.glsl"
#include "vplkit/estimators/estimator_state.glsl"
#include "vplkit/estimators/mis_estimator.glsl"
#include "vplkit/estimators/ris_mis_estimator.glsl"
#include "vplkit/estimators/ris_pool_entry.glsl"
#include "vplkit/estimators/ris_reservoir.glsl"
#include "vplkit/estimators/vpl_sum.glsl"
#include "vplkit/mis/heuristics.glsl"
#include "vplkit/mis/pdf_conversion.glsl"
#include "vplkit/sampling/cosine_hemisphere.glsl"
#include "vplkit/sampling/orthonormal_basis.glsl"
#include "vplkit/sampling/rng.glsl"
#include "vplkit/visibility/visibility_callables.glsl"
#include "vplkit/vpl/dprsm_patch.glsl"
#include "vplkit/vpl/dprsm_view.glsl"
#include "vplkit/vpl/luminance.glsl"
#include "vplkit/vpl/vpl.glsl"

vplkit_ris_pool_entry vplkit_load_ris_pool_entry(uint pool, uint index);

// Entry for the draw c (vplkit_ris_mis_draw_candidate) with its jitter already in c.s.xi. The unit
// normal of a patch point is its texel's plane record's (vplkit_dprsm_view_plane_at: one load with
// VPLKIT_DPRSM_PLANE_ACCESSOR), as the C++ takes it; the radiance is made from that unit normal.
vplkit_ris_pool_entry vplkit_ris_pool_make_entry(vplkit_dprsm_view view, vplkit_ris_mis_draw c, int vpl_mode,
                                                 float depth_tolerance) {
  vplkit_ris_pool_entry e = vplkit_make_ris_pool_entry();
  e.texel = c.s.texel;
  e.xi = c.s.xi;
  if (c.s.texel < 0 || !(c.pmf > 0.0)) return e;
  vplkit_vpl v;
  vec3 n_v;
  float area;
  if (vpl_mode == vplkit_vpl_patch) {
    vplkit_dprsm_patch_sample p = vplkit_dprsm_patch_vpl(view, c.s.texel, c.s.xi, depth_tolerance);
    v = p.point;
    if (!vplkit_vpl_has_flux(v)) return e;
    // A point with flux has a plane (height != 0), whose normal is unit_or_zero(n_t).
    n_v = vplkit_dprsm_view_plane_at(view, c.s.texel).xyz;
    area = vplkit_vpl_patch_area(p.solid_angle, p.distance, p.cos_alpha);
    e.at_centre = p.at_centre ? 1 : 0;
  } else {
    v = vplkit_dprsm_view_vpl_at(view, c.s.texel);
    if (!vplkit_vpl_has_flux(v)) return e;
    n_v = vplkit_unit_or_zero(v.normal);
    area = vplkit_mis_texel_patch_area(view, c.s.texel);
  }
  e.position = v.position;
  e.normal = n_v;
  e.area = area;
  e.radiance = vplkit_reflected_radiance_unit_normal(view.light.position, view.light.intensity, v.position, n_v,
                                                     vplkit_load_dprsm_albedo(c.s.texel));
  e.pmf = c.pmf;
  return e;
}

// Entry i of a pool: draws u, then with vplkit_vpl_patch xi0, xi1, from the stream (seed, i).
vplkit_ris_pool_entry vplkit_ris_pool_draw_entry(vplkit_dprsm_view view, uint distribution, uint seed, uint i,
                                                 int vpl_mode, float depth_tolerance) {
  vplkit_counter_rng rng = vplkit_make_counter_rng(seed, i);
  float u = vplkit_rng_next_unit(rng);
  vec2 xi = vec2(0.0);
  if (vpl_mode == vplkit_vpl_patch) {
    xi.x = vplkit_rng_next_unit(rng);
    xi.y = vplkit_rng_next_unit(rng);
  }
  return vplkit_ris_pool_make_entry(view, vplkit_ris_mis_draw_candidate(view, distribution, u, xi), vpl_mode,
                                    depth_tolerance);
}

// h of vplkit_ris_mis_unshadowed for entry e: the expressions of vplkit_mis_vpl_unshadowed on the
// stored parts (the entry's normal is already unit). 0 for an empty entry, n2 <= 0, an at-centre
// point when n1 > 0, or a point that cannot light x.
vec3 vplkit_ris_pool_unshadowed(vplkit_gather_point gp, vplkit_ris_pool_entry e, float n1, float n2) {
  float pmf = vplkit_estimator_pmf(e.pmf);  // a denormal pmf counts as 0 (vpl_sum.glsl)
  if (!(pmf > 0.0) || !(n2 > 0.0)) return vec3(0.0);
  if (e.at_centre != 0 && n1 > 0.0) return vec3(0.0);
  if (vplkit_vpl_points_coincide(gp.position, e.position)) return vec3(0.0);
  vec3 wd = vplkit_unit_or_zero(e.position - gp.position);  // x -> y
  float cos2 = dot(vplkit_unit_or_zero(vplkit_gather_point_shading_normal(gp)), wd);
  float cos1 = -dot(e.normal, wd);
  if (!(cos2 > 0.0) || !(cos1 > 0.0) || !vplkit_gather_point_above(gp, wd)) return vec3(0.0);
  vec3 f = gp.albedo * e.radiance * (cos2 / vplkit_vpl_pi);
  float p1 = vplkit_cosine_pdf_solid_angle(cos2);
  vec3 w = gp.position - e.position;
  float p2 = vplkit_vpl_pdf_solid_angle(pmf, dot(w, w), e.area, cos1);
  return vplkit_estimator_finite_or_zero(vplkit_mis_balance_value(f, n1, p1, n2, p2) * (n2 * pmf));
}

// The entry that u in [0, 1) picks of a pool of pool_size > 0 entries: floor(u P), clamped below P.
// `precise`: the product must be the C++'s correctly rounded one (it decides the entry); NaN is
// tested on the bits (a compiler may fold the comparison), and reads as the first entry.
uint vplkit_ris_pool_index(float u, uint pool_size) {
  precise float x = u * float(pool_size);
  if (vplkit_is_nan(x) || !(x > 0.0)) return 0u;
  uint i = x < float(pool_size) ? uint(x) : pool_size;
  return i < pool_size ? i : pool_size - 1u;
}

// One reservoir of n_candidates candidates drawn uniformly from pool `pool` (pool_size entries):
// vplkit_ris_mis_resample's normalisation and kept record (vplkit_ris_mis_shade_kept shades it), the
// kept sample as (texel, xi) for spatial reuse. Empty for an invalid gather point, n_candidates
// <= 0, n2 <= 0 or an empty pool (no numbers drawn then). The weight target / pmf goes through
// vplkit_mis_div and the selection through vplkit_reservoir_update (`precise` u S < w), as in
// vplkit_ris_mis_resample.
vplkit_ris_reservoir vplkit_ris_mis_resample_pooled(vplkit_gather_point gp, uint pool, uint pool_size,
                                                    inout vplkit_counter_rng rng, int n_candidates, float n1, float n2,
                                                    out vplkit_ris_mis_kept kept) {
  vplkit_ris_reservoir r = vplkit_make_ris_reservoir();
  kept = vplkit_make_ris_mis_kept();
  if (!vplkit_gather_point_valid(gp) || n_candidates <= 0 || !(n2 > 0.0) || pool_size == 0u) return r;
  vplkit_weighted_reservoir res = vplkit_make_weighted_reservoir();
  for (int k = 0; k < n_candidates; ++k) {
    float u = vplkit_rng_next_unit(rng);
    float u_keep = vplkit_rng_next_unit(rng);
    vplkit_ris_pool_entry e = vplkit_load_ris_pool_entry(pool, vplkit_ris_pool_index(u, pool_size));
    vec3 h = vplkit_ris_pool_unshadowed(gp, e, n1, n2);
    float target = vplkit_luminance(h);
    if (!vplkit_reservoir_weight_usable(target)) continue;
    // An overflowing quotient is not a usable weight: the reservoir skips it.
    if (vplkit_reservoir_update(res, uint(k), vplkit_mis_div(target, vplkit_estimator_pmf(e.pmf)), u_keep)) {
      r.kept = vplkit_ris_sample(e.texel, e.xi);
      r.target = target;
      kept = vplkit_ris_mis_kept(h, e.position, e.normal);
    }
  }
  float m = float(n_candidates);
  r.confidence = m;
  if (!vplkit_reservoir_empty_of(res)) r.weight_sum = res.weight_sum / m;
  return r;
}

// Steps [begin, end) of vplkit_estimate_ris_mis_pooled (estimator_state.glsl):
// vplkit_estimate_ris_mis_range with each reservoir's candidates from the pool. `distribution` is
// the one the pool was drawn from (the gathering directions' p2 reads its pmf). Negative counts
// count as 0; n_candidates <= 0 or an empty pool (pool_size 0) makes n_ris 0 (gathering alone).
void vplkit_estimate_ris_mis_pooled_range(vplkit_gather_point gp, vplkit_dprsm_view view, uint distribution,
                                          uint pool, uint pool_size, inout vplkit_estimator_state state, int begin,
                                          int end, int n_dirs, int n_ris, int n_candidates,
                                          vplkit_voxel_tracer tracer, vplkit_visibility visibility,
                                          float depth_tolerance, int vpl_mode) {
  if (!vplkit_gather_point_valid(gp)) return;
  if (n_dirs < 0) n_dirs = 0;
  if (n_ris < 0 || n_candidates <= 0 || pool_size == 0u) n_ris = 0;  // an empty pool: gathering alone
  float n1 = float(n_dirs), n2 = vplkit_ris_mis_vpl_samples(n_ris, n_candidates);
  vplkit_orthonormal_basis frame = vplkit_make_orthonormal_basis(vplkit_gather_point_shading_normal(gp));
  for (int j = begin; j < end; ++j) {
    if (j < n_ris) {
      vplkit_ris_mis_kept kept;
      vplkit_ris_reservoir r =
          vplkit_ris_mis_resample_pooled(gp, pool, pool_size, state.rng, n_candidates, n1, n2, kept);
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

// vplkit_estimate_ris_mis with the candidates of every reservoir drawn from pool `pool`; the range
// form finishes with vplkit_estimate_ris_mis_finish.
vec3 vplkit_estimate_ris_mis_pooled(vplkit_gather_point gp, vplkit_dprsm_view view, uint distribution, uint pool,
                                    uint pool_size, inout vplkit_counter_rng rng, int n_dirs, int n_ris,
                                    int n_candidates, vplkit_voxel_tracer tracer, vplkit_visibility visibility,
                                    float depth_tolerance, int vpl_mode) {
  if (!vplkit_gather_point_valid(gp)) return vec3(0.0);
  if (n_dirs < 0) n_dirs = 0;
  if (n_ris < 0 || n_candidates <= 0 || pool_size == 0u) n_ris = 0;  // an empty pool: gathering alone
  if (n_dirs == 0 && n_ris == 0) return vec3(0.0);
  vplkit_estimator_state state = vplkit_make_estimator_state(rng);
  vplkit_estimate_ris_mis_pooled_range(gp, view, distribution, pool, pool_size, state, 0,
                                       n_dirs > n_ris ? n_dirs : n_ris, n_dirs, n_ris, n_candidates, tracer,
                                       visibility, depth_tolerance, vpl_mode);
  rng = state.rng;
  return vplkit_estimate_ris_mis_finish(state);
}

#endif  // VPLKIT_ESTIMATORS_RIS_CANDIDATE_POOL_GLSL
