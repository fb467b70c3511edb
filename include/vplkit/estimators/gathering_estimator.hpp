// SPDX-License-Identifier: MIT
#pragma once
// Cosine gathering through the DPRSM (docs/math.md section 5, strategy 1; the paper's Alg. 5
// without MIS): directions omega ~ cos(theta2)/pi around n_x are traced to their first hit y; y is
// lit when the DPRSM texel it projects into saw a surface at y's depth (dprsm_lookup within
// depth_tolerance), and each direction adds f / p1 = rho_x L_o(y), with L_o evaluated at y with the
// texel's normal and albedo (0 seen from behind: one-sided emission; 0 for a hit on x's own plane,
// vpl_hit_on_own_plane: a crease through x, seen edge-on). Converges to the one-bounce
// integral as the DPRSM sees it, not to the VPL sum (docs/math.md section 8).
// Random numbers: per direction u0, then u1 (estimator_state.hpp for the range form). An invalid
// gather point gives 0 and draws nothing. What is known at the hit, choosing the depth tolerance:
// docs/api/estimators.md, "Gathering".
#include <vplkit/core/gather_point.hpp>
#include <vplkit/core/vector.hpp>
#include <vplkit/estimators/estimator_state.hpp>
#include <vplkit/estimators/vpl_sum.hpp>
#include <vplkit/sampling/cosine_hemisphere.hpp>
#include <vplkit/sampling/orthonormal_basis.hpp>
#include <vplkit/sampling/rng.hpp>
#include <vplkit/visibility/light_visibility.hpp>
#include <vplkit/vpl/dprsm_lookup.hpp>
#include <vplkit/vpl/dprsm_view.hpp>
#include <vplkit/vpl/vpl.hpp>

