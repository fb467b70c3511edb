// SPDX-License-Identifier: MIT
// vplrender's kernel of --method gather, one invocation per pixel: --dirs cosine-distributed
// gathering rays through the variant's tracer, each hit looked up in the DPRSM
// (vplkit_estimate_gathering_range). No distribution. The host puts "#version 430" first and the
// variant's defines (estimate_params.h) in the preamble.
#include "estimate_visibility.glsl"
#include "vplkit/estimators/gathering_estimator.glsl"

void main() {
  uint p = vr_pixel();
  if (!vr_in_image(p)) return;
  vplkit_gather_point gp = vplkit_load_gather_point(int(p));
  bool valid = vplkit_gather_point_valid(gp);
  vplkit_estimator_state est = vr_begin_estimate(p);
  if (valid)
    vplkit_estimate_gathering_range(gp, vr_view(), est, vr_begin(), vr_end(), vr_make_tracer(vr_grid()),
                                    vr_params.depth_tolerance);
  vr_keep_estimate(p, est);
  if (vr_last_pass()) vr_write_estimate(p, gp, valid, vplkit_estimate_gathering_finish(est, vr_params.n_dirs));
}
