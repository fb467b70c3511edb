// SPDX-License-Identifier: MIT
// vplrender's kernel of --method mis and mis-as-published (VR_VARIANT: the vplkit_mis_* mode), one
// invocation per pixel: --dirs gathering rays and --vpls draws from the one mixture, combined by
// the balance heuristic (vplkit_estimate_mis_range). The host puts "#version 430" first and the
// variant's defines (estimate_params.h) in the preamble.
#define VR_ONE_MIXTURE
#include "estimate_visibility.glsl"
#include "estimate_distributions.glsl"
#include "vplkit/estimators/mis_estimator.glsl"

void main() {
  uint p = vr_pixel();
  if (!vr_in_image(p)) return;
  vplkit_gather_point gp = vplkit_load_gather_point(int(p));
  bool valid = vplkit_gather_point_valid(gp);
  vplkit_estimator_state est = vr_begin_estimate(p);
  if (valid) {
    vr_load_mixtures();
#if VR_SAMPLER == VR_SAMPLER_SHARE_TREE
    // Step j draws VPL j while j < n_vpls (the gathering hits only evaluate pmfs): a dispatch's first
    // draw is min(begin, n_vpls).
    vr_begin_share_tree_stream(est.rng, min(vr_begin(), vr_params.n_vpls));
#endif
    vplkit_voxel_grid grid = vr_grid();
    vplkit_estimate_mis_range(gp, vr_view(), 0u, est, vr_begin(), vr_end(), vr_params.n_dirs, vr_params.n_vpls,
                              vr_make_tracer(grid), vr_make_visibility(grid), vr_params.depth_tolerance, VR_VARIANT,
                              VR_VPL_MODE);
  }
  vr_keep_estimate(p, est);
  if (vr_last_pass())
    vr_write_estimate(p, gp, valid, vplkit_estimate_mis_finish(est, vr_params.n_dirs, vr_params.n_vpls, VR_VARIANT));
}
