#pragma once
// The exhaustive VPL sum L(x) = sum_t L_t(x) V(x, y_t) (docs/math.md section 2): the estimand of
// every CDF method and their reference (feasible for small DPRSMs; O(2 R^2) visibility queries).
#include <vplkit/core/gather_point.hpp>
#include <vplkit/core/vector.hpp>
#include <vplkit/vpl/dprsm_view.hpp>
#include <vplkit/vpl/vpl.hpp>

#include <cmath>
#include <limits>

namespace vplkit {

// v when every component is finite, else 0: the last guard of every estimator's per-sample value.
template <class T>
inline vec3<T> estimator_finite_or_zero(vec3<T> v) {
  const T big = std::numeric_limits<T>::max();
  const bool ok = std::abs(v.x) <= big && std::abs(v.y) <= big && std::abs(v.z) <= big;  // NaN fails
  return ok ? v : vec3<T>(T(0));
}

// L_t(x) V(x, y_t) for texel t: 0 for an index outside the view, a texel without flux, or a
// back-facing pair; visibility is queried only when the unoccluded contribution is non-zero (so a
// ray is spent only where it can matter). The per-sample term of every VPL-sampling estimator.
template <class T, class Visibility>
inline vec3<T> vpl_visible_contribution(const gather_point<T>& gp, const dprsm_view<T>& view, int t,
                                        const Visibility& visibility, T dmin) {
  if (t < 0 || t >= view.texel_count()) return vec3<T>(T(0));
  const vpl<T> v = view.vpl_at(t);
  const vec3<T> c = vpl_contribution(gp.position, gp.normal, gp.albedo, v, dmin);
  if (!(c.x > T(0) || c.y > T(0) || c.z > T(0))) return vec3<T>(T(0));
  return visibility(gp.position, gp.normal, v.position, v.normal) ? c : vec3<T>(T(0));
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

}  // namespace vplkit
