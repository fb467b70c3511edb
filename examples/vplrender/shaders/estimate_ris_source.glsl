// SPDX-License-Identifier: MIT
// vplrender's RIS kernels (estimate_ris.comp, estimate_ris_mis.comp): the distribution a pixel's
// candidates come from. Their parameters are vr_params.ris (estimate_ris_params.h, nested in the
// estimate block of estimate_params.h). Included after
// estimate_distributions.glsl; the kernel defines VR_ONE_MIXTURE before that unless
// VR_RIS_PER_REGION.
#ifndef VPLRENDER_ESTIMATE_RIS_SOURCE_GLSL
#define VPLRENDER_ESTIMATE_RIS_SOURCE_GLSL

#include "estimate_ris_params.h"
#include "vplkit/builders/local_weights.glsl"

// The mixture the pixel's candidates come from (render/cpu/ris_render.hpp's dist_of): with
// --candidate-source local the pixel's region's, else mixture 0 (in registers: VR_ONE_MIXTURE).
uint vr_ris_distribution(uint p) {
#ifdef VR_RIS_PER_REGION
  int w = vr_params.width;
  return uint(vplkit_region_of_pixel(int(p) % w, int(p) / w, w, vr_params.height, vr_params.ris.regions_x,
                                     vr_params.ris.regions_y));
#else
  return 0u;
#endif
}

#endif  // VPLRENDER_ESTIMATE_RIS_SOURCE_GLSL
