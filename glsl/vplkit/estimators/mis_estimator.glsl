// SPDX-License-Identifier: MIT
// vplkit GLSL pack: multiple importance sampling of cosine gathering and VPL sampling at one
// gather point (docs/math.md section 5); mirrors include/vplkit/estimators/mis_estimator.hpp
// (T = float): the same modes (vplkit_mis_solid_angle, vplkit_mis_as_published), random numbers
// and order of operations (docs/api/estimators.md, "For the GLSL mirror"). The distribution is an
// id for the two distribution hooks, visibility and tracing are the structs of
// visibility/visibility_callables.glsl (docs/glsl/estimators.md). Never NaN or Inf: every division
// goes through vplkit_balance_combined or vplkit_mis_div behind a guard. As in C++ with its
// defaults, vplkit_mis_gathering_sample, vplkit_estimate_mis_range and vplkit_estimate_mis come
// without and with a last `int vpl_mode`: vplkit_vpl_patch jitters every VPL sample over its
// texel's patch (two more numbers, u0 then u1, after its u) and uses the pointwise density of
// docs/math.md section 11 on both strategies.
#ifndef VPLKIT_ESTIMATORS_MIS_ESTIMATOR_GLSL
#define VPLKIT_ESTIMATORS_MIS_ESTIMATOR_GLSL

#include "vplkit/core/gather_point.glsl"
#include "vplkit/core/unit_or_zero.glsl"
#include "vplkit/distribution/discrete_sample.glsl"
#include "vplkit/estimators/estimator_state.glsl"
#include "vplkit/estimators/gathering_estimator.glsl"
#include "vplkit/estimators/vpl_sum.glsl"
#include "vplkit/mis/heuristics.glsl"
#include "vplkit/mis/pdf_conversion.glsl"
#include "vplkit/paraboloid/paraboloid.glsl"
#include "vplkit/paraboloid/texel_grid.glsl"
#include "vplkit/sampling/cosine_hemisphere.glsl"
#include "vplkit/sampling/orthonormal_basis.glsl"
#include "vplkit/sampling/rng.glsl"
#include "vplkit/visibility/visibility_callables.glsl"
#include "vplkit/vpl/dprsm_patch.glsl"
#include "vplkit/vpl/dprsm_view.glsl"
#include "vplkit/vpl/vpl.glsl"

vplkit_discrete_sample vplkit_estimator_distribution_sample(uint distribution, float u);
float vplkit_estimator_distribution_pmf(uint distribution, uint index);

// C++ enum class mis_mode { solid_angle, as_published }.
const int vplkit_mis_solid_angle = 0;
const int vplkit_mis_as_published = 1;

// f / (n1 p1 + n2 p2) per channel (balance_combined).
vec3 vplkit_mis_balance_value(vec3 f, float n1, float p1, float n2, float p2) {
  return vec3(vplkit_balance_combined(f.x, n1, p1, n2, p2), vplkit_balance_combined(f.y, n1, p1, n2, p2),
              vplkit_balance_combined(f.z, n1, p1, n2, p2));
}

// Area of texel t's patch, A_t = Omega_t d1^2 / cos(alpha), from the texel centre y_t.
float vplkit_mis_texel_patch_area(vplkit_dprsm_view view, int t) {
  vec3 y_t = vplkit_load_dprsm_position(t);
  return vplkit_vpl_patch_area(vplkit_dprsm_view_solid_angle(view, t), vplkit_scaled_length(y_t - view.light.position),
                               vplkit_vpl_cos_alpha(view.light.position, y_t, vplkit_load_dprsm_normal(t)));
}

// p2 of docs/math.md section 5 for the point y on texel t's patch seen from x:
// pmf d2^2 / (A_t cos(theta1)).
float vplkit_mis_vpl_pdf(vplkit_dprsm_view view, int t, float pmf, vec3 x, vec3 y) {
  vec3 w = x - y;
  float cos1 = dot(vplkit_unit_or_zero(vplkit_load_dprsm_normal(t)), vplkit_unit_or_zero(w));
  return vplkit_vpl_pdf_solid_angle(pmf, dot(w, w), vplkit_mis_texel_patch_area(view, t), cos1);
}

