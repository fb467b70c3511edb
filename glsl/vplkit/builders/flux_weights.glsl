// SPDX-License-Identifier: MIT
// vplkit GLSL pack: flux weights, w_t = luminance(Phi_t) for every texel that carries a VPL (0
// elsewhere): light-power sampling, the view-independent candidate source of the resampled
// estimator (estimators/ris_estimator.glsl); mirrors include/vplkit/builders/flux_weights.hpp
// (T = float). A weights kernel writes one per texel and cdf_build.comp turns them into the CDF.
//
// ACCESSORS: vplkit_load_dprsm_position / _normal / _albedo (vpl/dprsm_view.glsl).
#ifndef VPLKIT_BUILDERS_FLUX_WEIGHTS_GLSL
#define VPLKIT_BUILDERS_FLUX_WEIGHTS_GLSL

#include "vplkit/vpl/dprsm_view.glsl"
#include "vplkit/vpl/luminance.glsl"
#include "vplkit/vpl/vpl.glsl"

// w_t for one texel; 0 where the texel carries no VPL.
float vplkit_flux_weight_texel(vplkit_dprsm_view view, int texel) {
  vplkit_vpl v = vplkit_dprsm_view_vpl_at(view, texel);
  if (!vplkit_vpl_has_flux(v)) return 0.0;
  float w = vplkit_luminance(v.flux);
  return w > 0.0 ? w : 0.0;
}

#endif  // VPLKIT_BUILDERS_FLUX_WEIGHTS_GLSL
