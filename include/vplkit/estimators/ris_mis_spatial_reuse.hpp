// SPDX-License-Identifier: MIT
#pragma once
// Unbiased spatial reuse for resampled VPL sampling with gathering (ris_mis_estimator.hpp;
// docs/math.md, "RIS with gathering", "Spatial reuse with gathering"). The n2 RIS samples of
// estimate_ris_mis have the target lum(h_g), h_g(t, xi) = n2 pmf_g(t) f_g(y) / (n1 p1 + n2 p2_g):
// a pixel g can evaluate it for any sample (a texel and a jitter; the shift map is the identity),
// given the pmf of its own candidate distribution, so the generalized RIS of
// ris_spatial_reuse.hpp combines its reservoirs unchanged, with the target
//     p_hat_g(s) = lum(ris_mis_unshadowed(g, view, s, pmf_g(s.texel), n1, n2, ...))    (ris_mis_target).
// The receiving pixel q shades the combined reservoir as its own: h_q(y) V(x_q, y) W with
// W = weight_sum / p_hat_q(y) (ris_mis_shade with q's distribution), 1/n2 and the gathering
// directions as in estimate_ris_mis. W is an unbiased contribution weight for q's target wherever
// the canonical input covers its support (p_hat_q(y) > 0 implies pmf_q(y) > 0, since h_q carries
// the factor pmf_q), so the estimate of the integral of w2_q f_q stays unbiased.
//
// pmf_g is the candidate distribution of pixel g: distribution_of(pixel) returns it (the same one
// everywhere for a global, gbg or flux source; the pixel's region's for local). Each pixel's
// stored target must have been made with its own distribution (ris_mis_resample with
// distribution_of(pixel)), which is what the receiver's MIS weights read.
//
// Random numbers: those of ris_spatial_reuse (1 + 3K per reuse, see ris_spatial_reuse.hpp).
#include <vplkit/core/gather_point.hpp>
#include <vplkit/distribution/weighted_reservoir.hpp>
#include <vplkit/estimators/ris_mis_estimator.hpp>
#include <vplkit/estimators/ris_reservoir.hpp>
#include <vplkit/estimators/ris_spatial_reuse.hpp>
#include <vplkit/estimators/vpl_sum.hpp>
#include <vplkit/sampling/rng.hpp>
#include <vplkit/vpl/dprsm_view.hpp>
#include <vplkit/vpl/luminance.hpp>

#include <cstddef>

namespace vplkit {

// p_hat_g(s) = lum(h_g(s)) at the gather point g of pixel `pixel`, with the pmf of
// distribution_of(pixel): the target ris_mis_candidate gives the sample when g's candidate pass
// draws it (0 where the luminance is not a usable weight, as there).
template <class T, class DistributionOf>
struct ris_mis_target {
  const dprsm_view<T>* view = nullptr;
  const DistributionOf* distribution_of = nullptr;
  T n1 = T(0), n2 = T(0);
  vpl_mode mode = vpl_mode::point;
  T depth_tolerance = T(0);
  T operator()(int pixel, const gather_point<T>& g, const ris_sample<T>& s) const {
    if (s.texel < 0 || s.texel >= view->texel_count()) return T(0);
    const T pmf = estimator_pmf(T((*distribution_of)(pixel).pmf(std::size_t(s.texel))));
    vpl<T> v;
    const T p = luminance(ris_mis_unshadowed(g, *view, s, pmf, n1, n2, mode, depth_tolerance, v));
    return reservoir_weight_usable(p) ? p : T(0);
  }
};

// Combines pixel `pixel`'s canonical reservoir (ris_mis_resample at gp with distribution_of(pixel))
// with up to settings.neighbours neighbours' (load(pixel) -> ris_neighbour<T>: their gather points
// and reservoirs of the same candidate pass), by ris_spatial_reuse_with and the target
// ris_mis_target. Shade the result with ris_mis_shade(gp, view, distribution_of(pixel), ...).
template <class T, class Load, class DistributionOf>
inline ris_reservoir<T> ris_mis_spatial_reuse(const gather_point<T>& gp, int pixel, int width, int height,
                                              const dprsm_view<T>& view, const ris_reservoir<T>& canonical,
                                              const Load& load, const ris_spatial_settings<T>& settings,
                                              counter_rng& rng, const DistributionOf& distribution_of, T n1, T n2,
                                              vpl_mode mode, T depth_tolerance) {
  return ris_spatial_reuse_with(gp, pixel, width, height, canonical, load, settings, rng,
                                ris_mis_target<T, DistributionOf>{&view, &distribution_of, n1, n2, mode,
                                                                  depth_tolerance});
}

}  // namespace vplkit