namespace vplkit {

// What one gathering ray found.
template <class T>
struct gathering_ray_result {
  bool lit = false;          // hit, projected into a texel that saw it, seen from its lit side
  bool in_front = false;     // lit, in front of the surface its texel saw (dprsm_lookup_result)
  int texel = -1;            // the DPRSM texel the hit projects into (-1: no hit / at the light /
                             // a hit on x's own plane, trace_gathering_ray)
  vec3<T> hit{T(0)};         // y (valid when texel >= 0)
  vec3<T> radiance{T(0)};    // L_o(y) towards x; 0 unless lit
};

// The texel a gathering hit projects into and whether the light reaches it: the DPRSM's plane test
// within depth_tolerance (dprsm_lookup), or, where the tracer answers shadow rays
// (light_visibility.hpp) and knows the hit's surface, that shadow ray; in_front stays the plane's
// verdict (MIS gives such hits to gathering alone), and only lit hits are in front.
template <class T, class Tracer>
inline dprsm_lookup_result gathering_hit_lookup(const dprsm_view<T>& view, const ray_hit<T>& h, const Tracer& tracer,
                                                T depth_tolerance) {
  dprsm_lookup_result lk = dprsm_lookup(view, h.position, depth_tolerance);
  if constexpr (tracer_has_light_visibility<Tracer, T>::value) {
    if (tracer.answers_light_visibility() && ray_hit_has_normal(h) && dprsm_texel_saw_surface(view, lk.texel)) {
      const vec3<T> c = view.light.position;
      lk.lit = tracer.light_visible(h.position, ray_hit_normal_towards(h, c), c);
      lk.in_front = lk.in_front && lk.lit;
    }
  }
  return lk;
}

// What the hit h of a ray leaving x sends towards x: the lookup and L_o (no hit: nothing). Shared by
// trace_gathering_ray and the clamp compensation (clamp_compensation.hpp), which traces its own rays.
template <class T, class Tracer>
inline gathering_ray_result<T> evaluate_gathering_hit(const dprsm_view<T>& view, vec3<T> x, const ray_hit<T>& h,
                                                      const Tracer& tracer, T depth_tolerance) {
  gathering_ray_result<T> r;
  if (!h.hit) return r;
  const dprsm_lookup_result lk = gathering_hit_lookup(view, h, tracer, depth_tolerance);
  r.texel = lk.texel;
  r.hit = h.position;
  if (!lk.lit) return r;
  r.radiance = dprsm_hit_radiance(view, lk, x, h, depth_tolerance);
  r.lit = r.radiance.x > T(0) || r.radiance.y > T(0) || r.radiance.z > T(0);
  r.in_front = r.lit && lk.in_front;
  return r;
}

// Traces the ray leaving surface x (normal n_x, any length) along dir and evaluates L_o at the hit.
// A hit on x's own plane (vpl_hit_on_own_plane: a crease through x, coincident surfaces) sends
// nothing and reads as no hit (texel -1): the tracer's lifted origin met a surface that x sees
// edge-on. This is the rule of every gathering strategy (gathering, MIS's gathering half, the
// clamp's compensation, the GBG weights; docs/math.md, "The clamp's compensation").
template <class T, class Tracer>
inline gathering_ray_result<T> trace_gathering_ray(const dprsm_view<T>& view, vec3<T> x, vec3<T> n_x,
                                                   vec3<T> dir, const Tracer& tracer, T depth_tolerance) {
  const ray_hit<T> h = tracer(x, n_x, dir);
  if (vpl_hit_on_own_plane(x, h)) return gathering_ray_result<T>{};
  return evaluate_gathering_hit(view, x, h, tracer, depth_tolerance);
}

// Value of one cosine-distributed direction (local: its coordinates in the gather point's ONB):
// f / p1 = rho_x L_o(y) (the cos(theta2)/pi of f and p1 cancel); 0 at or below the horizon, and
// 0 below the geometric surface (the frame is the shading normal's; docs/math.md section 12).
template <class T, class Tracer>
inline vec3<T> gathering_sample(const gather_point<T>& gp, const dprsm_view<T>& view,
                                const orthonormal_basis<T>& frame, vec3<T> local, const Tracer& tracer,
                                T depth_tolerance) {
  if (!(local.z > T(0))) return vec3<T>(T(0));
  const vec3<T> dir = to_world(frame, local);
  if (!gather_point_accepts_direction(gp, dir)) return vec3<T>(T(0));
  const gathering_ray_result<T> r = trace_gathering_ray(view, gp.position, gp.normal, dir, tracer, depth_tolerance);
  return estimator_finite_or_zero(gp.albedo * r.radiance);
}

// Directions [begin, end) of estimate_gathering (estimator_state.hpp).
template <class T, class Tracer>
inline void estimate_gathering_range(const gather_point<T>& gp, const dprsm_view<T>& view,
                                     estimator_state<T>& state, int begin, int end, const Tracer& tracer,
                                     T depth_tolerance) {
  if (!gather_point_valid(gp)) return;
  const orthonormal_basis<T> frame = make_orthonormal_basis(gather_point_shading_normal(gp));
  for (int k = begin; k < end; ++k) {
    const T u0 = rng_next_unit<T>(state.rng);
    const T u1 = rng_next_unit<T>(state.rng);
    state.sum += gathering_sample(gp, view, frame, sample_cosine_hemisphere(vec2<T>(u0, u1)), tracer,
                                  depth_tolerance);
  }
}

template <class T>
inline vec3<T> estimate_gathering_finish(const estimator_state<T>& state, int n_dirs) {
  return n_dirs > 0 ? state.sum / T(n_dirs) : vec3<T>(T(0));
}

template <class T, class Tracer>
inline vec3<T> estimate_gathering(const gather_point<T>& gp, const dprsm_view<T>& view, counter_rng& rng,
                                  int n_dirs, const Tracer& tracer, T depth_tolerance) {
  if (!gather_point_valid(gp) || n_dirs <= 0) return vec3<T>(T(0));
  estimator_state<T> state = make_estimator_state<T>(rng);
  estimate_gathering_range(gp, view, state, 0, n_dirs, tracer, depth_tolerance);
  rng = state.rng;
  return estimate_gathering_finish(state, n_dirs);
}

}  // namespace vplkit
