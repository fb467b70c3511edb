// SPDX-License-Identifier: MIT
// vplrender's kernel of --method ris-mis (vplkit/estimators/ris_mis_estimator.glsl; docs/math.md,
// "RIS with gathering"), one invocation per pixel: --dirs gathering rays and --vpls RIS samples of
// --candidates candidates from the candidate source, balanced as --method mis balances its VPL
// draws (vplkit_estimate_ris_mis_range). Its steps are the units (a step: one RIS sample and one
// direction, as mis's); they split over dispatches like mis's (VR_SPLIT). Unclamped: no clamp
// compensation, and no spatial reuse (the backend refuses --spatial). The host puts "#version 430"
// first and the variant's defines (estimate_params.h, estimate_ris_params.h) in the preamble.
//
// Why a kernel of its own, and not a switch in estimate_ris.comp (reasoned for NVIDIA Hopper, warps
// of 32, not measured on llvmpipe): a GPU allocates a kernel's registers for the largest set of
// values live at any point of the whole program, and occupancy follows (65536 registers per SM and
// at most 2048 resident threads: 32 registers per thread keep every warp slot, 64 half of them; a
// kernel past its limit spills to local memory). A uniform switch would compile both estimators
// into one program; a define in estimate_ris.comp would only keep its passes, reservoir buffer and
// clamp compensation out of the way with more #if branches. Here the program is estimate_mis.comp's
// with the VPL draw replaced by a reservoir: per step the candidate loop holds the weighted
// reservoir (sum, kept weight) and the kept sample (texel, jitter, target), then the kept sample's
// visibility march, then the direction's march and DPRSM lookup. Those live ranges follow one
// another, so the peak is the larger of a march and the candidate loop on top of the pixel's
// constants (gather point, frame, mixture, n1, n2, stream, sum): the register budget of mis's
// kernel, not the sum of ris's and gathering's. M is uniform over a warp, so the candidate loop's
// trip count is too; the divergent, memory-bound parts are the two marches per step, as in mis.
#include "estimate_ris_params.h"
#ifndef VR_RIS_PER_REGION
#define VR_ONE_MIXTURE
#endif
#include "estimate_visibility.glsl"
#include "estimate_distributions.glsl"
#include "estimate_ris_source.glsl"
#include "vplkit/estimators/ris_mis_estimator.glsl"

void main() {
  uint p = vr_pixel();
  if (!vr_in_image(p)) return;
  vplkit_gather_point gp = vplkit_load_gather_point(int(p));
  bool valid = vplkit_gather_point_valid(gp);
  vplkit_estimator_state est = vr_begin_estimate(p);
  if (valid) {
    vr_load_mixtures();
    vplkit_voxel_grid grid = vr_grid();
    vplkit_estimate_ris_mis_range(gp, vr_view(), vr_ris_distribution(p), est, vr_begin(), vr_end(), vr_params.n_dirs,
                                  vr_params.n_vpls, vr_ris.candidates, vr_make_tracer(grid), vr_make_visibility(grid),
                                  vr_params.depth_tolerance, VR_VPL_MODE);
  }
  vr_keep_estimate(p, est);
  if (vr_last_pass()) vr_write_estimate(p, gp, valid, vplkit_estimate_ris_mis_finish(est));
}
