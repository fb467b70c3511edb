// SPDX-License-Identifier: MIT
// vplkit GLSL pack: cosine gathering through the DPRSM (docs/math.md section 5, strategy 1; the
// paper's Alg. 5 without MIS); mirrors include/vplkit/estimators/gathering_estimator.hpp
// (T = float), random numbers included: each direction omega ~ cos(theta2)/pi adds
// f / p1 = rho_x L_o(y) where the DPRSM sees its first hit y lit from the front (0 for a hit on
// x's own plane, vplkit_vpl_hit_on_own_plane). Tracing: a
// vplkit_voxel_tracer stands for the C++ tracer (use depth_tolerance >=
// vplkit_voxel_tracer_depth_tolerance). ACCESSORS: the DPRSM's and vplkit_load_voxel_word.
// Rays within about 1e-6 of a voxel edge, texel edge or the tolerance may decide differently from
// the C++ (GPU sin/cos); the parity test counts them (docs/glsl/estimators.md).
#ifndef VPLKIT_ESTIMATORS_GATHERING_ESTIMATOR_GLSL
#define VPLKIT_ESTIMATORS_GATHERING_ESTIMATOR_GLSL

#include "vplkit/core/gather_point.glsl"
#include "vplkit/estimators/estimator_state.glsl"
#include "vplkit/estimators/vpl_sum.glsl"
#include "vplkit/sampling/cosine_hemisphere.glsl"
#include "vplkit/sampling/orthonormal_basis.glsl"
#include "vplkit/sampling/rng.glsl"
#include "vplkit/visibility/visibility_callables.glsl"
#include "vplkit/vpl/dprsm_lookup.glsl"
#include "vplkit/vpl/dprsm_view.glsl"
#include "vplkit/vpl/vpl.glsl"

// What one gathering ray found.
struct vplkit_gathering_ray_result {
  bool lit;       // hit, projected into a texel that saw it, seen from its lit side
  bool in_front;  // lit, in front of the surface its texel saw
  int texel;      // the DPRSM texel the hit projects into (-1: no hit / at the light)
  vec3 hit;       // y (valid when texel >= 0)
  vec3 radiance;  // L_o(y) towards x; 0 unless lit
};

// The texel a gathering hit projects into and whether the light reaches it: the DPRSM's plane
// test, or the tracer's shadow ray (light_exact) where the hit's surface is known.
vplkit_dprsm_lookup_result vplkit_gathering_hit_lookup(vplkit_dprsm_view view, vplkit_ray_hit h,
                                                       vplkit_voxel_tracer tracer, float depth_tolerance) {
  vplkit_dprsm_lookup_result lk = vplkit_dprsm_lookup(view, h.position, depth_tolerance);
  if (tracer.light_exact && vplkit_ray_hit_has_normal(h) && vplkit_dprsm_texel_saw_surface(view, lk.texel)) {
    vec3 c = view.light.position;
    lk.lit = vplkit_voxel_tracer_light_visible(tracer, h.position, vplkit_ray_hit_normal_towards(h, c), c);
    lk.in_front = lk.in_front && lk.lit;
  }
  return lk;
}

// What the hit h of a ray leaving x sends towards x: the lookup and L_o (no hit: nothing). Shared by
// vplkit_trace_gathering_ray and the clamp compensation (clamp_compensation.glsl).
vplkit_gathering_ray_result vplkit_evaluate_gathering_hit(vplkit_dprsm_view view, vec3 x, vplkit_ray_hit h,
                                                          vplkit_voxel_tracer tracer, float depth_tolerance) {
  vplkit_gathering_ray_result r = vplkit_gathering_ray_result(false, false, -1, vec3(0.0), vec3(0.0));
  if (!h.hit) return r;
  vplkit_dprsm_lookup_result lk = vplkit_gathering_hit_lookup(view, h, tracer, depth_tolerance);
  r.texel = lk.texel;
  r.hit = h.position;
  if (!lk.lit) return r;
  r.radiance = vplkit_dprsm_hit_radiance(view, lk, x, h, depth_tolerance);
  r.lit = r.radiance.x > 0.0 || r.radiance.y > 0.0 || r.radiance.z > 0.0;
  r.in_front = r.lit && lk.in_front;
  return r;
}

