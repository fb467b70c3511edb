// SPDX-License-Identifier: MIT
#pragma once
// Local CDFs (docs/math.md section 4, paper section 5.2): N distributions, one per image region.
// Each round draws one VPL from every distribution; n_rounds rounds (the paper's N_NG), N *
// n_rounds VPLs.
//
// Combinations (the estimand is the exhaustive VPL sum in both):
//   balance (default): sample t drawn from CDF_i adds L_t V / sum_j p_j(t); the total is divided
//     by n_rounds. This is sampling the mixture (1/N) sum_j p_j, i.e. the balance heuristic over
//     the N CDFs: unbiased wherever ANY CDF covers t, and no seam at region borders.
//   average (as published): (1 / (N n_rounds)) sum L_t V / p_i(t), each sample divided by the pmf
//     of the CDF that drew it. Unbiased only where EVERY CDF covers t: a VPL missing from CDF_j
//     loses its share 1/N of the estimate.
// An empty CDF (total 0) draws nothing (its draws have pmf 0 and add 0) but still counts in N for
// `average`; for `balance` it adds 0 to every sum_j p_j, so balance stays unbiased.
//
// Random numbers: for round r = 0 .. n_rounds-1, for i = 0 .. N-1: one u = rng_next_unit<T>(rng),
// passed to distributions[i].sample(u), and with vpl_mode::patch u0, u1, the jitter inside the
// drawn texel (three per sample, always). Cost: `balance` evaluates N pmfs per sample (N^2 per
// round). An invalid gather point returns 0 and consumes none.
// vpl_mode::patch (docs/math.md section 11): each sample is the jittered point of its texel; the
// jitter density is the same under every CDF, so the combinations divide by the pmfs as above and
// the estimand becomes the continuous integral.
#include <vplkit/core/gather_point.hpp>
#include <vplkit/core/vector.hpp>
#include <vplkit/estimators/estimator_state.hpp>
#include <vplkit/estimators/vpl_sum.hpp>
#include <vplkit/sampling/rng.hpp>
#include <vplkit/vpl/dprsm_patch.hpp>
#include <vplkit/vpl/dprsm_view.hpp>

#include <cstddef>
#include <limits>

namespace vplkit {

enum class local_combination { balance, average };

// sum_j pmf_j(t) over the N distributions: the (unnormalised) mixture density at t.
template <class T, class Distribution>
inline T local_mixture_pmf_sum(const Distribution* distributions, int n_distributions, std::size_t t) {
  T s = T(0);
  for (int j = 0; j < n_distributions; ++j) s += estimator_pmf(T(distributions[j].pmf(t)));
  return s;
}

// Rounds [begin, end) of estimate_local (estimator_state.hpp).
template <class T, class Distribution, class Visibility>
inline void estimate_local_range(const gather_point<T>& gp, const dprsm_view<T>& view,
                                 const Distribution* distributions, int n_distributions,
                                 estimator_state<T>& state, int begin, int end, const Visibility& visibility,
                                 T dmin, local_combination combination = local_combination::balance,
                                 vpl_mode mode = vpl_mode::point,
                                 T depth_tolerance = std::numeric_limits<T>::infinity()) {
  if (!gather_point_valid(gp) || n_distributions <= 0 || distributions == nullptr) return;
  const std::size_t n_texels = std::size_t(view.texel_count());
  for (int r = begin; r < end; ++r)
    for (int i = 0; i < n_distributions; ++i) {
      const auto s = distributions[i].sample(rng_next_unit<T>(state.rng));
      vec2<T> xi(T(0));
      if (mode == vpl_mode::patch) {
        xi.x = rng_next_unit<T>(state.rng);
        xi.y = rng_next_unit<T>(state.rng);
      }
      const T pmf_i = estimator_pmf(T(s.pmf));
      if (!(pmf_i > T(0)) || s.index >= n_texels) continue;
      const vec3<T> c =
          mode == vpl_mode::patch
              ? vpl_patch_visible_contribution(gp, view, int(s.index), xi, visibility, dmin, depth_tolerance)
              : vpl_visible_contribution(gp, view, int(s.index), visibility, dmin);
      if (!(c.x > T(0) || c.y > T(0) || c.z > T(0))) continue;
      // balance: pmf_i(t) > 0 is one of the terms, so the divisor is > 0.
      const T divisor = combination == local_combination::balance
                            ? local_mixture_pmf_sum<T>(distributions, n_distributions, s.index)
                            : pmf_i * T(n_distributions);
      state.sum += estimator_finite_or_zero(c / divisor);
    }
}

template <class T>
inline vec3<T> estimate_local_finish(const estimator_state<T>& state, int n_rounds) {
  return n_rounds > 0 ? state.sum / T(n_rounds) : vec3<T>(T(0));
}

template <class T, class Distribution, class Visibility>
inline vec3<T> estimate_local(const gather_point<T>& gp, const dprsm_view<T>& view,
                              const Distribution* distributions, int n_distributions, counter_rng& rng,
                              int n_rounds, const Visibility& visibility, T dmin,
                              local_combination combination = local_combination::balance,
                              vpl_mode mode = vpl_mode::point,
                              T depth_tolerance = std::numeric_limits<T>::infinity()) {
  if (!gather_point_valid(gp) || n_rounds <= 0 || n_distributions <= 0 || distributions == nullptr)
    return vec3<T>(T(0));
  estimator_state<T> state = make_estimator_state<T>(rng);
  estimate_local_range(gp, view, distributions, n_distributions, state, 0, n_rounds, visibility, dmin,
                       combination, mode, depth_tolerance);
  rng = state.rng;
  return estimate_local_finish(state, n_rounds);
}

}  // namespace vplkit
