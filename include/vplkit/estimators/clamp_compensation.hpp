// SPDX-License-Identifier: MIT
#pragma once
// Bias compensation for the VPL distance clamp (docs/math.md, "The clamp's compensation"; Kollig & Keller 2004).
// A VPL sample divides by max(d^2, dmin^2): in solid angle at x it carries the unclamped integrand
// times min(1, d^2 / dmin^2), d the distance from x to the VPL's point. What the clamp removes is
// the near field weighted by (1 - d^2 / dmin^2) where d < dmin. This estimator adds it back by
// cosine gathering: each direction omega ~ cos(theta2)/pi is traced to its first hit y, and where
// y lies closer than dmin the direction adds
//     f / p1 * (1 - d^2 / dmin^2) = rho_x L_o(y) (1 - d^2 / dmin^2),   d = |y - x|,
// with the lit test and L_o of gathering (evaluate_gathering_hit's: dprsm_hit_radiance, the DPRSM's
// plane test or the tracer's shadow ray; the shadow ray last, only where the rest is not 0). The two weights sum to 1 at every distance, so
//     clamped VPL estimate + this  ->  the far field of the VPL estimand + the near field of gathering,
// which is the unclamped integral wherever the two estimands agree within dmin of x (math.md,
// "The clamp's compensation" says where they do not). Zero, exactly, where no surface lies within dmin of x along
// a traced direction; zero for dmin = 0 or NaN (no clamp). A negative dmin acts as |dmin|, as
// in the clamp (dmin * dmin); an infinite one turns every VPL off (vpl_geometry_term gives 0) and
// this into plain gathering.
//
// Only the near field is needed, so the rays are short: a tracer with trace_within(x, n_x, dir,
// reach) (visibility_callables.hpp) is asked for hits within |dmin| only; any other tracer traces
// the whole ray, with the same result. Only hits within dmin are looked up (and shadow-tested).
// And most gather points have no other surface within dmin: a tracer with surface_within (the
// triangle voxels) says so once per gather point, and then no direction is traced at all (the
// result is the same 0; the directions' numbers are skipped, not drawn).
// Random numbers: per direction u0, then u1, always (whatever dmin and the hit), as
// estimate_gathering; an invalid gather point gives 0 and draws nothing. The renderer draws them
// from a stream of their own (clamp_compensation_stream), so that turning the compensation on
// leaves the VPL estimator's samples as they were. Never NaN or Inf.
#include <vplkit/core/gather_point.hpp>
#include <vplkit/core/unit_or_zero.hpp>
#include <vplkit/core/vector.hpp>
#include <vplkit/estimators/estimator_state.hpp>
#include <vplkit/estimators/gathering_estimator.hpp>
#include <vplkit/estimators/vpl_sum.hpp>
#include <vplkit/sampling/cosine_hemisphere.hpp>
#include <vplkit/sampling/orthonormal_basis.hpp>
#include <vplkit/sampling/rng.hpp>
#include <vplkit/visibility/light_visibility.hpp>
#include <vplkit/vpl/dprsm_lookup.hpp>
#include <vplkit/vpl/dprsm_patch.hpp>
#include <vplkit/vpl/dprsm_view.hpp>
#include <vplkit/vpl/vpl.hpp>

#include <cmath>
#include <cstdint>
#include <type_traits>
#include <utility>