// p2 of docs/math.md section 11 for the point y of texel t's patch seen from x (a gathering hit):
// pmf d2^2 / (A(uv) cos(theta1)) with A(uv) = Omega(uv) d1^2 / cos(alpha), all at y itself,
// Omega(uv) over t's patch block.
float vplkit_mis_patch_vpl_pdf(vplkit_dprsm_view view, int t, float pmf, vec3 x, vec3 y) {
  vec3 c = view.light.position;
  vec3 n_t = vplkit_load_dprsm_normal(t);
  vplkit_paraboloid_point q =
      vplkit_paraboloid_from_direction(vplkit_light_frame_to_light(view.light.frame, y - c));
  ivec2 xy = vplkit_texel_coords(t, view.resolution);
  vplkit_texel_block block = vplkit_texel_patch_block(xy.x, xy.y, view.resolution);
  float area = vplkit_vpl_patch_area(vplkit_texel_block_point_solid_angle(q.uv, block, view.resolution),
                                     vplkit_scaled_length(y - c), vplkit_vpl_cos_alpha(c, y, n_t));
  vec3 w = x - y;
  float cos1 = dot(vplkit_unit_or_zero(n_t), vplkit_unit_or_zero(w));
  return vplkit_vpl_pdf_solid_angle(pmf, dot(w, w), area, cos1);
}

// Does the light direction of the gathering hit y fall where texel t's patch moves its points to
// the centre? (vplkit_dprsm_patch_direction_at_centre.)
bool vplkit_mis_patch_hit_at_centre(vplkit_dprsm_view view, int t, vec3 y) {
  return vplkit_dprsm_patch_direction_at_centre(view, t, y);
}

// sin(theta) from cos(theta) as the paper computes it (theta = acos(cos)). `precise`: 1 - c * c
// must not become an FMA (the C++ rounds c * c first).
float vplkit_mis_sin_from_cos(float c) {
  precise float s2 = 1.0 - c * c;
  return s2 > 0.0 ? sqrt(s2) : 0.0;
}

// One gathering sample (local direction in the ONB of n_x); n1 = n_dirs, n2 = n_vpls. A hit on
// x's own plane gives 0 through vplkit_trace_gathering_ray (the C++ says why that is MIS-consistent).
vec3 vplkit_mis_gathering_sample(vplkit_gather_point gp, vplkit_dprsm_view view, uint distribution,
                                 vplkit_orthonormal_basis frame, vec3 local, vplkit_voxel_tracer tracer,
                                 float depth_tolerance, float n1, float n2, int mode, int vpl_mode) {
  float cos2 = local.z;
  if (!(cos2 > 0.0)) return vec3(0.0);
  vec3 dir = vplkit_to_world(frame, local);
  if (!vplkit_gather_point_accepts_direction(gp, dir)) return vec3(0.0);
  vplkit_gathering_ray_result r = vplkit_trace_gathering_ray(view, gp.position, gp.normal, dir, tracer, depth_tolerance);
  if (!r.lit) return vec3(0.0);
  vec3 f = gp.albedo * r.radiance * (cos2 / vplkit_vpl_pi);
  float pmf = vplkit_estimator_pmf(vplkit_estimator_distribution_pmf(distribution, uint(r.texel)));
  if (mode == vplkit_mis_solid_angle) {
    float p1 = vplkit_cosine_pdf_solid_angle(cos2);
    // Hits in front of their texel's surface and the parts of patches whose points sit at the
    // centre belong to gathering alone (weight 1): the VPL strategy samples neither.
    if (n1 > 0.0 && (r.in_front || (vpl_mode == vplkit_vpl_patch && vplkit_mis_patch_hit_at_centre(view, r.texel, r.hit))))
      return vplkit_mis_balance_value(f, n1, p1, 0.0, 0.0);
    float p2 = vpl_mode == vplkit_vpl_patch ? vplkit_mis_patch_vpl_pdf(view, r.texel, pmf, gp.position, r.hit)
                                            : vplkit_mis_vpl_pdf(view, r.texel, pmf, gp.position, r.hit);
    return vplkit_mis_balance_value(f, n1, p1, n2, p2);
  }
  float sin2 = vplkit_mis_sin_from_cos(cos2);
  float p1 = vplkit_cosine_pdf_as_published(cos2, sin2);
  if (!(p1 > 0.0)) return vec3(0.0);
  vplkit_mis_weight_pair w = vplkit_mis_weights_as_published(cos2, sin2, pmf);
  return vplkit_estimator_finite_or_zero(f * vplkit_mis_div(w.gathering, p1));
}

