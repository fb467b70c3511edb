// SPDX-License-Identifier: MIT
// vplkit GLSL pack: bias compensation for the VPL distance clamp (docs/math.md, "The clamp's compensation"; Kollig &
// Keller 2004); mirrors include/vplkit/estimators/clamp_compensation.hpp (T = float), random numbers
// included. Each direction omega ~ cos(theta2)/pi is traced to its first hit y; where y lies closer
// than dmin it adds rho_x L_o(y) (1 - d^2 / dmin^2) (the lit test and L_o of gathering,
// vplkit_evaluate_gathering_hit's, the shadow ray last), what the clamp max(d^2, dmin^2) took from the VPL strategy there.
// Added to a clamped VPL estimate, the sum converges to the unclamped integral where the VPL and
// gathering estimands agree within dmin of x. The rays stop at |dmin|
// (vplkit_voxel_tracer_trace_within: vplkit_user_trace_within where the shader defines it,
// else vplkit_user_trace traces the whole ray, same result).
// ACCESSORS: the DPRSM's and vplkit_load_voxel_word. The decisions (the distance against dmin, x on
// the hit's plane) are `precise`; a hit within about 1e-6 of dmin or of the plane test may still
// decide differently from the C++ (GPU sin/cos of the direction); the parity test counts them.
#ifndef VPLKIT_ESTIMATORS_CLAMP_COMPENSATION_GLSL
#define VPLKIT_ESTIMATORS_CLAMP_COMPENSATION_GLSL

#include "vplkit/core/gather_point.glsl"
#include "vplkit/core/unit_or_zero.glsl"
#include "vplkit/estimators/estimator_state.glsl"
#include "vplkit/estimators/gathering_estimator.glsl"
#include "vplkit/estimators/vpl_sum.glsl"
#include "vplkit/sampling/cosine_hemisphere.glsl"
#include "vplkit/sampling/orthonormal_basis.glsl"
#include "vplkit/sampling/rng.glsl"
#include "vplkit/visibility/visibility_callables.glsl"
#include "vplkit/vpl/dprsm_lookup.glsl"
#include "vplkit/vpl/dprsm_patch.glsl"
#include "vplkit/vpl/dprsm_view.glsl"
#include "vplkit/vpl/vpl.glsl"

// 1 - d^2 / dmin^2 where the clamp is active (d^2 < dmin^2), else 0 (also dmin^2 = 0 or NaN).
float vplkit_clamp_compensation_weight(float d_sq, float dmin) {
  precise float dmin_sq = dmin * dmin;
  if (!(d_sq < dmin_sq)) return 0.0;
  return 1.0 - d_sq / dmin_sq;
}

// May a ray from x meet anything within dmin that counts? False only when the tracer can say that
// every surface point within |dmin| lies in a plane through x (within a quarter of the on-plane
// rule's tolerance); then no direction is traced.
bool vplkit_clamp_compensation_may_add(vplkit_voxel_tracer tracer, vplkit_gather_point gp, float dmin) {
  if (!(dmin * dmin > 0.0)) return false;
  return vplkit_voxel_tracer_surface_within(tracer, gp.position, gp.normal, abs(dmin),
                                            vplkit_vpl_coincidence_tolerance(gp.position, gp.position) / 4.0);
}

// The compensation's own stream for a pixel whose estimator draws from `estimator` (its key only).
vplkit_counter_rng vplkit_clamp_compensation_stream(vplkit_counter_rng estimator) {
  return vplkit_counter_rng(vplkit_rng_key(estimator.key, 0xC1A3C0u), 0u);
}

// What a hit h within dmin of x (its weight > 0) adds: rho_x L_o(y) times its weight, with the lit
// test and L_o of gathering, the lit test's shadow ray last: traced only for a hit whose value would
// not be 0 (the same result as lit test first; vplkit_clamp_compensation_hit_value in the C++).
vec3 vplkit_clamp_compensation_hit_value(vplkit_gather_point gp, vplkit_dprsm_view view, vplkit_ray_hit h, float weight,
                                         vplkit_voxel_tracer tracer, float dmin, float depth_tolerance, int vpl_mode) {
  vplkit_dprsm_lookup_result lk = vplkit_dprsm_lookup(view, h.position, depth_tolerance);
  // vplkit_gathering_hit_lookup's condition: where it holds, the shadow ray alone decides.
  bool shadow_ray = tracer.light_exact && vplkit_ray_hit_has_normal(h) && vplkit_dprsm_texel_saw_surface(view, lk.texel);
  if (!shadow_ray && !lk.lit) return vec3(0.0);
  vec3 radiance = vplkit_dprsm_hit_radiance(view, lk, gp.position, h, depth_tolerance);
  if (!(radiance.x > 0.0 || radiance.y > 0.0 || radiance.z > 0.0)) return vec3(0.0);
  if (vpl_mode == vplkit_vpl_patch && vplkit_dprsm_patch_direction_at_centre(view, lk.texel, h.position)) {
    precise vec3 wc = vplkit_load_dprsm_position(lk.texel) - gp.position;
    precise float dc_sq = dot(wc, wc);
    weight = vplkit_clamp_compensation_weight(dc_sq, dmin);
    if (!(weight > 0.0)) return vec3(0.0);
  }
  if (shadow_ray) {
    vec3 c = view.light.position;
    if (!vplkit_voxel_tracer_light_visible(tracer, h.position, vplkit_ray_hit_normal_towards(h, c), c)) return vec3(0.0);
  }
  return vplkit_estimator_finite_or_zero(gp.albedo * radiance * weight);
}

