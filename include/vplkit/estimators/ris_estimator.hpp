// SPDX-License-Identifier: MIT
#pragma once
// Resampled importance sampling of VPLs (Talbot et al. 2005; docs/math.md section 13). Per
// gather point x:
//   1. draw M candidates x_1..x_M from a distribution p over the texels (any distribution the
//      estimators take: a builder's defensive mixture, a region's CDF, the flux CDF of
//      builders/flux_weights.hpp), with vpl_mode::patch each with its jitter xi;
//   2. weigh each by w_i = p_hat(x_i) / p(x_i), where the target p_hat is the luminance of the
//      unshadowed contribution at x (ris_target: vpl_contribution, no visibility);
//   3. keep one with a streaming weighted reservoir (distribution/weighted_reservoir.hpp):
//      y = x_i with probability w_i / sum_j w_j;
//   4. test visibility for y only, and return
//          f(y) W,   W = (1 / p_hat(y)) (1/M) sum_i w_i,   f(y) = L_y(x) V(x, y).
// E[f(y) W] is the VPL sum (point) or the patch integral (patch) wherever p(t) > 0 for every t
// with p_hat > 0 (a defensive mixture, the flux CDF), and p_hat > 0 wherever f is: the estimand of
// estimate_vpl_sampling, for one visibility query per sample instead of one per candidate. The
// candidates cost a distribution draw and one unshadowed contribution each.
//
// Samples and reservoirs. A sample is a texel and its jitter (ris_sample); a reservoir keeps one
// with the generalized-RIS normalisation (Lin et al. 2022): weight_sum = (1/M) sum w_i, the kept
// sample's target, and its confidence M, so that W = weight_sum / target; spatial reuse
// (ris_spatial_reuse.hpp) combines reservoirs of this form. glsl/vplkit/estimators/ris_params.h
// stores one in a 32-byte record for a buffer.
//
// Random numbers, per candidate (the GLSL mirror follows them): u for distribution.sample(u);
// with vpl_mode::patch u0 then u1, the jitter; then one u per kept reservoir (the selection). All of
// them always, also when the draw is empty, so the layout does not depend on the scene: a round of
// estimate_ris takes M (2 or 4) numbers. An invalid gather point, M <= 0 or k <= 0 consumes none.
//
// Keep k: ris_resample_candidates fills k reservoirs from the same candidates (k selections with
// replacement, each its own u); ris_shade_kept averages their k values and tests visibility once
// per distinct sample. Each value is unbiased, so their mean is.
#include <vplkit/core/gather_point.hpp>
#include <vplkit/core/vector.hpp>
#include <vplkit/distribution/weighted_reservoir.hpp>
#include <vplkit/estimators/estimator_state.hpp>
#include <vplkit/estimators/ris_reservoir.hpp>
#include <vplkit/estimators/vpl_sum.hpp>
#include <vplkit/sampling/rng.hpp>
#include <vplkit/vpl/dprsm_patch.hpp>
#include <vplkit/vpl/dprsm_view.hpp>
#include <vplkit/vpl/luminance.hpp>
#include <vplkit/vpl/vpl.hpp>

#include <cstddef>
#include <cstdint>
#include <limits>

