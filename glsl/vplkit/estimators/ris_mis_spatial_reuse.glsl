// SPDX-License-Identifier: MIT
// vplkit GLSL pack: unbiased spatial reuse for resampled VPL sampling with gathering (docs/math.md,
// "Spatial reuse with gathering"); mirrors include/vplkit/estimators/ris_mis_spatial_reuse.hpp
// (T = float): ris_spatial_reuse.glsl's generalized RIS with the target lum(h_g) of
// ris_mis_estimator.glsl at each pixel g, with the pmf of g's own candidate distribution. Random
// numbers as vplkit_ris_spatial_reuse. Include this file instead of (or before) ris_spatial_reuse.glsl:
// it compiles that file's ris-mis target in (VPLKIT_RIS_MIS_REUSE).
// ACCESSORS: those of ris_spatial_reuse.glsl, and vplkit_ris_reuse_distribution(pixel) (the id of
// the pixel's candidate distribution for the hooks of mis_estimator.glsl, which it also needs).
#ifndef VPLKIT_ESTIMATORS_RIS_MIS_SPATIAL_REUSE_GLSL
#define VPLKIT_ESTIMATORS_RIS_MIS_SPATIAL_REUSE_GLSL

#if defined(VPLKIT_ESTIMATORS_RIS_SPATIAL_REUSE_GLSL) && !defined(VPLKIT_RIS_MIS_REUSE)
#error "ris_mis_spatial_reuse.glsl: include it before ris_spatial_reuse.glsl (or define VPLKIT_RIS_MIS_REUSE first)"
#endif
#ifndef VPLKIT_RIS_MIS_REUSE
#define VPLKIT_RIS_MIS_REUSE
#endif
#include "vplkit/estimators/ris_mis_estimator.glsl"
#include "vplkit/estimators/ris_spatial_reuse.glsl"

// Combines pixel `pixel`'s canonical reservoir (vplkit_ris_mis_resample with the pixel's
// distribution) with up to settings.neighbours neighbours' by the target lum(h); shade the result
// with vplkit_ris_mis_shade and the pixel's distribution.
vplkit_ris_reservoir vplkit_ris_mis_spatial_reuse(vplkit_gather_point gp, int pixel, int width, int height,
                                                  vplkit_dprsm_view view, vplkit_ris_reservoir canonical,
                                                  vplkit_ris_spatial_settings settings, inout vplkit_counter_rng rng,
                                                  float n1, float n2, int vpl_mode, float depth_tolerance) {
  return vplkit_ris_spatial_reuse_with(gp, pixel, width, height, canonical, settings, rng,
                                       vplkit_make_ris_mis_target(view, n1, n2, vpl_mode, depth_tolerance));
}

#endif  // VPLKIT_ESTIMATORS_RIS_MIS_SPATIAL_REUSE_GLSL