// Traces the ray leaving surface x (normal n_x, any length) along dir and evaluates L_o at the hit;
// a hit on x's own plane (vplkit_vpl_hit_on_own_plane) sends nothing and reads as no hit (texel
// -1), as in the C++.
vplkit_gathering_ray_result vplkit_trace_gathering_ray(vplkit_dprsm_view view, vec3 x, vec3 n_x, vec3 dir,
                                                       vplkit_voxel_tracer tracer, float depth_tolerance) {
  vplkit_ray_hit h = vplkit_voxel_tracer_trace(tracer, x, n_x, dir);
  if (vplkit_vpl_hit_on_own_plane(x, h))
    return vplkit_gathering_ray_result(false, false, -1, vec3(0.0), vec3(0.0));
  return vplkit_evaluate_gathering_hit(view, x, h, tracer, depth_tolerance);
}

// Value of one cosine-distributed direction (local: its coordinates in the gather point's ONB):
// f / p1 = rho_x L_o(y) (the cos(theta2)/pi of f and p1 cancel); 0 at or below the horizon, and
// 0 below the geometric surface (the frame is the shading normal's).
vec3 vplkit_gathering_sample(vplkit_gather_point gp, vplkit_dprsm_view view, vplkit_orthonormal_basis frame,
                             vec3 local, vplkit_voxel_tracer tracer, float depth_tolerance) {
  if (!(local.z > 0.0)) return vec3(0.0);
  vec3 dir = vplkit_to_world(frame, local);
  if (!vplkit_gather_point_accepts_direction(gp, dir)) return vec3(0.0);
  vplkit_gathering_ray_result r = vplkit_trace_gathering_ray(view, gp.position, gp.normal, dir, tracer, depth_tolerance);
  return vplkit_estimator_finite_or_zero(gp.albedo * r.radiance);
}

// Directions [begin, end) of vplkit_estimate_gathering (estimator_state.glsl).
void vplkit_estimate_gathering_range(vplkit_gather_point gp, vplkit_dprsm_view view,
                                     inout vplkit_estimator_state state, int begin, int end,
                                     vplkit_voxel_tracer tracer, float depth_tolerance) {
  if (!vplkit_gather_point_valid(gp)) return;
  vplkit_orthonormal_basis frame = vplkit_make_orthonormal_basis(vplkit_gather_point_shading_normal(gp));
  for (int k = begin; k < end; ++k) {
    float u0 = vplkit_rng_next_unit(state.rng);
    float u1 = vplkit_rng_next_unit(state.rng);
    state.sum += vplkit_gathering_sample(gp, view, frame, vplkit_sample_cosine_hemisphere(vec2(u0, u1)), tracer,
                                         depth_tolerance);
  }
}

vec3 vplkit_estimate_gathering_finish(vplkit_estimator_state state, int n_dirs) {
  return n_dirs > 0 ? state.sum / float(n_dirs) : vec3(0.0);
}

vec3 vplkit_estimate_gathering(vplkit_gather_point gp, vplkit_dprsm_view view, inout vplkit_counter_rng rng,
                               int n_dirs, vplkit_voxel_tracer tracer, float depth_tolerance) {
  if (!vplkit_gather_point_valid(gp) || n_dirs <= 0) return vec3(0.0);
  vplkit_estimator_state state = vplkit_make_estimator_state(rng);
  vplkit_estimate_gathering_range(gp, view, state, 0, n_dirs, tracer, depth_tolerance);
  rng = state.rng;
  return vplkit_estimate_gathering_finish(state, n_dirs);
}

#endif  // VPLKIT_ESTIMATORS_GATHERING_ESTIMATOR_GLSL
