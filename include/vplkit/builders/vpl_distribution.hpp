// SPDX-License-Identifier: MIT
#pragma once
// From builder weights to the distribution the estimators sample (docs/math.md section 3):
//     p(t) = (1 - eps) w_t / sum w  +  eps / |F|    for t in F, the texels carrying a VPL,
// F = { t : vpl_at(t).flux > 0 in some channel } (vpl_has_flux). Every VPL that can contribute is
// in F, so with eps > 0 every contributing VPL has p(t) >= eps / |F| > 0 and the estimator
// L_t / p(t) stays unbiased even where median filling or a visibility-blind subset left w_t = 0.
//
// eps = 0 is the plain discrete_cdf over the weights (the paper): the mixture is built with no
// fallback at all, so an all-zero weight array gives an EMPTY distribution (sample() returns pmf 0;
// the estimator must then return 0 for the pixel) rather than silently switching to uniform.
// eps > 0 with all-zero weights gives the uniform distribution over F (defensive_mixture sends all
// mass to the fallback); a DPRSM with no VPL at all (F empty) gives an empty distribution.
#include <vplkit/core/error.hpp>
#include <vplkit/distribution/defensive_mixture.hpp>
#include <vplkit/distribution/discrete_cdf.hpp>
#include <vplkit/vpl/dprsm_view.hpp>
#include <vplkit/vpl/vpl.hpp>

#include <cmath>
#include <cstddef>
#include <limits>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace vplkit {

// Uniform distribution over the texels that carry a VPL (size 2 R^2; empty when none does).
template <class T>
inline discrete_cdf<T> make_vpl_fallback(const dprsm_view<T>& view) {
  view.validate();
  const int n = view.texel_count();
  std::vector<T> ones(std::size_t(n), T(0));
  for (int t = 0; t < n; ++t) ones[std::size_t(t)] = vpl_has_flux(view.vpl_at(t)) ? T(1) : T(0);
  return discrete_cdf<T>(ones.data(), ones.size());
}

namespace detail {

template <class T>
inline void check_vpl_weights(const T* weights, std::size_t n, std::size_t expected,
                              const char* who) {
  if (n != expected)
    throw invalid_input(std::string(who) + ": " + std::to_string(n) +
                        " weights, the DPRSM has 2 R^2 = " + std::to_string(expected) + " texels");
  if (n > 0 && weights == nullptr) throw invalid_input(std::string(who) + ": null weights pointer");
  for (std::size_t i = 0; i < n; ++i) {
    const T w = weights[i];
    if (!(w >= T(0) && w <= std::numeric_limits<T>::max())) {
      std::ostringstream s;
      s.precision(std::numeric_limits<T>::max_digits10);
      s << who << ": weight[" << i << "] = " << w << " is "
        << (std::isnan(w) ? "NaN" : std::isinf(w) ? "infinite" : "negative")
        << "; builder weights must be finite and >= 0";
      throw invalid_input(s.str());
    }
  }
}

template <class T>
inline void check_eps(T eps, const char* who) {
  if (!(eps >= T(0) && eps <= T(1)))
    throw invalid_input(std::string(who) + ": eps = " + std::to_string(eps) +
                        " is outside [0, 1]");
}

}  // namespace detail

// The defensive mixture for one weight array of 2 R^2 entries (any builder's output) and a
// prebuilt fallback (make_vpl_fallback(view); pass it to share one fallback between several
// distributions). Throws invalid_input when the size is not 2 R^2, a weight is negative / NaN /
// infinite (naming the first), eps is outside [0, 1] or NaN, or the weights sum past T's range.
template <class T>
inline defensive_mixture<T> make_vpl_distribution(const T* weights, std::size_t n,
                                                  const dprsm_view<T>& view,
                                                  const discrete_cdf<T>& fallback, T eps) {
  const char* who = "make_vpl_distribution";
  detail::check_eps(eps, who);
  const std::size_t expected = std::size_t(view.texel_count());
  detail::check_vpl_weights(weights, n, expected, who);
  if (fallback.size() != expected && fallback.size() != 0)
    throw invalid_input(std::string(who) + ": fallback has " + std::to_string(fallback.size()) +
                        " entries, expected " + std::to_string(expected));
  discrete_cdf<T> learned(weights, n);
  if (eps == T(0)) return defensive_mixture<T>(std::move(learned), discrete_cdf<T>(), T(0));
  return defensive_mixture<T>(std::move(learned), fallback, eps);
}

template <class T>
inline defensive_mixture<T> make_vpl_distribution(const T* weights, std::size_t n,
                                                  const dprsm_view<T>& view, T eps) {
  detail::check_eps(eps, "make_vpl_distribution");
  // Validates the view too; eps = 0 needs no fallback, so skip building one.
  if (eps == T(0)) {
    view.validate();
    return make_vpl_distribution(weights, n, view, discrete_cdf<T>(), eps);
  }
  return make_vpl_distribution(weights, n, view, make_vpl_fallback(view), eps);
}

template <class T>
inline defensive_mixture<T> make_vpl_distribution(const std::vector<T>& weights,
                                                  const dprsm_view<T>& view, T eps) {
  return make_vpl_distribution(weights.data(), weights.size(), view, eps);
}

// One mixture per region from the flat region-major array of build_local_weights
// (regions * 2 R^2 entries), all sharing one fallback. A region whose weights are all 0 gives an
// empty mixture when eps = 0 and the uniform fallback when eps > 0.
template <class T>
inline std::vector<defensive_mixture<T>> make_local_vpl_distributions(
    const std::vector<T>& flat_weights, int regions, const dprsm_view<T>& view, T eps) {
  const char* who = "make_local_vpl_distributions";
  detail::check_eps(eps, who);
  view.validate();
  const std::size_t per = std::size_t(view.texel_count());
  if (regions < 1 || flat_weights.size() != std::size_t(regions) * per)
    throw invalid_input(std::string(who) + ": " + std::to_string(flat_weights.size()) +
                        " weights for " + std::to_string(regions) + " regions of 2 R^2 = " +
                        std::to_string(per) + " texels");
  const discrete_cdf<T> fallback = eps == T(0) ? discrete_cdf<T>() : make_vpl_fallback(view);
  std::vector<defensive_mixture<T>> out;
  out.reserve(std::size_t(regions));
  for (int i = 0; i < regions; ++i)
    out.push_back(make_vpl_distribution(flat_weights.data() + std::size_t(i) * per, per, view,
                                        fallback, eps));
  return out;
}

}  // namespace vplkit
