// SPDX-License-Identifier: MIT
#pragma once
// Flux weights: every texel weighted by the luminance of its VPL's flux,
//     w_t = luminance(Phi_t),   Phi_t = rho_t I_s Omega_t (vpl_at, docs/math.md section 2),
// the light-power sampling of many-light renderers (RTXDI's local-light PDF samples lights by their
// power). It knows nothing of the view: the baseline candidate source of the resampled estimator
// (estimators/ris_estimator.hpp) against which the view-dependent CDFs (global, local, gbg) are
// measured. Feed the weights to make_vpl_distribution (builders/vpl_distribution.hpp) like any
// builder's.
//
// Every texel that carries a VPL has w_t > 0 (the luminance coefficients are positive and a VPL has
// a positive channel), so the flux CDF alone already covers every VPL that can contribute; a texel
// without one gets exactly 0.
#include <vplkit/vpl/dprsm_view.hpp>
#include <vplkit/vpl/luminance.hpp>
#include <vplkit/vpl/vpl.hpp>

#include <cstddef>
#include <vector>

namespace vplkit {

// w_t for one texel (0 where the texel carries no VPL): the per-invocation function of a GPU
// pass; never throws.
template <class T>
inline T flux_weight_texel(const dprsm_view<T>& view, int texel) {
  const vpl<T> v = view.vpl_at(texel);
  if (!vpl_has_flux(v)) return T(0);
  const T w = luminance(v.flux);
  return w > T(0) ? w : T(0);  // written so that NaN gives 0
}

// The 2 R^2 flux weights of a DPRSM (throws invalid_input for a bad view).
template <class T>
inline std::vector<T> build_flux_weights(const dprsm_view<T>& view) {
  view.validate();
  std::vector<T> w(std::size_t(view.texel_count()), T(0));
  for (int t = 0; t < view.texel_count(); ++t) w[std::size_t(t)] = flux_weight_texel(view, t);
  return w;
}

}  // namespace vplkit
