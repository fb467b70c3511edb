// SPDX-License-Identifier: MIT
#pragma once
// The exhaustive VPL sum L(x) = sum_t L_t(x) V(x, y_t) (docs/math.md section 2): the estimand of
// every CDF method and their reference (feasible for small DPRSMs; O(2 R^2) visibility queries).
// Its patch form (docs/math.md section 11) puts m x m stratified jittered points in every texel:
// an unbiased, seeded Monte Carlo estimate of the continuous integral that patch-sampled VPLs
// converge to.
#include <vplkit/core/gather_point.hpp>
#include <vplkit/core/vector.hpp>
#include <vplkit/sampling/rng.hpp>
#include <vplkit/vpl/dprsm_patch.hpp>
#include <vplkit/vpl/dprsm_view.hpp>
#include <vplkit/vpl/vpl.hpp>

#include <cmath>
#include <cstdint>
#include <limits>

namespace vplkit {

// v when every component is finite, else 0: the last guard of every estimator's per-sample value.
template <class T>
inline vec3<T> estimator_finite_or_zero(vec3<T> v) {
  const T big = std::numeric_limits<T>::max();
  const bool ok = std::abs(v.x) <= big && std::abs(v.y) <= big && std::abs(v.z) <= big;  // NaN fails
  return ok ? v : vec3<T>(T(0));
}

// A drawn sample's pmf as the estimators use it: 0 unless it is a finite normal number
// (p >= FLT_MIN). The library's distributions never return a pmf in (0, FLT_MIN) (their stored
// values are >= 2^-103 apart, docs/api/distribution.md); for a user's distribution this is the
// normal-range contract of docs/math.md, "GPU arithmetic model": a denormal pmf is 0 on a GPU that flushes
// and in C++ under DAZ, so it counts as 0 everywhere, and the draw adds 0.
template <class T>
inline T estimator_pmf(T p) {
  return (p >= std::numeric_limits<T>::min() && p <= std::numeric_limits<T>::max()) ? p : T(0);
}

// L_t(x) V(x, y_t) for texel t: 0 for an index outside the view, a texel without flux, or a
// back-facing pair; visibility is queried only when the unoccluded contribution is non-zero (so a
// ray is spent only where it can matter). The per-sample term of every VPL-sampling estimator.
template <class T, class Visibility>
inline vec3<T> vpl_visible_contribution(const gather_point<T>& gp, const dprsm_view<T>& view, int t,
                                        const Visibility& visibility, T dmin) {
  if (t < 0 || t >= view.texel_count()) return vec3<T>(T(0));
  const vpl<T> v = view.vpl_at(t);
  const vec3<T> c = vpl_contribution(gp, v, dmin);
  if (!(c.x > T(0) || c.y > T(0) || c.z > T(0))) return vec3<T>(T(0));
  return visibility(gp.position, gp.normal, v.position, v.normal) ? c : vec3<T>(T(0));
}

// L(y) V(x, y) for the point y of texel t's patch that xi selects (dprsm_patch_vpl): the
// per-sample term of every patch-sampled VPL estimator. 0 for an index outside the view, a
// rejected point, or a back-facing pair; visibility is queried only when the unoccluded
// contribution is non-zero.
template <class T, class Visibility>
inline vec3<T> vpl_patch_visible_contribution(const gather_point<T>& gp, const dprsm_view<T>& view, int t,
                                              vec2<T> xi, const Visibility& visibility, T dmin,
                                              T depth_tolerance) {
  if (t < 0 || t >= view.texel_count()) return vec3<T>(T(0));
  const dprsm_patch_sample<T> s = dprsm_patch_vpl(view, t, xi, depth_tolerance);
  const vec3<T> c = vpl_contribution(gp, s.point, dmin);
  if (!(c.x > T(0) || c.y > T(0) || c.z > T(0))) return vec3<T>(T(0));
  return visibility(gp.position, gp.normal, s.point.position, s.point.normal) ? c : vec3<T>(T(0));
}

// The exhaustive sum's running total, kept in double whatever T is, so the reference does not
// lose digits over 10^5+ terms (the GLSL mirror keeps a compensated float pair instead).
struct vpl_sum_state {
  vec3<double> sum = vec3<double>(0.0);
};

// Adds L_t(x) V(x, y_t) of the texels [begin, end) (clipped to the view) to state.sum, in texel
// order; nothing for an invalid (background) gather point.
template <class T, class Visibility>
inline void exhaustive_vpl_sum_range(const gather_point<T>& gp, const dprsm_view<T>& view,
                                     vpl_sum_state& state, int begin, int end,
                                     const Visibility& visibility, T dmin) {
  if (!gather_point_valid(gp)) return;
  const int n = view.texel_count();
  const int first = begin < 0 ? 0 : begin, last = end < n ? end : n;
  for (int t = first; t < last; ++t)
    state.sum += vec3<double>(vpl_visible_contribution(gp, view, t, visibility, dmin));
}

// The sum rounded once to T.
template <class T>
inline vec3<T> exhaustive_vpl_sum_finish(const vpl_sum_state& state) {
  return vec3<T>(state.sum);
}

// sum_t L_t(x) V(x, y_t) over all 2 R^2 texels (invalid and unlit texels have zero flux); 0 for
// an invalid (background) gather point.
template <class T, class Visibility>
inline vec3<T> exhaustive_vpl_sum(const gather_point<T>& gp, const dprsm_view<T>& view,
                                  const Visibility& visibility, T dmin) {
  if (!gather_point_valid(gp)) return vec3<T>(T(0));
  vpl_sum_state state;
  exhaustive_vpl_sum_range(gp, view, state, 0, view.texel_count(), visibility, dmin);
  return exhaustive_vpl_sum_finish<T>(state);
}

// ---- patch form --------------------------------------------------------------------------------
//
// Texel t's stratum (i, j) of m x m (i along u) takes its two numbers from `stream` at the fixed
// counters stream.counter + 2 (t m^2 + j m + i) and + 1 (u along u, then along v): random access,
// so any split of the texels into ranges, in any order, gives the same numbers, and a texel
// without flux draws nothing. The counters wrap once 4 R^2 m^2 exceeds 2^32 (R = 16384 with
// m >= 2, R = 8192 with m >= 4): numbers then repeat, which correlates strata but stays correct. xi = ((i + u0) / m, (j + u1) / m).

// The jitter of texel t's stratum k = j m + i.
template <class T>
inline vec2<T> exhaustive_vpl_patch_jitter(const counter_rng& stream, int t, int strata, int i, int j) {
  const std::uint32_t m = std::uint32_t(strata);
  counter_rng r{stream.key,
                stream.counter + 2u * (std::uint32_t(t) * m * m + std::uint32_t(j) * m + std::uint32_t(i))};
  const T u0 = rng_next_unit<T>(r);
  const T u1 = rng_next_unit<T>(r);
  return vec2<T>((T(i) + u0) / T(strata), (T(j) + u1) / T(strata));
}

// Adds sum_k L(y_tk) V(x, y_tk) over the m^2 strata of the texels [begin, end) (clipped to the
// view) to state.sum, texel by texel in order, strata row by row; nothing for an invalid gather
// point or strata <= 0.
template <class T, class Visibility>
inline void exhaustive_vpl_patch_sum_range(const gather_point<T>& gp, const dprsm_view<T>& view,
                                           vpl_sum_state& state, int begin, int end, const counter_rng& stream,
                                           int strata, const Visibility& visibility, T dmin,
                                           T depth_tolerance) {
  if (!gather_point_valid(gp) || strata <= 0) return;
  const int n = view.texel_count();
  const int first = begin < 0 ? 0 : begin, last = end < n ? end : n;
  for (int t = first; t < last; ++t) {
    if (!vpl_has_flux(view.vpl_at(t))) continue;
    for (int j = 0; j < strata; ++j)
      for (int i = 0; i < strata; ++i)
        state.sum += vec3<double>(vpl_patch_visible_contribution(
            gp, view, t, exhaustive_vpl_patch_jitter<T>(stream, t, strata, i, j), visibility, dmin,
            depth_tolerance));
  }
}

// The sum divided by m^2 (the mean over each texel's strata), rounded once to T; 0 for strata <= 0.
template <class T>
inline vec3<T> exhaustive_vpl_patch_sum_finish(const vpl_sum_state& state, int strata) {
  if (strata <= 0) return vec3<T>(T(0));
  return vec3<T>(state.sum / (double(strata) * double(strata)));
}

// sum_t mean_k L(y_tk) V(x, y_tk) over all 2 R^2 texels: an unbiased estimate of the continuous
// integral with m^2 stratified points per texel (docs/math.md section 11); 0 for an invalid
// gather point.
template <class T, class Visibility>
inline vec3<T> exhaustive_vpl_patch_sum(const gather_point<T>& gp, const dprsm_view<T>& view,
                                        const counter_rng& stream, int strata, const Visibility& visibility,
                                        T dmin, T depth_tolerance) {
  if (!gather_point_valid(gp) || strata <= 0) return vec3<T>(T(0));
  vpl_sum_state state;
  exhaustive_vpl_patch_sum_range(gp, view, state, 0, view.texel_count(), stream, strata, visibility, dmin,
                                 depth_tolerance);
  return exhaustive_vpl_patch_sum_finish<T>(state, strata);
}

}  // namespace vplkit
