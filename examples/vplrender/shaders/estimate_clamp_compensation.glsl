// SPDX-License-Identifier: MIT
// vplrender's estimate kernels with VR_CLAMP_COMPENSATION (--clamp-compensation on; reference,
// global, gbg, local, ris): what the VPL clamp max(d^2, dmin^2) removed, added back to the pixel's
// estimate (docs/math.md, "The clamp's compensation"; vplkit_estimate_clamp_compensation), as the
// CPU backend adds it: clamp_dirs cosine directions per gather point from the pixel's
// vplkit_clamp_compensation_stream, traced by vr_make_tracer (the gathering rays' visibility and
// lit test), the estimate's VR_VPL_MODE, dmin and depth tolerance; finished, then added to the
// finished estimate. Two forms, the same numbers (docs/renderer.md, "The clamp compensation's
// passes"):
//  - VR_CLAMP_COMPENSATION_PASS defined (--clamp-compensation-pass compacted, the default): the
//    passes of clamp_compensation.comp computed the term before the estimate kernel, only at the
//    pixels whose near-surface test says a surface may lie within dmin, and left it in vr_out[p];
//    the estimate kernel adds that and writes the estimate over it.
//  - else (inline): the directions are the kernel's units [clamp_first_unit, clamp_first_unit +
//    clamp_dirs) after the estimator's, so a split render (VR_SPLIT 1) cuts them with the same
//    [begin, end) and keeps their state between dispatches in the lanes of vr_pixel_state the
//    estimators leave free (estimate_params.h).
// Without VR_CLAMP_COMPENSATION this file adds nothing but vr_clamp_compensation_may_add.
// Included after estimate_visibility.glsl (its tracer and accessors; with exact rays also the
// triangle voxel lists and their near-surface test).
#ifndef VPLRENDER_ESTIMATE_CLAMP_COMPENSATION_GLSL
#define VPLRENDER_ESTIMATE_CLAMP_COMPENSATION_GLSL

#include "estimate_visibility.glsl"
#include "vplkit/estimators/clamp_compensation.glsl"

#ifdef VR_CLAMP_COMPENSATION
// May a direction at gp (a valid gather point) add anything: false only where the near-surface
// test says every surface within dmin lies in a plane through gp (vplkit_clamp_compensation_may_add
// with the tracer's answer). The BVH tracer answers vplkit_voxel_tracer_surface_within with true (it
// cannot say), so with exact rays the triangle voxel grid answers (the same triangles), as the CPU
// backend's exact tracer asks it. One test per pixel and frame: the mark pass of
// clamp_compensation.comp runs it (compacted), or the estimate kernel (inline).
bool vr_clamp_compensation_may_add(vplkit_gather_point gp) {
#if VR_VISIBILITY == VR_VISIBILITY_EXACT
  return vr_params.dmin * vr_params.dmin > 0.0 &&
         vplkit_triangle_voxel_surface_within(vr_grid(), gp.position, abs(vr_params.dmin),
                                              vplkit_vpl_coincidence_tolerance(gp.position, gp.position) / 4.0);
#else
  return vplkit_clamp_compensation_may_add(vr_make_tracer(vr_grid()), gp, vr_params.dmin);
#endif
}

// Directions [begin, end) of the compensation at gp (a valid gather point whose test said maybe).
void vr_clamp_compensation_trace(vplkit_gather_point gp, inout vplkit_estimator_state c, int begin, int end) {
  vplkit_estimate_clamp_compensation_range(gp, vr_view(), c, begin, end, vr_make_tracer(vr_grid()), vr_params.dmin,
                                           vr_params.depth_tolerance, VR_VPL_MODE);
}

// What the last direction leaves: the term added to the finished estimate. `precise`, so that a
// compiler cannot fuse its division (a multiplication by 1 / n) into the caller's addition, which
// it could inline but not after the term went through the compacted passes' buffer: both forms
// round the term alone, and give the same image bit for bit.
vec3 vr_clamp_compensation_term(vplkit_estimator_state c) {
  precise vec3 term = vplkit_estimate_clamp_compensation_finish(c, vr_params.clamp_dirs);
  return term;
}

#ifdef VR_CLAMP_COMPENSATION_PASS
// The terms of clamp_compensation.comp's passes are in vr_out, one per pixel (0 where the test said
// no), until the last pass of the estimate writes the estimate over them (estimate_io.glsl).
// The estimate kernel carries no state of the compensation: these keep the inline form's call sites.
vplkit_estimator_state vr_begin_clamp_compensation(uint p) {
  return vplkit_make_estimator_state(vplkit_counter_rng(0u, 0u));
}
void vr_clamp_compensation_range(vplkit_gather_point gp, inout vplkit_estimator_state c) {}
void vr_keep_clamp_compensation(uint p, vplkit_estimator_state c) {}
vec3 vr_finish_clamp_compensation(uint p, vplkit_estimator_state c) { return vr_out[p].xyz; }
vec3 vr_clamp_compensation_whole(uint p, vplkit_gather_point gp, bool valid) { return valid ? vr_out[p].xyz : vec3(0.0); }
#else
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

// Directions [begin, end) of the compensation at gp (a valid gather point): none where the
// near-surface test says no, the numbers they would draw skipped.
void vr_clamp_compensation_dirs(vplkit_gather_point gp, inout vplkit_estimator_state c, int begin, int end) {
  if (!(begin < end)) return;
#if VR_VISIBILITY == VR_VISIBILITY_EXACT
  if (!vr_clamp_compensation_may_add(gp)) {
    c.rng.counter += 2u * uint(end - begin);
    return;
  }
#endif
  // (the other kinds' tracers answer the test inside vplkit_estimate_clamp_compensation_range)
  vr_clamp_compensation_trace(gp, c, begin, end);
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
vec3 vr_finish_clamp_compensation(uint p, vplkit_estimator_state c) { return vr_clamp_compensation_term(c); }

// All of the compensation at pixel p, in one dispatch (ris's reuse rounds, whose units are rounds
// and not split): 0 at an invalid gather point.
vec3 vr_clamp_compensation_whole(uint p, vplkit_gather_point gp, bool valid) {
  if (!valid) return vec3(0.0);
  vplkit_estimator_state c =
      vplkit_make_estimator_state(vplkit_clamp_compensation_stream(vplkit_make_counter_rng(vr_params.seed, p)));
  vr_clamp_compensation_dirs(gp, c, 0, vr_params.clamp_dirs);
  return vr_clamp_compensation_term(c);
}
#endif  // VR_CLAMP_COMPENSATION_PASS
#endif

#endif  // VPLRENDER_ESTIMATE_CLAMP_COMPENSATION_GLSL
