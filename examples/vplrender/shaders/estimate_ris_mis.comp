// SPDX-License-Identifier: MIT
// vplrender's kernel of --method ris-mis (vplkit/estimators/ris_mis_estimator.glsl; docs/math.md,
// "RIS with gathering"), one invocation per pixel: --dirs gathering rays and --vpls RIS samples of
// --candidates candidates from the candidate source, balanced as --method mis balances its VPL
// draws (vplkit_estimate_ris_mis_range). Its steps are the units (a step: one RIS sample and one
// direction, as mis's); they split over dispatches like mis's (VR_SPLIT). Unclamped: no clamp
// compensation. With --spatial K > 0 (VR_RIS_PASS, estimate_ris_params.h) the steps are rounds of
// two dispatches, in the order of render/cpu/ris_render.hpp's render_ris_mis_cpu: the candidate
// pass writes each pixel's reservoir (if the round is below n2), the reuse pass combines it with K
// neighbours' (vplkit_ris_mis_spatial_reuse: each pixel's target with its own distribution's pmf),
// shades it and traces the round's gathering direction (if below n1); the round is vr_params.begin.
// The host puts "#version 430" first and the variant's defines (estimate_params.h,
// estimate_ris_params.h) in the preamble.
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
#include "vplkit/estimators/ris_params.h"
#if VR_RIS_PASS == VR_RIS_PASS_REUSE
#include "vplkit/estimators/ris_mis_spatial_reuse.glsl"
#endif
#ifdef VR_RIS_POOL
#include "vplkit/estimators/ris_candidate_pool.glsl"
#include "vplkit/estimators/ris_pool_params.h"
#endif

#if VR_RIS_PASS == VR_RIS_PASS_CANDIDATES
layout(std430, binding = VR_RIS_BINDING_RESERVOIRS) restrict writeonly buffer VrRisReservoirs {
  vplkit_ris_reservoir_record vr_reservoirs[];
};
#elif VR_RIS_PASS == VR_RIS_PASS_REUSE
layout(std430, binding = VR_RIS_BINDING_RESERVOIRS) restrict readonly buffer VrRisReservoirs {
  vplkit_ris_reservoir_record vr_reservoirs[];
};
vplkit_ris_reservoir vplkit_load_ris_reservoir(int pixel) {
  vplkit_ris_reservoir_record r = vr_reservoirs[pixel];  // a local copy: see vr_unpack_mixture
  return vplkit_ris_reservoir_from_record(r);
}
// A neighbour's target uses its own candidate distribution (its region's for local).
uint vplkit_ris_reuse_distribution(int pixel) { return vr_ris_distribution(uint(pixel)); }
#endif

#ifdef VR_RIS_POOL
// --candidate-pool: vr_params.ris.pool_size entries per candidate distribution (one pool, or one per
// region with VR_RIS_PER_REGION), written by the pool pass, read by every other pass.
#if VR_RIS_PASS == VR_RIS_PASS_POOL
layout(std430, binding = VR_RIS_BINDING_POOL) restrict buffer VrRisPool { vplkit_ris_pool_record vr_pool[]; };
#else
layout(std430, binding = VR_RIS_BINDING_POOL) restrict readonly buffer VrRisPool { vplkit_ris_pool_record vr_pool[]; };
#endif
vplkit_ris_pool_entry vplkit_load_ris_pool_entry(uint pool, uint index) {
  vplkit_ris_pool_record r = vr_pool[pool * vr_params.ris.pool_size + index];  // a local copy: see vr_unpack_mixture
  return vplkit_ris_pool_entry_from_record(r);
}
uint vr_ris_pools() {
#ifdef VR_RIS_PER_REGION
  return uint(vr_params.ris.regions_x * vr_params.ris.regions_y);
#else
  return 1u;
#endif
}
#endif

