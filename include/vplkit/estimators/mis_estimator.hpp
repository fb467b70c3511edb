// SPDX-License-Identifier: MIT
#pragma once
// Multiple importance sampling of cosine gathering (strategy 1, n_dirs samples) and VPL sampling
// from a distribution (strategy 2, n_vpls samples) at one gather point (docs/math.md section 5,
// paper section 6).
//   mis_mode::solid_angle (default): both strategies as solid-angle densities at x,
//     p1 = cos(theta2)/pi and p2 = p(t) d2^2 / (A_t cos(theta1)); every sample of either adds
//     balance_combined(f, n_dirs, p1, n_vpls, p2), f = (rho_x/pi) L_o cos(theta2). No dmin clamp;
//     holes are covered by gathering. With vpl_mode::point it converges to the one-bounce integral
//     up to the midpoint-rule error of the VPL term; with vpl_mode::patch (docs/math.md section
//     11) the VPL samples are jittered points of their texels' patches, p2 is the pointwise
//     density p(t) d2^2 / (A(uv) cos(theta1)) of the point itself (a gathering hit is projected
//     into the DPRSM for its texel and uv), and both strategies sample one integral; the parts of
//     patches whose points move to the texel centre (dprsm_patch.hpp) belong to gathering.
//   mis_mode::as_published: the paper's weights and evaluation, literally (eq. 7-15, Alg. 4-6);
//     biased (measured).
// Random numbers: for j < max(n_dirs, n_vpls): if j < n_vpls one u for the VPL (and with
// vpl_mode::patch u0, u1 for its jitter), then if j < n_dirs u0, u1 for the direction. An invalid
// gather point gives 0 and draws nothing; never NaN or Inf. The expectation, both modes in
// detail, the measured bias: docs/api/estimators.md, "MIS".
#include <vplkit/core/gather_point.hpp>
#include <vplkit/core/unit_or_zero.hpp>
#include <vplkit/core/vector.hpp>
#include <vplkit/estimators/estimator_state.hpp>
#include <vplkit/estimators/gathering_estimator.hpp>
#include <vplkit/estimators/vpl_sum.hpp>
#include <vplkit/mis/heuristics.hpp>
#include <vplkit/mis/pdf_conversion.hpp>
#include <vplkit/paraboloid/paraboloid.hpp>
#include <vplkit/paraboloid/texel_grid.hpp>
#include <vplkit/sampling/cosine_hemisphere.hpp>
#include <vplkit/sampling/orthonormal_basis.hpp>
#include <vplkit/sampling/rng.hpp>
#include <vplkit/vpl/dprsm_patch.hpp>
#include <vplkit/vpl/dprsm_view.hpp>
#include <vplkit/vpl/vpl.hpp>

#include <cmath>
#include <cstddef>
#include <limits>

