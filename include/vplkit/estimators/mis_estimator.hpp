#pragma once
// Multiple importance sampling of cosine gathering (strategy 1, n_dirs samples) and VPL sampling
// from a distribution (strategy 2, n_vpls samples) at one gather point (docs/math.md section 5,
// paper section 6).
//   mis_mode::solid_angle (default): both strategies as solid-angle densities at x,
//     p1 = cos(theta2)/pi and p2 = p(t) d2^2 / (A_t cos(theta1)); every sample of either adds
//     balance_combined(f, n_dirs, p1, n_vpls, p2), f = (rho_x/pi) L_o cos(theta2). No dmin clamp;
//     holes are covered by gathering. Converges to the one-bounce integral up to the midpoint-rule
//     error of the VPL term.
//   mis_mode::as_published: the paper's weights and evaluation, literally (eq. 7-15, Alg. 4-6);
//     biased (measured).
// Random numbers: for j < max(n_dirs, n_vpls): if j < n_vpls one u for the VPL, then if
// j < n_dirs u0, u1 for the direction. An invalid gather point gives 0 and draws nothing; never
// NaN or Inf. The expectation, both modes in detail, the measured bias: docs/api/estimators.md, "MIS".
#include <vplkit/core/gather_point.hpp>
#include <vplkit/core/unit_or_zero.hpp>
#include <vplkit/core/vector.hpp>
#include <vplkit/estimators/estimator_state.hpp>
#include <vplkit/estimators/gathering_estimator.hpp>
#include <vplkit/estimators/vpl_sum.hpp>
#include <vplkit/mis/heuristics.hpp>
#include <vplkit/mis/pdf_conversion.hpp>
#include <vplkit/sampling/cosine_hemisphere.hpp>
#include <vplkit/sampling/orthonormal_basis.hpp>
#include <vplkit/sampling/rng.hpp>
#include <vplkit/vpl/dprsm_view.hpp>
#include <vplkit/vpl/vpl.hpp>

#include <cmath>
#include <cstddef>