void main() {
#if VR_RIS_PASS == VR_RIS_PASS_POOL
  // One invocation per entry: entry i of the pools laid end to end, of distribution i / pool_size,
  // from the stream (pool_seed, i) as render/cpu/ris_render.hpp's fill_ris_candidate_pool.
  uint i = vr_pixel();
  if (i >= vr_ris_pools() * vr_params.ris.pool_size) return;
  vr_load_mixtures();
  vr_pool[i] = vplkit_make_ris_pool_record(vplkit_ris_pool_draw_entry(
      vr_view(), i / vr_params.ris.pool_size, vr_params.ris.pool_seed, i, VR_VPL_MODE, vr_params.depth_tolerance));
#else
  uint p = vr_pixel();
  if (!vr_in_image(p)) return;
  vplkit_gather_point gp = vplkit_load_gather_point(int(p));
  bool valid = vplkit_gather_point_valid(gp);
  vplkit_estimator_state est = vr_begin_estimate(p);
  if (valid) vr_load_mixtures();
#if VR_RIS_PASS == VR_RIS_PASS_ESTIMATE
  if (valid) {
    vplkit_voxel_grid grid = vr_grid();
#ifdef VR_RIS_POOL
    uint d = vr_ris_distribution(p);
    vplkit_estimate_ris_mis_pooled_range(gp, vr_view(), d, d, vr_params.ris.pool_size, est, vr_begin(), vr_end(),
                                         vr_params.n_dirs, vr_params.n_vpls, vr_params.ris.candidates,
                                         vr_make_tracer(grid), vr_make_visibility(grid), vr_params.depth_tolerance,
                                         VR_VPL_MODE);
#else
    vplkit_estimate_ris_mis_range(gp, vr_view(), vr_ris_distribution(p), est, vr_begin(), vr_end(), vr_params.n_dirs,
                                  vr_params.n_vpls, vr_params.ris.candidates, vr_make_tracer(grid),
                                  vr_make_visibility(grid), vr_params.depth_tolerance, VR_VPL_MODE);
#endif
  }
  vr_keep_estimate(p, est);
  if (vr_last_pass()) vr_write_estimate(p, gp, valid, vplkit_estimate_ris_mis_finish(est));
#else
  // The round's counts, as vplkit_estimate_ris_mis_range normalises them.
  int round = vr_begin();
  int n_dirs = max(vr_params.n_dirs, 0);
  int n_ris = vr_params.ris.candidates > 0 ? max(vr_params.n_vpls, 0) : 0;
  float n1 = float(n_dirs), n2 = vplkit_ris_mis_vpl_samples(n_ris, vr_params.ris.candidates);
#if VR_RIS_PASS == VR_RIS_PASS_CANDIDATES
  // An invalid pixel's record is the empty reservoir (as on the CPU; see estimate_ris.comp).
  vplkit_ris_reservoir r = vplkit_make_ris_reservoir();
  if (valid && round < n_ris) {
#ifdef VR_RIS_POOL
    vplkit_ris_mis_kept kept;
    r = vplkit_ris_mis_resample_pooled(gp, vr_ris_distribution(p), vr_params.ris.pool_size, est.rng,
                                       vr_params.ris.candidates, n1, n2, kept);
#else
    r = vplkit_ris_mis_resample(gp, vr_view(), vr_ris_distribution(p), est.rng, vr_params.ris.candidates, n1, n2,
                                VR_VPL_MODE, vr_params.depth_tolerance);
#endif
  }
  vr_reservoirs[p] = vplkit_make_ris_reservoir_record(r);
  vr_keep_estimate(p, est);
#else
  if (valid) {
    vplkit_voxel_grid grid = vr_grid();
    uint d = vr_ris_distribution(p);
    if (round < n_ris) {
      vplkit_ris_spatial_settings settings =
          vplkit_ris_spatial_settings(vr_params.ris.neighbours, vr_params.ris.radius, vr_params.ris.min_normal_cos,
                                      vr_params.ris.max_plane_slope, vr_params.ris.mis);
      vplkit_ris_reservoir r = vplkit_ris_mis_spatial_reuse(gp, int(p), vr_params.width, vr_params.height, vr_view(),
                                                            vplkit_load_ris_reservoir(int(p)), settings, est.rng, n1,
                                                            n2, VR_VPL_MODE, vr_params.depth_tolerance);
      est.sum += vplkit_ris_mis_shade(gp, vr_view(), d, r, vr_make_visibility(grid), n1, n2, VR_VPL_MODE,
                                      vr_params.depth_tolerance) / float(n_ris);
    }
    if (round < n_dirs) {
      float u0 = vplkit_rng_next_unit(est.rng);
      float u1 = vplkit_rng_next_unit(est.rng);
      vplkit_orthonormal_basis frame = vplkit_make_orthonormal_basis(vplkit_gather_point_shading_normal(gp));
      est.sum += vplkit_mis_gathering_sample(gp, vr_view(), d, frame, vplkit_sample_cosine_hemisphere(vec2(u0, u1)),
                                             vr_make_tracer(grid), vr_params.depth_tolerance, n1, n2,
                                             vplkit_mis_solid_angle, VR_VPL_MODE);
    }
  }
  vr_keep_estimate(p, est);
  if (vr_last_pass()) vr_write_estimate(p, gp, valid, vplkit_estimate_ris_mis_finish(est));
#endif
#endif
#endif
}