namespace vplkit {

enum class mis_mode { solid_angle, as_published };

// f / (n1 p1 + n2 p2) per channel (balance_combined's values, the denominator formed once; with
// balance_combined's host shortcut where it applies to all three channels).
template <class T>
inline vec3<T> mis_balance_value(vec3<T> f, T n1, T p1, T n2, T p2) {
  if constexpr (detail::mis_host_arithmetic<T>) {
    T d;
    if (detail::balance_denominator_plain(n1, p1, n2, p2, d)) {
      if (!(d > T(0))) return vec3<T>(T(0));
      vec3<T> q;
      if (detail::balance_divide_plain(f.x, d, q.x) && detail::balance_divide_plain(f.y, d, q.y) &&
          detail::balance_divide_plain(f.z, d, q.z))
        return q;
    }
  }
  const mis_balance_denominator<T> den = balance_denominator(n1, p1, n2, p2);
  return vec3<T>(balance_divide(f.x, den), balance_divide(f.y, den), balance_divide(f.z, den));
}

// Area of texel t's patch, A_t = Omega_t d1^2 / cos(alpha), from the texel centre y_t.
template <class T>
inline T mis_texel_patch_area(const dprsm_view<T>& view, int t) {
  const vec3<T> y_t = view.position[t];
  return vpl_patch_area(view.solid_angle(t), scaled_length(y_t - view.light.position),
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

// p2 of docs/math.md section 11 for the point y of texel t's patch seen from x: the texel's pmf
// times the jitter's density at y converted to solid angle at x, pmf d2^2 / (A(uv) cos(theta1))
// with A(uv) = Omega(uv) d1^2 / cos(alpha), everything at y itself: uv where the light sees y,
// d1 = |y - c|, cos(alpha) against n_t, Omega(uv) over t's patch block (a rim texel's point is
// drawn over 2 x 2 texels). For a gathering hit y (which the lookup placed in t, so t owns uv).
template <class T>
inline T mis_patch_vpl_pdf(const dprsm_view<T>& view, int t, T pmf, vec3<T> x, vec3<T> y) {
  const vec3<T> c = view.light.position;
  const vec3<T> n_t = view.normal[t];
  const paraboloid_point<T> q = paraboloid_from_direction(view.light.frame.to_light(y - c));
  const ivec2 xy = texel_coords(t, view.resolution);
  const texel_block block = texel_patch_block(xy.x, xy.y, view.resolution);
  const T area = vpl_patch_area(texel_block_point_solid_angle(q.uv, block, view.resolution), scaled_length(y - c),
                                vpl_cos_alpha(c, y, n_t));
  const vec3<T> w = x - y;
  const T cos1 = glm::dot(unit_or_zero(n_t), unit_or_zero(w));
  return vpl_pdf_solid_angle(pmf, glm::dot(w, w), area, cos1);
}

// Does the light direction of the gathering hit y fall where texel t's patch moves its points to
// the centre? (dprsm_patch_direction_at_centre: MIS gives those directions to gathering alone.)
template <class T>
inline bool mis_patch_hit_at_centre(const dprsm_view<T>& view, int t, vec3<T> y) {
  return dprsm_patch_direction_at_centre(view, t, y);
}

// sin(theta) from cos(theta) as the paper computes it (theta = acos(cos)).
template <class T>
inline T mis_sin_from_cos(T c) {
  const T s2 = T(1) - c * c;
  return s2 > T(0) ? std::sqrt(s2) : T(0);
}

// One gathering sample (local direction in the ONB of n_x); n1 = n_dirs, n2 = n_vpls. A hit on
// x's own plane (a crease through x, coincident surfaces) gives 0, through trace_gathering_ray's
// rule: the VPL strategy reaches no direction into such a surface (its points all lie on a plane
// through x, so it samples only directions within that plane, a set of measure zero), so p2 = 0
// there, gathering's balance weight is 1, and its f is 0: the ray-casting function (first hit at
// t > 0) passes a surface that x lies on. The VPL samples on that surface add 0 too (cos(theta1)
// = 0 at x): both strategies estimate the same integral, without the surface seen edge-on.
template <class T, class Distribution, class Tracer>
inline vec3<T> mis_gathering_sample(const gather_point<T>& gp, const dprsm_view<T>& view,
                                    const Distribution& distribution, const orthonormal_basis<T>& frame,
                                    vec3<T> local, const Tracer& tracer, T depth_tolerance, T n1, T n2,
                                    mis_mode mode, vpl_mode vmode = vpl_mode::point) {
  const T cos2 = local.z;
  if (!(cos2 > T(0))) return vec3<T>(T(0));
  const vec3<T> dir = to_world(frame, local);
  if (!gather_point_accepts_direction(gp, dir)) return vec3<T>(T(0));
  const gathering_ray_result<T> r = trace_gathering_ray(view, gp.position, gp.normal, dir, tracer, depth_tolerance);
  if (!r.lit) return vec3<T>(T(0));
  const vec3<T> f = gp.albedo * r.radiance * (cos2 / vpl_pi<T>);
  const T pmf = estimator_pmf(T(distribution.pmf(std::size_t(r.texel))));
  if (mode == mis_mode::solid_angle) {
    const T p1 = cosine_pdf_solid_angle(cos2);
    // Hits in front of the surface their texel saw (another surface: the VPL strategy's points lie
    // on the texel's plane, behind them) and the parts of patches whose points sit at the centre
    // belong to gathering alone (weight 1): the VPL strategy samples neither.
    if (n1 > T(0) && (r.in_front || (vmode == vpl_mode::patch && mis_patch_hit_at_centre(view, r.texel, r.hit))))
      return mis_balance_value(f, n1, p1, T(0), T(0));
    const T p2 = vmode == vpl_mode::patch ? mis_patch_vpl_pdf(view, r.texel, pmf, gp.position, r.hit)
                                          : mis_vpl_pdf(view, r.texel, pmf, gp.position, r.hit);
    return mis_balance_value(f, n1, p1, n2, p2);
  }
  const T sin2 = mis_sin_from_cos(cos2);
  const T p1 = cosine_pdf_as_published(cos2, sin2);
  if (!(p1 > T(0))) return vec3<T>(T(0));
  const mis_weight_pair<T> w = mis_weights_as_published(cos2, sin2, pmf);
  return estimator_finite_or_zero(f * (w.gathering / p1));
}

// What a VPL sample's value needs of the gather point beyond the point itself: its unit shading
// and geometric normals (unit_or_zero of gather_point_shading_normal and of the normal), computed
// once per point for the many samples evaluated there (RIS candidates) instead of once per sample.
// The same values as the per-sample expressions, so the same bits.
template <class T>
struct mis_receiver {
  vec3<T> shading_unit{T(0)};
  vec3<T> geometric_unit{T(0)};
};

template <class T>
inline mis_receiver<T> make_mis_receiver(const gather_point<T>& gp) {
  return mis_receiver<T>{unit_or_zero(gather_point_shading_normal(gp)), unit_or_zero(gp.normal)};
}

// mis_vpl_unshadowed with gp's unit normals from rx = make_mis_receiver(gp) and the VPL's unit
// normal n_v = unit_or_zero(v.normal) given (for a patch point, its texel's plane record holds
// it): the same expressions, without their normalisations.
template <class T>
inline vec3<T> mis_vpl_unshadowed_unit(const gather_point<T>& gp, const mis_receiver<T>& rx,
                                       const dprsm_view<T>& view, int t, const vpl<T>& v, vec3<T> n_v, T pmf,
                                       T area, T n1, T n2) {
  if (!vpl_has_flux(v)) return vec3<T>(T(0));
  if (vpl_points_coincide(gp.position, v.position)) return vec3<T>(T(0));
  const vec3<T> wd = unit_or_zero(v.position - gp.position);  // x -> y
  const T cos2 = glm::dot(rx.shading_unit, wd);
  const T cos1 = -glm::dot(n_v, wd);
  // gather_point_above(gp, wd), with gp's unit normal from rx.
  if (!(cos2 > T(0)) || !(cos1 > T(0)) || !(glm::dot(rx.geometric_unit, wd) > T(0))) return vec3<T>(T(0));
  const vec3<T> f = gp.albedo *
                    reflected_radiance_unit_normal(view.light.position, view.light.intensity, v.position, n_v,
                                                   view.albedo[t]) *
                    (cos2 / vpl_pi<T>);
  const T p1 = cosine_pdf_solid_angle(cos2);
  const vec3<T> w = gp.position - v.position;
  const T p2 = vpl_pdf_solid_angle(pmf, glm::dot(w, w), area, cos1);
  return mis_balance_value(f, n1, p1, n2, p2);
}

// The solid_angle value of a VPL sample at the VPL v of texel t drawn with probability pmf > 0,
// without its visibility: f at v over n1 p1 + n2 p2, where area is the A of p2 (the texel's A_t
// for a point VPL, A(uv) for a patch point); 0 where v cannot light x (no flux, v at x, either
// cosine not positive, below x's geometric plane). ris_mis_estimator.hpp weighs candidates by it
// (through mis_vpl_unshadowed_unit).
template <class T>
inline vec3<T> mis_vpl_unshadowed(const gather_point<T>& gp, const dprsm_view<T>& view, int t, const vpl<T>& v,
                                  T pmf, T area, T n1, T n2) {
  return mis_vpl_unshadowed_unit(gp, make_mis_receiver(gp), view, t, v, unit_or_zero(v.normal), pmf, area, n1, n2);
}

// The value of a VPL sample at the VPL v of texel t, drawn with probability pmf > 0; area is the
// A of its p2. solid_angle: mis_vpl_unshadowed times V(x, v), queried only where that is not 0;
// as_published: the paper's weights at (direction to v, pmf) times L_v V / pmf.
template <class T, class Visibility>
inline vec3<T> mis_vpl_value(const gather_point<T>& gp, const dprsm_view<T>& view, int t, const vpl<T>& v, T pmf,
                             T area, const Visibility& visibility, T n1, T n2, mis_mode mode) {
  if (mode == mis_mode::as_published) {
    const vec3<T> c = vpl_contribution(gp, v, T(0));
    if (!(c.x > T(0) || c.y > T(0) || c.z > T(0))) return vec3<T>(T(0));
    if (!visibility(gp.position, gp.normal, v.position, v.normal)) return vec3<T>(T(0));
    const T cos2 = glm::dot(unit_or_zero(gather_point_shading_normal(gp)), unit_or_zero(v.position - gp.position));
    const mis_weight_pair<T> w = mis_weights_as_published(cos2, mis_sin_from_cos(cos2), pmf);
    return estimator_finite_or_zero(c * (w.vpl / pmf));
  }
  const vec3<T> value = mis_vpl_unshadowed(gp, view, t, v, pmf, area, n1, n2);
  if (!(value.x > T(0) || value.y > T(0) || value.z > T(0))) return vec3<T>(T(0));
  if (!visibility(gp.position, gp.normal, v.position, v.normal)) return vec3<T>(T(0));
  return value;
}

// One VPL sample drawn with u (vpl_mode::point: the VPL at the texel centre).
template <class T, class Distribution, class Visibility>
inline vec3<T> mis_vpl_sample(const gather_point<T>& gp, const dprsm_view<T>& view,
                              const Distribution& distribution, T u, const Visibility& visibility, T n1, T n2,
                              mis_mode mode) {
  const auto s = distribution.sample(u);
  const T pmf = estimator_pmf(T(s.pmf));
  if (!(pmf > T(0)) || s.index >= std::size_t(view.texel_count())) return vec3<T>(T(0));
  const int t = int(s.index);
  return mis_vpl_value(gp, view, t, view.vpl_at(t), pmf, mis_texel_patch_area(view, t), visibility, n1, n2,
                       mode);
}

// One patch-sampled VPL sample drawn with u and jittered by xi: dprsm_patch_vpl with the lookup's
// depth_tolerance, so that it samples exactly the points the gathering strategy counts as lit,
// and p2 from the sampled point's own Omega(uv), d1 and cos(alpha).
template <class T, class Distribution, class Visibility>
inline vec3<T> mis_vpl_patch_sample(const gather_point<T>& gp, const dprsm_view<T>& view,
                                    const Distribution& distribution, T u, vec2<T> xi, const Visibility& visibility,
                                    T n1, T n2, mis_mode mode, T depth_tolerance) {
  const auto s = distribution.sample(u);
  const T pmf = estimator_pmf(T(s.pmf));
  if (!(pmf > T(0)) || s.index >= std::size_t(view.texel_count())) return vec3<T>(T(0));
  const int t = int(s.index);
  const dprsm_patch_sample<T> p = dprsm_patch_vpl(view, t, xi, depth_tolerance);
  // A point moved to the centre stands for directions that gathering covers alone (weight 0 here),
  // unless no direction is traced (n1 = 0: plain VPL sampling, f / (n2 p2) with A(uv) at y_t, its
  // flux's contribution over n2 pmf). Weight 1 for the moved points instead would bring back the
  // VPL strategy's 1/d2^2 at creases, where receivers sit next to the texel centres (fireflies).
  if (p.at_centre && n1 > T(0)) return vec3<T>(T(0));
  return mis_vpl_value(gp, view, t, p.point, pmf, vpl_patch_area(p.solid_angle, p.distance, p.cos_alpha),
                       visibility, n1, n2, mode);
}

// Steps [begin, end) of estimate_mis (estimator_state.hpp); step j draws VPL j (j < n_vpls), then
// direction j (j < n_dirs), so the steps run to max(n_dirs, n_vpls). Negative counts count as 0.
template <class T, class Distribution, class Tracer, class Visibility>
inline void estimate_mis_range(const gather_point<T>& gp, const dprsm_view<T>& view,
                               const Distribution& distribution, estimator_state<T>& state, int begin, int end,
                               int n_dirs, int n_vpls, const Tracer& tracer, const Visibility& visibility,
                               T depth_tolerance, mis_mode mode = mis_mode::solid_angle,
                               vpl_mode vmode = vpl_mode::point) {
  if (!gather_point_valid(gp)) return;
  if (n_dirs < 0) n_dirs = 0;
  if (n_vpls < 0) n_vpls = 0;
  const T n1 = T(n_dirs), n2 = T(n_vpls);
  const orthonormal_basis<T> frame = make_orthonormal_basis(gather_point_shading_normal(gp));
  for (int j = begin; j < end; ++j) {
    if (j < n_vpls) {
      const T u = rng_next_unit<T>(state.rng);
      if (vmode == vpl_mode::patch) {
        const T u0 = rng_next_unit<T>(state.rng);
        const T u1 = rng_next_unit<T>(state.rng);
        state.sum += mis_vpl_patch_sample(gp, view, distribution, u, vec2<T>(u0, u1), visibility, n1, n2, mode,
                                          depth_tolerance);
      } else {
        state.sum += mis_vpl_sample(gp, view, distribution, u, visibility, n1, n2, mode);
      }
    }
    if (j < n_dirs) {
      const T u0 = rng_next_unit<T>(state.rng);
      const T u1 = rng_next_unit<T>(state.rng);
      state.sum += mis_gathering_sample(gp, view, distribution, frame, sample_cosine_hemisphere(vec2<T>(u0, u1)),
                                        tracer, depth_tolerance, n1, n2, mode, vmode);
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
                            mis_mode mode = mis_mode::solid_angle, vpl_mode vmode = vpl_mode::point) {
  if (!gather_point_valid(gp)) return vec3<T>(T(0));
  if (n_dirs < 0) n_dirs = 0;
  if (n_vpls < 0) n_vpls = 0;
  if (n_dirs == 0 && n_vpls == 0) return vec3<T>(T(0));
  estimator_state<T> state = make_estimator_state<T>(rng);
  estimate_mis_range(gp, view, distribution, state, 0, n_dirs > n_vpls ? n_dirs : n_vpls, n_dirs, n_vpls,
                     tracer, visibility, depth_tolerance, mode, vmode);
  rng = state.rng;
  return estimate_mis_finish(state, n_dirs, n_vpls, mode);
}

}  // namespace vplkit
