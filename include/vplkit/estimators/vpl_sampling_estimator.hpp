// SPDX-License-Identifier: MIT
#pragma once
// VPL sampling by inverse transform (docs/math.md section 3):
//     L^(x) = (1/N) sum_k L_{t_k}(x) V / p(t_k),   t_k ~ p.
// Unbiased for the exhaustive VPL sum wherever p(t) > 0 for every t with L_t(x) > 0
// (defensive_mixture guarantees that; a plain CDF with holes is biased, the paper's behaviour).
//
// Distribution: anything with `sample(T u) -> {index, pmf}` over the flat DPRSM index
// (discrete_cdf, alias_table, defensive_mixture, flat_face_roulette, ...) of size texel_count().
// A draw with pmf 0 (empty distribution) or an index outside the view adds 0 and is never divided.
// Random numbers, in this order (the GLSL mirror follows it): for k = 0 .. N-1, one u = the next
// rng_next_unit<T>(rng), passed to sample(u); with vpl_mode::patch two more, u0 then u1, the
// jitter xi = (u0, u1) inside the drawn texel (dprsm_patch_vpl), drawn whatever the draw gave, so
// every sample takes exactly three. An invalid gather point returns 0 and consumes none.
// Visibility(x, n_x, y, n_t) -> bool is queried once per sample with a non-zero contribution.
//
// vpl_mode::point (default, the paper's) converges to the exhaustive VPL sum (the midpoint rule);
// vpl_mode::patch to the continuous one-bounce integral (docs/math.md section 11), with
// depth_tolerance the window of dprsm_patch_vpl (pass the gathering lookup's tolerance to get
// gathering's estimand exactly; +inf, the default, keeps every plane point).
#include <vplkit/core/gather_point.hpp>
#include <vplkit/core/vector.hpp>
#include <vplkit/distribution/face_roulette.hpp>
#include <vplkit/distribution/flat_face_roulette.hpp>
#include <vplkit/estimators/estimator_state.hpp>
#include <vplkit/estimators/vpl_sum.hpp>
#include <vplkit/sampling/rng.hpp>
#include <vplkit/vpl/dprsm_patch.hpp>
#include <vplkit/vpl/dprsm_view.hpp>

#include <limits>

namespace vplkit {

// One sample's value L_t V / p(t) for the draw u (0 when pmf is 0 or t is out of range).
template <class T, class Distribution, class Visibility>
inline vec3<T> vpl_sampling_sample(const gather_point<T>& gp, const dprsm_view<T>& view,
                                   const Distribution& distribution, T u, const Visibility& visibility,
                                   T dmin) {
  const auto s = distribution.sample(u);
  const T pmf = estimator_pmf(T(s.pmf));
  if (!(pmf > T(0)) || s.index >= std::size_t(view.texel_count())) return vec3<T>(T(0));
  const vec3<T> c = vpl_visible_contribution(gp, view, int(s.index), visibility, dmin);
  // A denormal pmf can overflow the quotient: such a draw has negligible probability, and an
  // Inf would poison the image, so it adds 0 (as balance_combined does).
  return estimator_finite_or_zero(c / pmf);
}

// The patch-sampled sample: L(y) V / p(t) at the point y of the drawn texel that xi selects.
template <class T, class Distribution, class Visibility>
inline vec3<T> vpl_sampling_patch_sample(const gather_point<T>& gp, const dprsm_view<T>& view,
                                         const Distribution& distribution, T u, vec2<T> xi,
                                         const Visibility& visibility, T dmin, T depth_tolerance) {
  const auto s = distribution.sample(u);
  const T pmf = estimator_pmf(T(s.pmf));
  if (!(pmf > T(0)) || s.index >= std::size_t(view.texel_count())) return vec3<T>(T(0));
  const vec3<T> c = vpl_patch_visible_contribution(gp, view, int(s.index), xi, visibility, dmin, depth_tolerance);
  return estimator_finite_or_zero(c / pmf);
}

// Samples [begin, end) of estimate_vpl_sampling (estimator_state.hpp).
template <class T, class Distribution, class Visibility>
inline void estimate_vpl_sampling_range(const gather_point<T>& gp, const dprsm_view<T>& view,
                                        const Distribution& distribution, estimator_state<T>& state,
                                        int begin, int end, const Visibility& visibility, T dmin,
                                        vpl_mode mode = vpl_mode::point,
                                        T depth_tolerance = std::numeric_limits<T>::infinity()) {
  if (!gather_point_valid(gp)) return;
  for (int k = begin; k < end; ++k) {
    const T u = rng_next_unit<T>(state.rng);
    if (mode == vpl_mode::patch) {
      const T u0 = rng_next_unit<T>(state.rng);
      const T u1 = rng_next_unit<T>(state.rng);
      state.sum += vpl_sampling_patch_sample(gp, view, distribution, u, vec2<T>(u0, u1), visibility, dmin,
                                             depth_tolerance);
    } else {
      state.sum += vpl_sampling_sample(gp, view, distribution, u, visibility, dmin);
    }
  }
}

template <class T>
inline vec3<T> estimate_vpl_sampling_finish(const estimator_state<T>& state, int n_samples) {
  return n_samples > 0 ? state.sum / T(n_samples) : vec3<T>(T(0));
}

template <class T, class Distribution, class Visibility>
inline vec3<T> estimate_vpl_sampling(const gather_point<T>& gp, const dprsm_view<T>& view,
                                     const Distribution& distribution, counter_rng& rng, int n_samples,
                                     const Visibility& visibility, T dmin, vpl_mode mode = vpl_mode::point,
                                     T depth_tolerance = std::numeric_limits<T>::infinity()) {
  if (!gather_point_valid(gp) || n_samples <= 0) return vec3<T>(T(0));
  estimator_state<T> state = make_estimator_state<T>(rng);
  estimate_vpl_sampling_range(gp, view, distribution, state, 0, n_samples, visibility, dmin, mode,
                              depth_tolerance);
  rng = state.rng;
  return estimate_vpl_sampling_finish(state, n_samples);
}

// The paper's Alg. 1 / 3: Russian roulette between the faces, then the face's CDF (one u per
// sample, as above). Same pmf as one CDF over both faces (face_roulette.hpp).
template <class T, class Visibility>
inline vec3<T> estimate_vpl_sampling(const gather_point<T>& gp, const dprsm_view<T>& view,
                                     const face_roulette<T>& roulette, counter_rng& rng, int n_samples,
                                     const Visibility& visibility, T dmin, vpl_mode mode = vpl_mode::point,
                                     T depth_tolerance = std::numeric_limits<T>::infinity()) {
  return estimate_vpl_sampling(gp, view, flat_face_roulette<T>(roulette, view.resolution), rng, n_samples,
                               visibility, dmin, mode, depth_tolerance);
}

}  // namespace vplkit