vec3 vplkit_mis_gathering_sample(vplkit_gather_point gp, vplkit_dprsm_view view, uint distribution,
                                 vplkit_orthonormal_basis frame, vec3 local, vplkit_voxel_tracer tracer,
                                 float depth_tolerance, float n1, float n2, int mode) {
  return vplkit_mis_gathering_sample(gp, view, distribution, frame, local, tracer, depth_tolerance, n1, n2, mode,
                                     vplkit_vpl_point);
}

// The solid_angle value of a VPL sample at the VPL v of texel t drawn with probability pmf > 0,
// without its visibility: f at v over n1 p1 + n2 p2, where area is the A of p2 (the texel's A_t for
// a point VPL, A(uv) for a patch point); 0 where v cannot light x (no flux, v at x, either cosine
// not positive, below x's geometric plane). ris_mis_estimator.glsl weighs candidates by it.
vec3 vplkit_mis_vpl_unshadowed(vplkit_gather_point gp, vplkit_dprsm_view view, int t, vplkit_vpl v, float pmf,
                               float area, float n1, float n2) {
  if (!vplkit_vpl_has_flux(v)) return vec3(0.0);
  if (vplkit_vpl_points_coincide(gp.position, v.position)) return vec3(0.0);
  vec3 wd = vplkit_unit_or_zero(v.position - gp.position);  // x -> y
  float cos2 = dot(vplkit_unit_or_zero(vplkit_gather_point_shading_normal(gp)), wd);
  float cos1 = -dot(vplkit_unit_or_zero(v.normal), wd);
  if (!(cos2 > 0.0) || !(cos1 > 0.0) || !vplkit_gather_point_above(gp, wd)) return vec3(0.0);
  vec3 f = gp.albedo *
           vplkit_reflected_radiance(view.light.position, view.light.intensity, v.position, v.normal,
                                     vplkit_load_dprsm_albedo(t)) *
           (cos2 / vplkit_vpl_pi);
  float p1 = vplkit_cosine_pdf_solid_angle(cos2);
  vec3 w = gp.position - v.position;
  float p2 = vplkit_vpl_pdf_solid_angle(pmf, dot(w, w), area, cos1);
  return vplkit_mis_balance_value(f, n1, p1, n2, p2);
}