namespace vplkit {

enum class mis_mode { solid_angle, as_published };

// f / (n1 p1 + n2 p2) per channel (balance_combined).
template <class T>
inline vec3<T> mis_balance_value(vec3<T> f, T n1, T p1, T n2, T p2) {
  return vec3<T>(balance_combined(f.x, n1, p1, n2, p2), balance_combined(f.y, n1, p1, n2, p2),
                 balance_combined(f.z, n1, p1, n2, p2));
}

// Area of texel t's patch, A_t = Omega_t d1^2 / cos(alpha), from the texel centre y_t.
template <class T>
inline T mis_texel_patch_area(const dprsm_view<T>& view, int t) {
  const vec3<T> y_t = view.position[t];
  return vpl_patch_area(view.solid_angle(t), glm::length(y_t - view.light.position),
                        vpl_cos_alpha(view.light.position, y_t, view.normal[t]));
}

// p2 of docs/math.md section 5 for the point y on texel t's patch seen from x:
// pmf d2^2 / (A_t cos(theta1)).
template <class T>
inline T mis_vpl_pdf(const dprsm_view<T>& view, int t, T pmf, vec3<T> x, vec3<T> y) {
  const vec3<T> w = x - y;
  const T cos1 = glm::dot(unit_or_zero(view.normal[t]), unit_or_zero(w));
  return vpl_pdf_solid_angle(pmf, glm::dot(w, w), mis_texel_patch_area(view, t), cos1);
}

// sin(theta) from cos(theta) as the paper computes it (theta = acos(cos)).
template <class T>
inline T mis_sin_from_cos(T c) {
  const T s2 = T(1) - c * c;
  return s2 > T(0) ? std::sqrt(s2) : T(0);
}

// One gathering sample (local direction in the ONB of n_x); n1 = n_dirs, n2 = n_vpls.
template <class T, class Distribution, class Tracer>
inline vec3<T> mis_gathering_sample(const gather_point<T>& gp, const dprsm_view<T>& view,
                                    const Distribution& distribution, const orthonormal_basis<T>& frame,
                                    vec3<T> local, const Tracer& tracer, T depth_tolerance, T n1, T n2,
                                    mis_mode mode) {
  const T cos2 = local.z;
  if (!(cos2 > T(0))) return vec3<T>(T(0));
  const gathering_ray_result<T> r =
      trace_gathering_ray(view, gp.position, gp.normal, to_world(frame, local), tracer, depth_tolerance);
  if (!r.lit) return vec3<T>(T(0));
  const vec3<T> f = gp.albedo * r.radiance * (cos2 / vpl_pi<T>);
  const T pmf = T(distribution.pmf(std::size_t(r.texel)));
  if (mode == mis_mode::solid_angle) {
    const T p1 = cosine_pdf_solid_angle(cos2);
    const T p2 = mis_vpl_pdf(view, r.texel, pmf, gp.position, r.hit);
    return mis_balance_value(f, n1, p1, n2, p2);
  }
  const T sin2 = mis_sin_from_cos(cos2);
  const T p1 = cosine_pdf_as_published(cos2, sin2);
  if (!(p1 > T(0))) return vec3<T>(T(0));
  const mis_weight_pair<T> w = mis_weights_as_published(cos2, sin2, pmf);
  return estimator_finite_or_zero(f * (w.gathering / p1));
}

// One VPL sample drawn with u.
template <class T, class Distribution, class Visibility>
inline vec3<T> mis_vpl_sample(const gather_point<T>& gp, const dprsm_view<T>& view,
                              const Distribution& distribution, T u, const Visibility& visibility, T n1, T n2,
                              mis_mode mode) {
  const auto s = distribution.sample(u);
  const T pmf = T(s.pmf);
  if (!(pmf > T(0)) || s.index >= std::size_t(view.texel_count())) return vec3<T>(T(0));
  const int t = int(s.index);
  if (mode == mis_mode::as_published) {
    const vec3<T> c = vpl_visible_contribution(gp, view, t, visibility, T(0));
    if (!(c.x > T(0) || c.y > T(0) || c.z > T(0))) return vec3<T>(T(0));
    const T cos2 = glm::dot(unit_or_zero(gp.normal), unit_or_zero(view.position[t] - gp.position));
    const mis_weight_pair<T> w = mis_weights_as_published(cos2, mis_sin_from_cos(cos2), pmf);
    return estimator_finite_or_zero(c * (w.vpl / pmf));
  }
  const vpl<T> v = view.vpl_at(t);
  if (!vpl_has_flux(v)) return vec3<T>(T(0));
  if (vpl_points_coincide(gp.position, v.position)) return vec3<T>(T(0));
  const vec3<T> wd = unit_or_zero(v.position - gp.position);  // x -> y_t
  const T cos2 = glm::dot(unit_or_zero(gp.normal), wd);
  const T cos1 = -glm::dot(unit_or_zero(v.normal), wd);
  if (!(cos2 > T(0)) || !(cos1 > T(0))) return vec3<T>(T(0));
  if (!visibility(gp.position, gp.normal, v.position, v.normal)) return vec3<T>(T(0));
  const vec3<T> f = gp.albedo *
                    reflected_radiance(view.light.position, view.light.intensity, v.position, v.normal,
                                       view.albedo[t]) *
                    (cos2 / vpl_pi<T>);
  const T p1 = cosine_pdf_solid_angle(cos2);
  const T p2 = mis_vpl_pdf(view, t, pmf, gp.position, v.position);
  return mis_balance_value(f, n1, p1, n2, p2);
}

// Steps [begin, end) of estimate_mis (estimator_state.hpp); step j draws VPL j (j < n_vpls), then
// direction j (j < n_dirs), so the steps run to max(n_dirs, n_vpls). Negative counts count as 0.
template <class T, class Distribution, class Tracer, class Visibility>
inline void estimate_mis_range(const gather_point<T>& gp, const dprsm_view<T>& view,
                               const Distribution& distribution, estimator_state<T>& state, int begin, int end,
                               int n_dirs, int n_vpls, const Tracer& tracer, const Visibility& visibility,
                               T depth_tolerance, mis_mode mode = mis_mode::solid_angle) {
  if (!gather_point_valid(gp)) return;
  if (n_dirs < 0) n_dirs = 0;
  if (n_vpls < 0) n_vpls = 0;
  const T n1 = T(n_dirs), n2 = T(n_vpls);
  const orthonormal_basis<T> frame = make_orthonormal_basis(gp.normal);
  for (int j = begin; j < end; ++j) {
    if (j < n_vpls)
      state.sum += mis_vpl_sample(gp, view, distribution, rng_next_unit<T>(state.rng), visibility, n1, n2, mode);
    if (j < n_dirs) {
      const T u0 = rng_next_unit<T>(state.rng);
      const T u1 = rng_next_unit<T>(state.rng);
      state.sum += mis_gathering_sample(gp, view, distribution, frame, sample_cosine_hemisphere(vec2<T>(u0, u1)),
                                        tracer, depth_tolerance, n1, n2, mode);
    }
  }
}

// solid_angle: the 1/n_i are inside balance_combined. as_published: Alg. 4 divides by NBDIR.
template <class T>
inline vec3<T> estimate_mis_finish(const estimator_state<T>& state, int n_dirs, int n_vpls,
                                   mis_mode mode = mis_mode::solid_angle) {
  if (n_dirs < 0) n_dirs = 0;
  if (n_vpls < 0) n_vpls = 0;
  if (n_dirs == 0 && n_vpls == 0) return vec3<T>(T(0));
  if (mode == mis_mode::as_published) return state.sum / T(n_dirs > 0 ? n_dirs : n_vpls);
  return state.sum;
}

template <class T, class Distribution, class Tracer, class Visibility>
inline vec3<T> estimate_mis(const gather_point<T>& gp, const dprsm_view<T>& view, const Distribution& distribution,
                            counter_rng& rng, int n_dirs, int n_vpls, const Tracer& tracer,
                            const Visibility& visibility, T depth_tolerance,
                            mis_mode mode = mis_mode::solid_angle) {
  if (!gather_point_valid(gp)) return vec3<T>(T(0));
  if (n_dirs < 0) n_dirs = 0;
  if (n_vpls < 0) n_vpls = 0;
  if (n_dirs == 0 && n_vpls == 0) return vec3<T>(T(0));
  estimator_state<T> state = make_estimator_state<T>(rng);
  estimate_mis_range(gp, view, distribution, state, 0, n_dirs > n_vpls ? n_dirs : n_vpls, n_dirs, n_vpls,
                     tracer, visibility, depth_tolerance, mode);
  rng = state.rng;
  return estimate_mis_finish(state, n_dirs, n_vpls, mode);
}

}  // namespace vplkit
