// SPDX-License-Identifier: MIT
// vplrender's kernel of --method reference, one invocation per pixel: the exhaustive VPL sum over
// every DPRSM texel with visibility, in compensated float (vplkit_exhaustive_vpl_sum_range; with
// VR_VPL_MODE patch vplkit_exhaustive_vpl_patch_sum_range, strata x strata jittered points per
// texel read from the pixel's stream at fixed counters, so every pass starts from the fresh stream).
// The host puts "#version 430" first and the variant's defines (estimate_params.h) in the preamble.
// With VR_CLAMP_COMPENSATION the clamp's compensation follows the texels (estimate_clamp_compensation.glsl).
#include "estimate_visibility.glsl"
#include "estimate_clamp_compensation.glsl"

void main() {
  uint p = vr_pixel();
  if (!vr_in_image(p)) return;
  vplkit_gather_point gp = vplkit_load_gather_point(int(p));
  bool valid = vplkit_gather_point_valid(gp);
  vplkit_vpl_sum_state sum = vr_begin_sum(p);
#ifdef VR_CLAMP_COMPENSATION
  vplkit_estimator_state clamp_comp = vr_begin_clamp_compensation(p);
  if (valid) vr_clamp_compensation_range(gp, clamp_comp);
#endif
  if (valid) {
#if VR_VPL_MODE == 1
    vplkit_exhaustive_vpl_patch_sum_range(gp, vr_view(), sum, vr_begin(), vr_end(),
                                          vplkit_make_counter_rng(vr_params.seed, p), vr_params.strata,
                                          vr_make_visibility(vr_grid()), vr_params.dmin, vr_params.depth_tolerance);
#else
    vplkit_exhaustive_vpl_sum_range(gp, vr_view(), sum, vr_begin(), vr_end(), vr_make_visibility(vr_grid()),
                                    vr_params.dmin);
#endif
  }
  vr_keep_sum(p, sum);
#ifdef VR_CLAMP_COMPENSATION
  vr_keep_clamp_compensation(p, clamp_comp);
#if VR_VPL_MODE == 1
  if (vr_last_pass())
    vr_write_estimate(p, gp, valid,
                      vplkit_exhaustive_vpl_patch_sum_finish(sum, vr_params.strata) + vr_finish_clamp_compensation(p, clamp_comp));
#else
  if (vr_last_pass())
    vr_write_estimate(p, gp, valid, vplkit_exhaustive_vpl_sum_finish(sum) + vr_finish_clamp_compensation(p, clamp_comp));
#endif
#else
#if VR_VPL_MODE == 1
  if (vr_last_pass()) vr_write_estimate(p, gp, valid, vplkit_exhaustive_vpl_patch_sum_finish(sum, vr_params.strata));
#else
  if (vr_last_pass()) vr_write_estimate(p, gp, valid, vplkit_exhaustive_vpl_sum_finish(sum));
#endif
#endif
}