// The value of a VPL sample at the VPL v of texel t, drawn with probability pmf > 0; area is the A
// of its p2. solid_angle: vplkit_mis_vpl_unshadowed times V(x, v), queried only where that is not
// 0; as_published: the paper's weights at (direction to v, pmf) times L_v V / pmf.
vec3 vplkit_mis_vpl_value(vplkit_gather_point gp, vplkit_dprsm_view view, int t, vplkit_vpl v, float pmf,
                          float area, vplkit_visibility visibility, float n1, float n2, int mode) {
  if (mode == vplkit_mis_as_published) {
    vec3 c = vplkit_vpl_contribution(gp, v, 0.0);
    if (!(c.x > 0.0 || c.y > 0.0 || c.z > 0.0)) return vec3(0.0);
    if (!vplkit_visibility_test(visibility, gp.position, gp.normal, v.position, v.normal)) return vec3(0.0);
    float cos2 = dot(vplkit_unit_or_zero(vplkit_gather_point_shading_normal(gp)), vplkit_unit_or_zero(v.position - gp.position));
    vplkit_mis_weight_pair w = vplkit_mis_weights_as_published(cos2, vplkit_mis_sin_from_cos(cos2), pmf);
    return vplkit_estimator_finite_or_zero(c * vplkit_mis_div(w.vpl, pmf));
  }
  vec3 value = vplkit_mis_vpl_unshadowed(gp, view, t, v, pmf, area, n1, n2);
  if (!(value.x > 0.0 || value.y > 0.0 || value.z > 0.0)) return vec3(0.0);
  if (!vplkit_visibility_test(visibility, gp.position, gp.normal, v.position, v.normal)) return vec3(0.0);
  return value;
}

// One VPL sample drawn with u (vplkit_vpl_point: the VPL at the texel centre).
vec3 vplkit_mis_vpl_sample(vplkit_gather_point gp, vplkit_dprsm_view view, uint distribution, float u,
                           vplkit_visibility visibility, float n1, float n2, int mode) {
  vplkit_discrete_sample s = vplkit_estimator_distribution_sample(distribution, u);
  float pmf = vplkit_estimator_pmf(s.pmf);
  if (!(pmf > 0.0) || s.index >= uint(vplkit_dprsm_view_texel_count(view))) return vec3(0.0);
  int t = int(s.index);
  return vplkit_mis_vpl_value(gp, view, t, vplkit_dprsm_view_vpl_at(view, t), pmf,
                              vplkit_mis_texel_patch_area(view, t), visibility, n1, n2, mode);
}

// One patch-sampled VPL sample drawn with u and jittered by xi, with the lookup's depth window.
vec3 vplkit_mis_vpl_patch_sample(vplkit_gather_point gp, vplkit_dprsm_view view, uint distribution, float u,
                                 vec2 xi, vplkit_visibility visibility, float n1, float n2, int mode,
                                 float depth_tolerance) {
  vplkit_discrete_sample s = vplkit_estimator_distribution_sample(distribution, u);
  float pmf = vplkit_estimator_pmf(s.pmf);
  if (!(pmf > 0.0) || s.index >= uint(vplkit_dprsm_view_texel_count(view))) return vec3(0.0);
  int t = int(s.index);
  vplkit_dprsm_patch_sample p = vplkit_dprsm_patch_vpl(view, t, xi, depth_tolerance);
  // A point moved to the centre: gathering covers its directions alone unless none is traced.
  if (p.at_centre && n1 > 0.0) return vec3(0.0);
  return vplkit_mis_vpl_value(gp, view, t, p.point, pmf, vplkit_vpl_patch_area(p.solid_angle, p.distance, p.cos_alpha),
                              visibility, n1, n2, mode);
}

