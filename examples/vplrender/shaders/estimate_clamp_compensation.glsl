// SPDX-License-Identifier: MIT
// vplrender's estimate kernels with VR_CLAMP_COMPENSATION (--clamp-compensation on; reference,
// global, gbg, local, ris): what the VPL clamp max(d^2, dmin^2) removed, added back to the pixel's
// estimate (docs/math.md, "The clamp's compensation"; vplkit_estimate_clamp_compensation), as the
// CPU backend adds it: clamp_dirs cosine directions per gather point from the pixel's
// vplkit_clamp_compensation_stream, traced by vr_make_tracer (the gathering rays' visibility and
// lit test), the estimate's VR_VPL_MODE, dmin and depth tolerance; finished, then added to the
// finished estimate. The directions are the kernel's units [clamp_first_unit, clamp_first_unit +
// clamp_dirs) after the estimator's, so a split render (VR_SPLIT 1) cuts them with the same
// [begin, end) and keeps their state between dispatches in the lanes of vr_pixel_state the
// estimators leave free (estimate_params.h). Without the define this file adds nothing.
// Included after estimate_visibility.glsl (its tracer and accessors; with exact rays also the
// triangle voxel lists and their near-surface test).
#ifndef VPLRENDER_ESTIMATE_CLAMP_COMPENSATION_GLSL
#define VPLRENDER_ESTIMATE_CLAMP_COMPENSATION_GLSL

#include "estimate_visibility.glsl"
#include "vplkit/estimators/clamp_compensation.glsl"

#ifdef VR_CLAMP_COMPENSATION
// The compensation's state at the start of this dispatch: its fresh stream, or the state kept.
vplkit_estimator_state vr_begin_clamp_compensation(uint p) {
  vplkit_counter_rng rng = vplkit_clamp_compensation_stream(vplkit_make_counter_rng(vr_params.seed, p));
#if VR_SPLIT
  if (vr_params.first_pass == 0) {
    vr_pixel_state s = vr_states[p];
    return vplkit_estimator_state(vec3(s.sum.w, s.comp.w, uintBitsToFloat(s.rng.z)),
                                  vplkit_counter_rng(rng.key, s.rng.w));
  }
#endif
  return vplkit_make_estimator_state(rng);
}

// Directions [begin, end) of the compensation at gp (a valid gather point).
void vr_clamp_compensation_dirs(vplkit_gather_point gp, inout vplkit_estimator_state c, int begin, int end) {
  if (!(begin < end)) return;
#if VR_VISIBILITY == VR_VISIBILITY_EXACT
  // The BVH tracer answers vplkit_voxel_tracer_surface_within with true (it cannot say), so every
  // gather point would trace; the CPU backend's exact tracer asks the triangle voxel grid (the same
  // triangles), and so does this: no other surface within dmin, no direction traced, the numbers
  // they would draw skipped (vplkit_clamp_compensation_may_add's test, with the grid's answer).
  if (!vplkit_triangle_voxel_surface_within(vr_grid(), gp.position, abs(vr_params.dmin),
                                            vplkit_vpl_coincidence_tolerance(gp.position, gp.position) / 4.0)) {
    c.rng.counter += 2u * uint(end - begin);
    return;
  }
#endif
  vplkit_estimate_clamp_compensation_range(gp, vr_view(), c, begin, end, vr_make_tracer(vr_grid()), vr_params.dmin,
                                           vr_params.depth_tolerance, VR_VPL_MODE);
}

// This dispatch's directions of the compensation at gp: the units of [begin, end) at or after
// clamp_first_unit.
void vr_clamp_compensation_range(vplkit_gather_point gp, inout vplkit_estimator_state c) {
  vr_clamp_compensation_dirs(gp, c, max(vr_params.begin - vr_params.clamp_first_unit, 0),
                             min(max(vr_params.end - vr_params.clamp_first_unit, 0), vr_params.clamp_dirs));
}

// Its state into the free lanes, after vr_keep_estimate / vr_keep_sum wrote the estimator's.
void vr_keep_clamp_compensation(uint p, vplkit_estimator_state c) {
#if VR_SPLIT
  if (vr_params.last_pass == 0) {
    vr_states[p].sum.w = c.sum.x;
    vr_states[p].comp.w = c.sum.y;
    vr_states[p].rng.z = floatBitsToUint(c.sum.z);
    vr_states[p].rng.w = c.rng.counter;
  }
#endif
}

// What the last dispatch adds to the finished estimate.
vec3 vr_finish_clamp_compensation(vplkit_estimator_state c) {
  return vplkit_estimate_clamp_compensation_finish(c, vr_params.clamp_dirs);
}

// All of the compensation at pixel p, in one dispatch (ris's reuse rounds, whose units are rounds
// and not split): 0 at an invalid gather point.
vec3 vr_clamp_compensation_whole(uint p, vplkit_gather_point gp, bool valid) {
  if (!valid) return vec3(0.0);
  vplkit_estimator_state c =
      vplkit_make_estimator_state(vplkit_clamp_compensation_stream(vplkit_make_counter_rng(vr_params.seed, p)));
  vr_clamp_compensation_dirs(gp, c, 0, vr_params.clamp_dirs);
  return vr_finish_clamp_compensation(c);
}
#endif

#endif  // VPLRENDER_ESTIMATE_CLAMP_COMPENSATION_GLSL
