// SPDX-License-Identifier: MIT
// vplrender's kernel of the VPL-sampling methods (global, gbg: render/method_traits.cpp), one
// invocation per pixel: --vpls draws from the one mixture (vplkit_estimate_vpl_sampling_range,
// docs/math.md section 3), each a VPL's contribution times one visibility query. The host puts
// "#version 430" first and the variant's defines (estimate_params.h) in the preamble. With
// VR_CLAMP_COMPENSATION the clamp's compensation follows the samples (estimate_clamp_compensation.glsl).
// With VR_SAMPLER_SHARE_TREE the tree stream starts at this dispatch's first sample
// (estimate_distributions.glsl).
#define VR_ONE_MIXTURE
#include "estimate_visibility.glsl"
#include "estimate_distributions.glsl"
#include "estimate_clamp_compensation.glsl"
#include "vplkit/estimators/vpl_sampling_estimator.glsl"

void main() {
  uint p = vr_pixel();
  if (!vr_in_image(p)) return;
  vplkit_gather_point gp = vplkit_load_gather_point(int(p));
  bool valid = vplkit_gather_point_valid(gp);
  vplkit_estimator_state est = vr_begin_estimate(p);
#ifdef VR_CLAMP_COMPENSATION
  vplkit_estimator_state clamp_comp = vr_begin_clamp_compensation(p);
#endif
  if (valid) {
    vr_load_mixtures();
#if VR_SAMPLER == VR_SAMPLER_SHARE_TREE
    vr_begin_share_tree_stream(est.rng, vr_begin());
#endif
    vplkit_estimate_vpl_sampling_range(gp, vr_view(), 0u, est, vr_begin(), vr_end(), vr_make_visibility(vr_grid()),
                                       vr_params.dmin, VR_VPL_MODE, vr_params.depth_tolerance);
#ifdef VR_CLAMP_COMPENSATION
    vr_clamp_compensation_range(gp, clamp_comp);
#endif
  }
  vr_keep_estimate(p, est);
#ifdef VR_CLAMP_COMPENSATION
  vr_keep_clamp_compensation(p, clamp_comp);
  if (vr_last_pass())
    vr_write_estimate(p, gp, valid,
                      vplkit_estimate_vpl_sampling_finish(est, vr_params.n_samples) + vr_finish_clamp_compensation(p, clamp_comp));
#else
  if (vr_last_pass()) vr_write_estimate(p, gp, valid, vplkit_estimate_vpl_sampling_finish(est, vr_params.n_samples));
#endif
}