// Steps [begin, end) of vplkit_estimate_mis (estimator_state.glsl); step j draws VPL j
// (j < n_vpls), then direction j (j < n_dirs). Negative counts count as 0.
void vplkit_estimate_mis_range(vplkit_gather_point gp, vplkit_dprsm_view view, uint distribution,
                               inout vplkit_estimator_state state, int begin, int end, int n_dirs, int n_vpls,
                               vplkit_voxel_tracer tracer, vplkit_visibility visibility, float depth_tolerance,
                               int mode, int vpl_mode) {
  if (!vplkit_gather_point_valid(gp)) return;
  if (n_dirs < 0) n_dirs = 0;
  if (n_vpls < 0) n_vpls = 0;
  float n1 = float(n_dirs), n2 = float(n_vpls);
  vplkit_orthonormal_basis frame = vplkit_make_orthonormal_basis(vplkit_gather_point_shading_normal(gp));
  for (int j = begin; j < end; ++j) {
    if (j < n_vpls) {
      float u = vplkit_rng_next_unit(state.rng);
      if (vpl_mode == vplkit_vpl_patch) {
        float u0 = vplkit_rng_next_unit(state.rng);
        float u1 = vplkit_rng_next_unit(state.rng);
        state.sum += vplkit_mis_vpl_patch_sample(gp, view, distribution, u, vec2(u0, u1), visibility, n1, n2, mode,
                                                 depth_tolerance);
      } else {
        state.sum += vplkit_mis_vpl_sample(gp, view, distribution, u, visibility, n1, n2, mode);
      }
    }
    if (j < n_dirs) {
      float u0 = vplkit_rng_next_unit(state.rng);
      float u1 = vplkit_rng_next_unit(state.rng);
      state.sum += vplkit_mis_gathering_sample(gp, view, distribution, frame,
                                               vplkit_sample_cosine_hemisphere(vec2(u0, u1)), tracer,
                                               depth_tolerance, n1, n2, mode, vpl_mode);
    }
  }
}

void vplkit_estimate_mis_range(vplkit_gather_point gp, vplkit_dprsm_view view, uint distribution,
                               inout vplkit_estimator_state state, int begin, int end, int n_dirs, int n_vpls,
                               vplkit_voxel_tracer tracer, vplkit_visibility visibility, float depth_tolerance,
                               int mode) {
  vplkit_estimate_mis_range(gp, view, distribution, state, begin, end, n_dirs, n_vpls, tracer, visibility,
                            depth_tolerance, mode, vplkit_vpl_point);
}

// solid_angle: the 1/n_i are inside balance_combined. as_published: Alg. 4 divides by NBDIR.
vec3 vplkit_estimate_mis_finish(vplkit_estimator_state state, int n_dirs, int n_vpls, int mode) {
  if (n_dirs < 0) n_dirs = 0;
  if (n_vpls < 0) n_vpls = 0;
  if (n_dirs == 0 && n_vpls == 0) return vec3(0.0);
  if (mode == vplkit_mis_as_published) return state.sum / float(n_dirs > 0 ? n_dirs : n_vpls);
  return state.sum;
}

vec3 vplkit_estimate_mis(vplkit_gather_point gp, vplkit_dprsm_view view, uint distribution,
                         inout vplkit_counter_rng rng, int n_dirs, int n_vpls, vplkit_voxel_tracer tracer,
                         vplkit_visibility visibility, float depth_tolerance, int mode, int vpl_mode) {
  if (!vplkit_gather_point_valid(gp)) return vec3(0.0);
  if (n_dirs < 0) n_dirs = 0;
  if (n_vpls < 0) n_vpls = 0;
  if (n_dirs == 0 && n_vpls == 0) return vec3(0.0);
  vplkit_estimator_state state = vplkit_make_estimator_state(rng);
  vplkit_estimate_mis_range(gp, view, distribution, state, 0, n_dirs > n_vpls ? n_dirs : n_vpls, n_dirs, n_vpls,
                            tracer, visibility, depth_tolerance, mode, vpl_mode);
  rng = state.rng;
  return vplkit_estimate_mis_finish(state, n_dirs, n_vpls, mode);
}

vec3 vplkit_estimate_mis(vplkit_gather_point gp, vplkit_dprsm_view view, uint distribution,
                         inout vplkit_counter_rng rng, int n_dirs, int n_vpls, vplkit_voxel_tracer tracer,
                         vplkit_visibility visibility, float depth_tolerance, int mode) {
  return vplkit_estimate_mis(gp, view, distribution, rng, n_dirs, n_vpls, tracer, visibility, depth_tolerance, mode,
                             vplkit_vpl_point);
}

#endif  // VPLKIT_ESTIMATORS_MIS_ESTIMATOR_GLSL