// Value of one cosine-distributed direction (local: its coordinates in the gather point's ONB);
// with vplkit_vpl_patch a hit whose light direction falls in its texel's moved part
// (vplkit_dprsm_patch_direction_at_centre) is weighed by the texel centre's distance, as the clamp
// weighed it.
vec3 vplkit_clamp_compensation_sample(vplkit_gather_point gp, vplkit_dprsm_view view, vplkit_orthonormal_basis frame,
                                      vec3 local, vplkit_voxel_tracer tracer, float dmin, float depth_tolerance,
                                      int vpl_mode) {
  if (!(dmin * dmin > 0.0) || !(local.z > 0.0)) return vec3(0.0);
  vec3 dir = vplkit_to_world(frame, local);
  if (!vplkit_gather_point_accepts_direction(gp, dir)) return vec3(0.0);
  vplkit_ray_hit h = vplkit_voxel_tracer_trace_within(tracer, gp.position, gp.normal, dir, abs(dmin));
  if (!h.hit) return vec3(0.0);
  precise vec3 w = h.position - gp.position;
  precise float d_sq = dot(w, w);
  float weight = vplkit_clamp_compensation_weight(d_sq, dmin);
  if (!(weight > 0.0)) return vec3(0.0);
  // x on the hit's own plane (a crease through x, coincident surfaces) sees it edge-on: nothing.
  if (vplkit_vpl_hit_on_own_plane(gp.position, h)) return vec3(0.0);
  return vplkit_clamp_compensation_hit_value(gp, view, h, weight, tracer, dmin, depth_tolerance, vpl_mode);
}

vec3 vplkit_clamp_compensation_sample(vplkit_gather_point gp, vplkit_dprsm_view view, vplkit_orthonormal_basis frame,
                                      vec3 local, vplkit_voxel_tracer tracer, float dmin, float depth_tolerance) {
  return vplkit_clamp_compensation_sample(gp, view, frame, local, tracer, dmin, depth_tolerance, vplkit_vpl_point);
}

// Directions [begin, end) of vplkit_estimate_clamp_compensation (estimator_state.glsl).
void vplkit_estimate_clamp_compensation_range(vplkit_gather_point gp, vplkit_dprsm_view view,
                                              inout vplkit_estimator_state state, int begin, int end,
                                              vplkit_voxel_tracer tracer, float dmin, float depth_tolerance,
                                              int vpl_mode) {
  if (!vplkit_gather_point_valid(gp)) return;
  if (begin < end && !vplkit_clamp_compensation_may_add(tracer, gp, dmin)) {
    state.rng.counter += 2u * uint(end - begin);  // the numbers the directions would draw
    return;
  }
  vplkit_orthonormal_basis frame = vplkit_make_orthonormal_basis(vplkit_gather_point_shading_normal(gp));
  for (int k = begin; k < end; ++k) {
    float u0 = vplkit_rng_next_unit(state.rng);
    float u1 = vplkit_rng_next_unit(state.rng);
    state.sum += vplkit_clamp_compensation_sample(gp, view, frame, vplkit_sample_cosine_hemisphere(vec2(u0, u1)),
                                                  tracer, dmin, depth_tolerance, vpl_mode);
  }
}

void vplkit_estimate_clamp_compensation_range(vplkit_gather_point gp, vplkit_dprsm_view view,
                                              inout vplkit_estimator_state state, int begin, int end,
                                              vplkit_voxel_tracer tracer, float dmin, float depth_tolerance) {
  vplkit_estimate_clamp_compensation_range(gp, view, state, begin, end, tracer, dmin, depth_tolerance, vplkit_vpl_point);
}

vec3 vplkit_estimate_clamp_compensation_finish(vplkit_estimator_state state, int n_dirs) {
  return n_dirs > 0 ? state.sum / float(n_dirs) : vec3(0.0);
}

// What the clamp at dmin removed from the VPL estimate at gp, with n_dirs directions.
vec3 vplkit_estimate_clamp_compensation(vplkit_gather_point gp, vplkit_dprsm_view view, inout vplkit_counter_rng rng,
                                        int n_dirs, vplkit_voxel_tracer tracer, float dmin, float depth_tolerance,
                                        int vpl_mode) {
  if (!vplkit_gather_point_valid(gp) || n_dirs <= 0) return vec3(0.0);
  vplkit_estimator_state state = vplkit_make_estimator_state(rng);
  vplkit_estimate_clamp_compensation_range(gp, view, state, 0, n_dirs, tracer, dmin, depth_tolerance, vpl_mode);
  rng = state.rng;
  return vplkit_estimate_clamp_compensation_finish(state, n_dirs);
}

vec3 vplkit_estimate_clamp_compensation(vplkit_gather_point gp, vplkit_dprsm_view view, inout vplkit_counter_rng rng,
                                        int n_dirs, vplkit_voxel_tracer tracer, float dmin, float depth_tolerance) {
  return vplkit_estimate_clamp_compensation(gp, view, rng, n_dirs, tracer, dmin, depth_tolerance, vplkit_vpl_point);
}

#endif  // VPLKIT_ESTIMATORS_CLAMP_COMPENSATION_GLSL
