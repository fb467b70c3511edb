// SPDX-License-Identifier: MIT
// vplrender's kernel of --method local, one invocation per pixel: rounds of one draw from each of
// the D region mixtures (vplkit_estimate_local_range, combined by VR_LOCAL_COMBINATION). The host
// puts "#version 430" first and the variant's defines (estimate_params.h) in the preamble. With
// VR_CLAMP_COMPENSATION the clamp's compensation follows the rounds (estimate_clamp_compensation.glsl).
#include "estimate_visibility.glsl"
#include "estimate_distributions.glsl"
#include "estimate_clamp_compensation.glsl"
#include "vplkit/estimators/local_estimator.glsl"

void main() {
  uint p = vr_pixel();
  if (!vr_in_image(p)) return;
  vplkit_gather_point gp = vplkit_load_gather_point(int(p));
  bool valid = vplkit_gather_point_valid(gp);
  vplkit_estimator_state est = vr_begin_estimate(p);
#ifdef VR_CLAMP_COMPENSATION
  vplkit_estimator_state clamp_comp = vr_begin_clamp_compensation(p);
  if (valid) vr_clamp_compensation_range(gp, clamp_comp);
#endif
#if VR_SAMPLER == VR_SAMPLER_SHARE_TREE
  // A round draws once from each region's mixture: round r's first draw is r D.
  if (valid) vr_begin_share_tree_stream(est.rng, vr_begin() * int(vr_params.n_distributions));
#endif
  if (valid)
    vplkit_estimate_local_range(gp, vr_view(), 0u, vr_params.n_distributions, est, vr_begin(), vr_end(),
                                vr_make_visibility(vr_grid()), vr_params.dmin, VR_LOCAL_COMBINATION, VR_VPL_MODE,
                                vr_params.depth_tolerance);
  vr_keep_estimate(p, est);
#ifdef VR_CLAMP_COMPENSATION
  vr_keep_clamp_compensation(p, clamp_comp);
  if (vr_last_pass())
    vr_write_estimate(p, gp, valid,
                      vplkit_estimate_local_finish(est, vr_params.n_samples) + vr_finish_clamp_compensation(p, clamp_comp));
#else
  if (vr_last_pass()) vr_write_estimate(p, gp, valid, vplkit_estimate_local_finish(est, vr_params.n_samples));
#endif
}