namespace vplkit {

// The most reservoirs ris_resample_candidates fills from one set of candidates (the GLSL mirror's
// VPLKIT_RIS_MAX_KEPT: a shader keeps them in a fixed array).
inline constexpr int ris_max_kept = 8;

// The VPL a sample stands for: the texel's (point) or its jittered patch point (patch, with the
// patch's depth window); zero flux for a texel outside the view or a rejected patch point.
template <class T>
inline vpl<T> ris_sample_vpl(const dprsm_view<T>& view, const ris_sample<T>& s, vpl_mode mode, T depth_tolerance) {
  if (s.texel < 0 || s.texel >= view.texel_count()) return vpl<T>{vec3<T>(T(0)), vec3<T>(T(0)), vec3<T>(T(0))};
  if (mode == vpl_mode::patch) return dprsm_patch_vpl(view, s.texel, s.xi, depth_tolerance).point;
  return view.vpl_at(s.texel);
}

// The target function p_hat: the luminance of the VPL's unshadowed contribution at gp (no
// visibility); 0 where it is not a usable weight (0, negative, NaN, infinite).
template <class T>
inline T ris_target(const gather_point<T>& gp, const vpl<T>& v, T dmin) {
  const T p = luminance(vpl_contribution(gp, v, dmin));
  return reservoir_weight_usable(p) ? p : T(0);
}

// One candidate: draws u (and with vpl_mode::patch u0, u1), sets its sample s and target, and
// returns its weight p_hat / p: 0 where the draw is empty (pmf 0), its index lies outside the view
// or its target is 0; an overflow (a pmf so small that the draw has negligible probability) is not
// a usable weight, and the reservoir skips it.
template <class T, class Distribution>
inline T ris_candidate(const gather_point<T>& gp, const dprsm_view<T>& view, const Distribution& distribution,
                       counter_rng& rng, T dmin, vpl_mode mode, T depth_tolerance, ris_sample<T>& s, T& target) {
  s = ris_sample<T>{};
  target = T(0);
  const T u = rng_next_unit<T>(rng);
  if (mode == vpl_mode::patch) {
    s.xi.x = rng_next_unit<T>(rng);
    s.xi.y = rng_next_unit<T>(rng);
  }
  const auto d = distribution.sample(u);
  const T pmf = T(d.pmf);
  if (!(pmf > T(0)) || d.index >= std::size_t(view.texel_count())) return T(0);
  s.texel = int(d.index);
  target = ris_target(gp, ris_sample_vpl(view, s, mode, depth_tolerance), dmin);
  return target / pmf;
}

// Draws n_candidates candidates from `distribution` and keeps one in each of reservoirs[0 .. n_kept)
// (n_kept clamped to ris_max_kept). Every reservoir gets confidence M = n_candidates and the same
// weight_sum. Random numbers: see the header.
template <class T, class Distribution>
inline void ris_resample_candidates(const gather_point<T>& gp, const dprsm_view<T>& view,
                                    const Distribution& distribution, counter_rng& rng, int n_candidates,
                                    ris_reservoir<T>* reservoirs, int n_kept, T dmin,
                                    vpl_mode mode = vpl_mode::point,
                                    T depth_tolerance = std::numeric_limits<T>::infinity()) {
  const int k = n_kept < ris_max_kept ? n_kept : ris_max_kept;
  for (int j = 0; j < k; ++j) reservoirs[j] = ris_reservoir<T>{};
  if (!gather_point_valid(gp) || n_candidates <= 0 || k <= 0) return;
  weighted_reservoir<T> res[ris_max_kept];
  for (int i = 0; i < n_candidates; ++i) {
    ris_sample<T> s;
    T target;
    const T w = ris_candidate(gp, view, distribution, rng, dmin, mode, depth_tolerance, s, target);
    for (int j = 0; j < k; ++j)
      if (reservoir_update(res[j], std::uint32_t(i), w, rng_next_unit<T>(rng))) {
        reservoirs[j].kept = s;
        reservoirs[j].target = target;
      }
  }
  const T m = T(n_candidates);
  for (int j = 0; j < k; ++j) {
    reservoirs[j].confidence = m;
    if (!reservoir_empty_of(res[j])) reservoirs[j].weight_sum = res[j].weight_sum / m;
  }
}

// One reservoir from n_candidates candidates (ris_resample_candidates with k = 1).
template <class T, class Distribution>
inline ris_reservoir<T> ris_resample(const gather_point<T>& gp, const dprsm_view<T>& view,
                                     const Distribution& distribution, counter_rng& rng, int n_candidates, T dmin,
                                     vpl_mode mode = vpl_mode::point,
                                     T depth_tolerance = std::numeric_limits<T>::infinity()) {
  ris_reservoir<T> r;
  ris_resample_candidates(gp, view, distribution, rng, n_candidates, &r, 1, dmin, mode, depth_tolerance);
  return r;
}

// f(y) W for the reservoir's sample y at gp: the unshadowed contribution times V(x, y) (queried
// only when the contribution is non-zero), times W = weight_sum / target. The reservoir's target
// must be p_hat(y) at this gp (a reservoir of gp's candidates, or the output of a reuse at gp).
// 0 for an invalid gather point or a reservoir without a sample; never NaN or Inf.
template <class T, class Visibility>
inline vec3<T> ris_shade(const gather_point<T>& gp, const dprsm_view<T>& view, const ris_reservoir<T>& r,
                         const Visibility& visibility, T dmin, vpl_mode mode = vpl_mode::point,
                         T depth_tolerance = std::numeric_limits<T>::infinity()) {
  if (!gather_point_valid(gp) || !ris_reservoir_has_sample(r)) return vec3<T>(T(0));
  const vpl<T> v = ris_sample_vpl(view, r.kept, mode, depth_tolerance);
  const vec3<T> c = vpl_contribution(gp, v, dmin);
  if (!(c.x > T(0) || c.y > T(0) || c.z > T(0))) return vec3<T>(T(0));
  if (!visibility(gp.position, gp.normal, v.position, v.normal)) return vec3<T>(T(0));
  return estimator_finite_or_zero(c * (r.weight_sum / r.target));
}

// The mean of ris_shade over reservoirs[0 .. n_kept): a sample kept by several reservoirs is shaded
// (and its visibility queried) once. 0 for n_kept <= 0.
template <class T, class Visibility>
inline vec3<T> ris_shade_kept(const gather_point<T>& gp, const dprsm_view<T>& view, const ris_reservoir<T>* reservoirs,
                              int n_kept, const Visibility& visibility, T dmin, vpl_mode mode = vpl_mode::point,
                              T depth_tolerance = std::numeric_limits<T>::infinity()) {
  const int k = n_kept < ris_max_kept ? n_kept : ris_max_kept;
  if (k <= 0) return vec3<T>(T(0));
  vec3<T> value[ris_max_kept];
  vec3<T> sum(T(0));
  for (int j = 0; j < k; ++j) {
    int same = -1;
    // The same sample with the same weights (reservoirs of one candidate set share weight_sum and
    // the target of a sample) has the same value.
    for (int i = 0; i < j && same < 0; ++i)
      if (ris_same_sample(reservoirs[i].kept, reservoirs[j].kept) &&
          reservoirs[i].weight_sum == reservoirs[j].weight_sum && reservoirs[i].target == reservoirs[j].target)
        same = i;
    value[j] = same >= 0 ? value[same] : ris_shade(gp, view, reservoirs[j], visibility, dmin, mode, depth_tolerance);
    sum += value[j];
  }
  return sum / T(k);
}

// Samples [begin, end) of estimate_ris (estimator_state.hpp): each sample one reservoir of
// n_candidates candidates and one ris_shade.
template <class T, class Distribution, class Visibility>
inline void estimate_ris_range(const gather_point<T>& gp, const dprsm_view<T>& view, const Distribution& distribution,
                               estimator_state<T>& state, int begin, int end, int n_candidates,
                               const Visibility& visibility, T dmin, vpl_mode mode = vpl_mode::point,
                               T depth_tolerance = std::numeric_limits<T>::infinity()) {
  if (!gather_point_valid(gp) || n_candidates <= 0) return;
  for (int k = begin; k < end; ++k) {
    const ris_reservoir<T> r = ris_resample(gp, view, distribution, state.rng, n_candidates, dmin, mode, depth_tolerance);
    state.sum += ris_shade(gp, view, r, visibility, dmin, mode, depth_tolerance);
  }
}

template <class T>
inline vec3<T> estimate_ris_finish(const estimator_state<T>& state, int n_samples) {
  return n_samples > 0 ? state.sum / T(n_samples) : vec3<T>(T(0));
}

// (1/N) sum over N independent RIS samples, each from its own n_candidates candidates: N
// visibility queries, N M candidates. N = 1, M = 1 is one VPL sample of estimate_vpl_sampling
// (f / p, up to the rounding of p_hat / p_hat).
template <class T, class Distribution, class Visibility>
inline vec3<T> estimate_ris(const gather_point<T>& gp, const dprsm_view<T>& view, const Distribution& distribution,
                            counter_rng& rng, int n_samples, int n_candidates, const Visibility& visibility, T dmin,
                            vpl_mode mode = vpl_mode::point,
                            T depth_tolerance = std::numeric_limits<T>::infinity()) {
  if (!gather_point_valid(gp) || n_samples <= 0 || n_candidates <= 0) return vec3<T>(T(0));
  estimator_state<T> state = make_estimator_state<T>(rng);
  estimate_ris_range(gp, view, distribution, state, 0, n_samples, n_candidates, visibility, dmin, mode,
                     depth_tolerance);
  rng = state.rng;
  return estimate_ris_finish(state, n_samples);
}

}  // namespace vplkit