namespace vplkit {

// Does Tracer offer trace_within(x, n_x, dir, reach) for vectors of T?
template <class Tracer, class T, class = void>
struct tracer_has_trace_within : std::false_type {};
template <class Tracer, class T>
struct tracer_has_trace_within<
    Tracer, T,
    std::void_t<decltype(ray_hit<T>(std::declval<const Tracer&>().trace_within(vec3<T>(), vec3<T>(), vec3<T>(), T())))>>
    : std::true_type {};

// Does Tracer offer surface_within(x, n_x, reach, plane_tolerance) for vectors of T?
template <class Tracer, class T, class = void>
struct tracer_has_surface_within : std::false_type {};
template <class Tracer, class T>
struct tracer_has_surface_within<
    Tracer, T,
    std::void_t<decltype(bool(std::declval<const Tracer&>().surface_within(vec3<T>(), vec3<T>(), T(), T())))>>
    : std::true_type {};

// May a ray from x meet anything within dmin that the compensation counts? False (from the
// tracer's surface_within, where it has one) only when every surface point within |dmin| lies in
// a plane through x, within a quarter of the on-plane rule's tolerance: every direction would add
// 0 (the rule, or no hit within dmin), so none is traced. True otherwise.
template <class T, class Tracer>
inline bool clamp_compensation_may_add(const Tracer& tracer, const gather_point<T>& gp, T dmin) {
  if (!(dmin * dmin > T(0))) return false;
  if constexpr (tracer_has_surface_within<Tracer, T>::value)
    return tracer.surface_within(gp.position, gp.normal, std::abs(dmin),
                                 vpl_coincidence_tolerance(gp.position, gp.position) / T(4));
  else return true;
}

// The first hit of the ray leaving x along dir when it lies within reach of x (else no hit or a
// farther one): trace_within where the tracer has it, else the whole ray.
template <class T, class Tracer>
inline ray_hit<T> trace_ray_within(const Tracer& tracer, vec3<T> x, vec3<T> n_x, vec3<T> dir, T reach) {
  if constexpr (tracer_has_trace_within<Tracer, T>::value) return tracer.trace_within(x, n_x, dir, reach);
  else return tracer(x, n_x, dir);
}

// The compensation's weight at distance^2 d_sq from x: 1 - d^2 / dmin^2 where the clamp is active
// (d^2 < dmin^2), else 0; 0 for dmin^2 = 0 or NaN. The VPL strategy's weight is the clamp itself,
// d^2 / max(d^2, dmin^2): the two sum to 1.
template <class T>
inline T clamp_compensation_weight(T d_sq, T dmin) {
  const T dmin_sq = dmin * dmin;
  if (!(d_sq < dmin_sq)) return T(0);  // also NaN d_sq, dmin^2 = 0 or NaN
  return T(1) - d_sq / dmin_sq;        // dmin^2 = Inf: 1
}

// The compensation's stream for a pixel whose estimator draws from `estimator` (its key only):
// independent of the estimator's numbers, so the clamped estimate is the same with or without it.
inline counter_rng clamp_compensation_stream(const counter_rng& estimator) {
  return counter_rng{rng_key(estimator.key, 0xC1A3C0u), 0u};
}

// What a hit h within dmin of x (its weight `weight` > 0) adds: rho_x L_o(y) times its weight, with
// the lit test and L_o of gathering (evaluate_gathering_hit's values), in the order that leaves the
// lit test's shadow ray for last: it is traced only for a hit whose value would not be 0 (the DPRSM
// texel saw a surface, L_o towards x is not 0 -- the hit's lit side faces x --, and with
// vpl_mode::patch the texel centre's weight is not 0). The result is the same as lit test first;
// the shadow ray is the most expensive part of a direction that hits.
template <class T, class Tracer>
inline vec3<T> clamp_compensation_hit_value(const gather_point<T>& gp, const dprsm_view<T>& view, const ray_hit<T>& h,
                                            T weight, const Tracer& tracer, T dmin, T depth_tolerance,
                                            vpl_mode vmode) {
  const dprsm_lookup_result lk = dprsm_lookup(view, h.position, depth_tolerance);
  // gathering_hit_lookup's condition: where it holds, the shadow ray alone decides the lit test.
  bool shadow_ray = false;
  if constexpr (tracer_has_light_visibility<Tracer, T>::value)
    shadow_ray = tracer.answers_light_visibility() && ray_hit_has_normal(h) && dprsm_texel_saw_surface(view, lk.texel);
  if (!shadow_ray && !lk.lit) return vec3<T>(T(0));
  const vec3<T> radiance = dprsm_hit_radiance(view, lk, gp.position, h, depth_tolerance);
  if (!(radiance.x > T(0) || radiance.y > T(0) || radiance.z > T(0))) return vec3<T>(T(0));
  if (vmode == vpl_mode::patch && dprsm_patch_direction_at_centre(view, lk.texel, h.position)) {
    const vec3<T> wc = view.position[lk.texel] - gp.position;
    weight = clamp_compensation_weight(glm::dot(wc, wc), dmin);
    if (!(weight > T(0))) return vec3<T>(T(0));
  }
  if constexpr (tracer_has_light_visibility<Tracer, T>::value) {
    if (shadow_ray) {
      const vec3<T> c = view.light.position;
      if (!tracer.light_visible(h.position, ray_hit_normal_towards(h, c), c)) return vec3<T>(T(0));
    }
  }
  return estimator_finite_or_zero(gp.albedo * radiance * weight);
}

// Value of one cosine-distributed direction (local: its coordinates in the gather point's ONB):
// rho_x L_o(y) (1 - d^2 / dmin^2) when the first hit y lies within dmin of x, else 0; 0 at or
// below the horizon and below the geometric surface, as gathering_sample. With vpl_mode::patch, d
// is the distance of the VPL strategy's point for y's light direction: y itself, except where that
// direction falls in the part of its texel whose plane points move to the texel centre
// (dprsm_patch_direction_at_centre): there the clamp weighed the centre, so the centre's
// distance decides, and the two weights still sum to 1 per light direction.
template <class T, class Tracer>
inline vec3<T> clamp_compensation_sample(const gather_point<T>& gp, const dprsm_view<T>& view,
                                         const orthonormal_basis<T>& frame, vec3<T> local, const Tracer& tracer,
                                         T dmin, T depth_tolerance, vpl_mode vmode = vpl_mode::point) {
  if (!(dmin * dmin > T(0)) || !(local.z > T(0))) return vec3<T>(T(0));
  const vec3<T> dir = to_world(frame, local);
  if (!gather_point_accepts_direction(gp, dir)) return vec3<T>(T(0));
  const ray_hit<T> h = trace_ray_within(tracer, gp.position, gp.normal, dir, std::abs(dmin));
  if (!h.hit) return vec3<T>(T(0));
  const vec3<T> w = h.position - gp.position;
  const T weight = clamp_compensation_weight(glm::dot(w, w), dmin);
  if (!(weight > T(0))) return vec3<T>(T(0));  // beyond dmin: the VPLs carry it unclamped
  // x on the hit's own plane (within its coordinates' rounding: a crease through x, coincident
  // surfaces) sees that surface edge-on, cos(theta1) = 0 for the VPL strategy: it sends nothing.
  if (vpl_hit_on_own_plane(gp.position, h)) return vec3<T>(T(0));
  return clamp_compensation_hit_value(gp, view, h, weight, tracer, dmin, depth_tolerance, vmode);
}

// Directions [begin, end) of estimate_clamp_compensation (estimator_state.hpp).
template <class T, class Tracer>
inline void estimate_clamp_compensation_range(const gather_point<T>& gp, const dprsm_view<T>& view,
                                              estimator_state<T>& state, int begin, int end, const Tracer& tracer,
                                              T dmin, T depth_tolerance, vpl_mode vmode = vpl_mode::point) {
  if (!gather_point_valid(gp)) return;
  if (begin < end && !clamp_compensation_may_add(tracer, gp, dmin)) {
    state.rng.counter += 2u * std::uint32_t(end - begin);  // the numbers the directions would draw
    return;
  }
  const orthonormal_basis<T> frame = make_orthonormal_basis(gather_point_shading_normal(gp));
  for (int k = begin; k < end; ++k) {
    const T u0 = rng_next_unit<T>(state.rng);
    const T u1 = rng_next_unit<T>(state.rng);
    state.sum += clamp_compensation_sample(gp, view, frame, sample_cosine_hemisphere(vec2<T>(u0, u1)), tracer, dmin,
                                           depth_tolerance, vmode);
  }
}

template <class T>
inline vec3<T> estimate_clamp_compensation_finish(const estimator_state<T>& state, int n_dirs) {
  return n_dirs > 0 ? state.sum / T(n_dirs) : vec3<T>(T(0));
}

// What the clamp at dmin removed from the VPL estimate at gp, estimated with n_dirs directions;
// add it to the clamped estimate of any VPL method (global, local, GBG: vpl_sampling_estimator,
// local_estimator), with that estimate's vpl_mode. depth_tolerance: that of gathering (dprsm_lookup).
template <class T, class Tracer>
inline vec3<T> estimate_clamp_compensation(const gather_point<T>& gp, const dprsm_view<T>& view, counter_rng& rng,
                                           int n_dirs, const Tracer& tracer, T dmin, T depth_tolerance,
                                           vpl_mode vmode = vpl_mode::point) {
  if (!gather_point_valid(gp) || n_dirs <= 0) return vec3<T>(T(0));
  estimator_state<T> state = make_estimator_state<T>(rng);
  estimate_clamp_compensation_range(gp, view, state, 0, n_dirs, tracer, dmin, depth_tolerance, vmode);
  rng = state.rng;
  return estimate_clamp_compensation_finish(state, n_dirs);
}

}  // namespace vplkit
