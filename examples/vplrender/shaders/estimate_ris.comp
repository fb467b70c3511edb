// SPDX-License-Identifier: MIT
// vplrender's kernel of --method ris (docs/math.md, "RIS"; render/cpu/ris_render.hpp is the CPU
// twin), one invocation per pixel, in the pass of VR_RIS_PASS (estimate_ris_params.h). The host
// puts "#version 430" first and the variant's defines (estimate_params.h, estimate_ris_params.h)
// in the preamble.
//
// Why it is laid out this way (reasoned for a GPU with warps of 32, not measured on llvmpipe):
//  - The M candidates of a reservoir stream through registers (vplkit_ris_resample keeps one
//    weighted reservoir and the kept sample): per candidate a CDF draw and an unshadowed
//    contribution, no storage traffic; only the kept sample pays a visibility query, so the
//    divergent, memory-bound part (the ray march) runs once per sample whatever M is.
//  - The reservoir record (vplkit_ris_reservoir_record, ris_params.h) is 32 bytes at a 32-byte
//    stride: the compiler may load or store it as two 16-byte vectors, and the 64 invocations of a
//    group (consecutive pixels) touch 2 KiB contiguous, so a warp's accesses coalesce into full
//    cache lines whatever the compiler does. It is written once per round and read by the reuse
//    pass: the only storage round trip RIS adds besides the split state (sum and stream, 48 bytes).
//  - The reuse pass reads the G-buffer and the reservoirs, nothing else per neighbour: no
//    candidate is redrawn, no ray is traced for a neighbour (the target has no visibility). The
//    neighbours of nearby pixels overlap, so their loads hit the caches. It holds K pixel indices
//    and K + 1 numbers in registers (ris_spatial_reuse.glsl); VPLKIT_RIS_MAX_NEIGHBOURS bounds them.
#include "estimate_ris_params.h"
#ifndef VR_RIS_PER_REGION
#define VR_ONE_MIXTURE
#endif
#include "estimate_visibility.glsl"
#include "estimate_distributions.glsl"
#include "estimate_ris_source.glsl"
#include "vplkit/estimators/ris_estimator.glsl"
#include "vplkit/estimators/ris_params.h"
#include "estimate_clamp_compensation.glsl"
#if VR_RIS_PASS == VR_RIS_PASS_REUSE
#include "vplkit/estimators/ris_spatial_reuse.glsl"
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
#endif

void main() {
  uint p = vr_pixel();
  if (!vr_in_image(p)) return;
  vplkit_gather_point gp = vplkit_load_gather_point(int(p));
  bool valid = vplkit_gather_point_valid(gp);
  vplkit_estimator_state est = vr_begin_estimate(p);
  if (valid) vr_load_mixtures();
#if VR_RIS_PASS == VR_RIS_PASS_ESTIMATE
#ifdef VR_CLAMP_COMPENSATION
  // The compensation's directions follow the samples as units (estimate_clamp_compensation.glsl).
  vplkit_estimator_state clamp_comp = vr_begin_clamp_compensation(p);
#endif
  if (valid) {
    vplkit_estimate_ris_range(gp, vr_view(), vr_ris_distribution(p), est, vr_begin(), vr_end(),
                              vr_params.ris.candidates, vr_make_visibility(vr_grid()), vr_params.dmin, VR_VPL_MODE,
                              vr_params.depth_tolerance);
#ifdef VR_CLAMP_COMPENSATION
    vr_clamp_compensation_range(gp, clamp_comp);
#endif
  }
  vr_keep_estimate(p, est);
#ifdef VR_CLAMP_COMPENSATION
  vr_keep_clamp_compensation(p, clamp_comp);
  if (vr_last_pass())
    vr_write_estimate(p, gp, valid,
                      vplkit_estimate_ris_finish(est, vr_params.n_samples) + vr_finish_clamp_compensation(p, clamp_comp));
#else
  if (vr_last_pass()) vr_write_estimate(p, gp, valid, vplkit_estimate_ris_finish(est, vr_params.n_samples));
#endif
#elif VR_RIS_PASS == VR_RIS_PASS_CANDIDATES
  // An invalid pixel's record is the empty reservoir (the CPU leaves its initial empty record):
  // the buffer is not cleared between frames, and a neighbour's test rejects the pixel anyway.
  vplkit_ris_reservoir r = vplkit_make_ris_reservoir();
  if (valid)
    r = vplkit_ris_resample(gp, vr_view(), vr_ris_distribution(p), est.rng, vr_params.ris.candidates, vr_params.dmin,
                            VR_VPL_MODE, vr_params.depth_tolerance);
  vr_reservoirs[p] = vplkit_make_ris_reservoir_record(r);
  vr_keep_estimate(p, est);
#else
  if (valid) {
    vplkit_ris_spatial_settings settings =
        vplkit_ris_spatial_settings(vr_params.ris.neighbours, vr_params.ris.radius, vr_params.ris.min_normal_cos,
                                    vr_params.ris.max_plane_slope, vr_params.ris.mis);
    vplkit_ris_reservoir r = vplkit_ris_spatial_reuse(gp, int(p), vr_params.width, vr_params.height, vr_view(),
                                                      vplkit_load_ris_reservoir(int(p)), settings, est.rng,
                                                      vr_params.dmin, VR_VPL_MODE, vr_params.depth_tolerance);
    est.sum += vplkit_ris_shade(gp, vr_view(), r, vr_make_visibility(vr_grid()), vr_params.dmin, VR_VPL_MODE,
                                vr_params.depth_tolerance);
  }
  vr_keep_estimate(p, est);
#ifdef VR_CLAMP_COMPENSATION
  // The rounds are the units here, so the last round's reuse adds the whole compensation.
  if (vr_last_pass())
    vr_write_estimate(p, gp, valid,
                      vplkit_estimate_ris_finish(est, vr_params.n_samples) + vr_clamp_compensation_whole(p, gp, valid));
#else
  if (vr_last_pass()) vr_write_estimate(p, gp, valid, vplkit_estimate_ris_finish(est, vr_params.n_samples));
#endif
#endif
}
