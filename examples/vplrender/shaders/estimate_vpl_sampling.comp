// SPDX-License-Identifier: MIT
// vplrender's kernel of the VPL-sampling methods (global, gbg: render/method_traits.cpp), one
// invocation per pixel: --vpls draws from the one mixture (vplkit_estimate_vpl_sampling_range,
// docs/math.md section 3), each a VPL's contribution times one visibility query. The host puts
// "#version 430" first and the variant's defines (estimate_params.h) in the preamble.
#define VR_ONE_MIXTURE
#include "estimate_visibility.glsl"
#include "estimate_distributions.glsl"
#include "vplkit/estimators/vpl_sampling_estimator.glsl"

void main() {
  uint p = vr_pixel();
  if (!vr_in_image(p)) return;
  vplkit_gather_point gp = vplkit_load_gather_point(int(p));
  bool valid = vplkit_gather_point_valid(gp);
  vplkit_estimator_state est = vr_begin_estimate(p);
  if (valid) {
    vr_load_mixtures();
    vplkit_estimate_vpl_sampling_range(gp, vr_view(), 0u, est, vr_begin(), vr_end(), vr_make_visibility(vr_grid()),
                                       vr_params.dmin, VR_VPL_MODE, vr_params.depth_tolerance);
  }
  vr_keep_estimate(p, est);
  if (vr_last_pass()) vr_write_estimate(p, gp, valid, vplkit_estimate_vpl_sampling_finish(est, vr_params.n_samples));
}
