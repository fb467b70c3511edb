// SPDX-License-Identifier: MIT
// vplkit GLSL pack: global weights (BRSM, Ritschel et al. 2011; docs/math.md section 4), the mean
// luminance of every VPL's contribution to a subset S of gather points, without visibility:
//     w_t = (1 / |S|) sum_{g in S} luminance(L_t(g));
// mirrors include/vplkit/builders/global_weights.hpp (T = float). The kernel global_weights.comp runs
// it over all texels (and the N regions of the local method).
//
// ACCESSORS (the including shader defines them):
//   vplkit_gather_point vplkit_load_subset_gather_point(int i);
//     entry i (0 <= i < count) of the subset, in the subset's order. The C++ per-texel function
//     takes valid points only, and build_global_weights drops the invalid ones (background pixels)
//     before: here entries failing vplkit_gather_point_valid are skipped and not counted, which is
//     the same arithmetic in both cases (so the accessor may return a zero normal for "no pixel",
//     e.g. a dropped stratum of gather_subset.comp).
//   vplkit_load_dprsm_position / _normal / _albedo (vpl/dprsm_view.glsl).
//
// Arithmetic, as in the C++: the per-texel sum runs in float over the subset in order, then is
// multiplied by 1.0 / float(|S|). A texel that carries no VPL gets exactly 0 without evaluating
// any contribution. Under llvmpipe's loop budget (docs/glsl.md) |S| must stay below about 65000
// (the paper's reference used 4k).
#ifndef VPLKIT_BUILDERS_GLOBAL_WEIGHTS_GLSL
#define VPLKIT_BUILDERS_GLOBAL_WEIGHTS_GLSL

#include "vplkit/core/gather_point.glsl"
#include "vplkit/vpl/dprsm_view.glsl"
#include "vplkit/vpl/luminance.glsl"
#include "vplkit/vpl/vpl.glsl"

vplkit_gather_point vplkit_load_subset_gather_point(int i);

// w_t for one texel from the `count` subset entries; 0 when no entry is valid or the texel carries
// no VPL.
float vplkit_global_weight_texel(vplkit_dprsm_view view, int texel, int count, float dmin) {
  vplkit_vpl v = vplkit_dprsm_view_vpl_at(view, texel);
  if (count <= 0 || !vplkit_vpl_has_flux(v)) return 0.0;
  float sum = 0.0;
  int used = 0;
  for (int i = 0; i < count; ++i) {
    vplkit_gather_point g = vplkit_load_subset_gather_point(i);
    if (!vplkit_gather_point_valid(g)) continue;
    sum += vplkit_luminance(vplkit_vpl_contribution(g, v, dmin));
    ++used;
  }
  if (used == 0) return 0.0;
  return sum * (1.0 / float(used));
}

#endif  // VPLKIT_BUILDERS_GLOBAL_WEIGHTS_GLSL
