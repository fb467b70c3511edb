// SPDX-License-Identifier: MIT
// docs/math.md section 10 for the clamp compensation (estimators/clamp_compensation.hpp), each case
// its own test: a gather point on a VPL, coincident surfaces and a crease through the gather point,
// grazing directions, dmin = 0 and the other special clamps, NaN and Inf inputs (gather point, hit,
// direction, depth tolerance, light). Never NaN, Inf or a negative value; where the case has a
// right answer, that answer.
#include <estimator_checks.hpp>
#include <synthetic_scene.hpp>

#include <vplkit/estimators/clamp_compensation.hpp>
#include <vplkit/estimators/gathering_estimator.hpp>
#include <vplkit/visibility/light_visibility.hpp>
#include <vplkit/vpl/dprsm_patch.hpp>
#include <vplkit/vpl/luminance.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <vector>

using namespace vplkit;
using namespace vplkit_test;

namespace {

// A tracer that reports one fixed hit for every ray (normal zero: a voxel-entry point).
template <class T>
struct fixed_hit_tracer {
  ray_hit<T> h;
  ray_hit<T> operator()(vec3<T>, vec3<T>, vec3<T>) const { return h; }
};

// The compensation at gp with n directions from a fixed stream.
template <class T, class Tracer>
vec3<T> compensation(const gather_point<T>& gp, const dprsm_view<T>& view, const Tracer& tracer, T dmin,
                     T tol = T(0), int n = 64) {
  counter_rng rng = make_counter_rng(11u, 7u);
  return estimate_clamp_compensation(gp, view, rng, n, tracer, dmin, tol);
}

// Upper bound of one direction's value at gp: rho_x times the brightest L_o of a lit point at least
// `d1` from the light (rho_t <= 1, cos <= 1).
template <class T>
T radiance_bound(const gather_point<T>& gp, const dprsm_view<T>& view, T d1) {
  const vec3<T> I = view.light.intensity;
  return glm::max(glm::max(gp.albedo.x, gp.albedo.y), gp.albedo.z) * glm::max(glm::max(I.x, I.y), I.z) /
         (vpl_pi<T> * d1 * d1);
}

}  // namespace

TEMPLATE_TEST_CASE("clamp compensation hard case: the gather point on a VPL", "[hardcases]", float, double) {
  using T = TestType;
  const lit_room<T> room(32);
  const auto tracer = with_light_visibility(room.tracer, room.vis);
  int tested = 0;
  for (int t = 0; t < room.view.texel_count() && tested < 40; t += 97) {
    if (!vpl_has_flux(room.view.vpl_at(t))) continue;
    for (const vec2<T>& xi : {vec2<T>(T(0.5)), vec2<T>(T(0.1), T(0.9))}) {
      const dprsm_patch_sample<T> p = dprsm_patch_vpl(room.view, t, xi, T(0));
      const vec3<T> n = glm::normalize(p.point.normal);
      for (const gather_point<T>& gp : {gather_point<T>{room.view.position[t], n, vec3<T>(T(0.6))},
                                       gather_point<T>{p.point.position, n, vec3<T>(T(0.6))}}) {
        const vec3<T> k = compensation(gp, room.view, tracer, T(0.5));
        INFO("texel " << t);
        CHECK(finite_nonneg(k));
        // the light is 0.3 or more from every surface of the room
        CHECK(luminance(k) <= radiance_bound(gp, room.view, T(0.3)));
        ++tested;
      }
    }
  }
  CHECK(tested >= 40);
}

TEMPLATE_TEST_CASE("clamp compensation hard case: a hit on the gather point's own plane sends nothing", "[hardcases]",
                   float, double) {
  using T = TestType;
  // Coincident surfaces (a second floor in the first's plane), and a crease through x (x on the
  // wall's plane, as a G-buffer point exactly on the edge): the hit lies in a plane through x,
  // seen edge-on; every such hit adds 0, however close, while a hit just off that plane counts.
  const lit_room<T> room(32);
  const vec3<T> up(T(0), T(1), T(0));
  const gather_point<T> gp{vec3<T>(T(1.2), T(0), T(1.0)), up, vec3<T>(T(0.7))};
  ray_hit<T> coincident;
  coincident.hit = true;
  coincident.position = gp.position + vec3<T>(T(1e-3), T(0), T(0));
  coincident.normal = up;  // the floor's plane, through x
  const auto on_plane = with_light_visibility(fixed_hit_tracer<T>{coincident}, room.vis);
  CHECK(compensation(gp, room.view, on_plane, T(0.5)) == vec3<T>(T(0)));
  ray_hit<T> crease = coincident;
  crease.normal = vec3<T>(T(1), T(0), T(0));  // a wall x = 1.2 + 1e-3 ... through x: x on it too
  crease.position = gp.position + vec3<T>(T(0), T(1e-3), T(1e-3));
  CHECK(compensation(gp, room.view, with_light_visibility(fixed_hit_tracer<T>{crease}, room.vis), T(0.5)) ==
        vec3<T>(T(0)));
  // the same wall 1e-3 beyond x: a real near field, counted
  ray_hit<T> wall = crease;
  wall.position = gp.position + vec3<T>(T(1e-3), T(1e-3), T(0));
  wall.normal = vec3<T>(T(-1), T(0), T(0));
  const vec3<T> k = compensation(gp, room.view, with_light_visibility(fixed_hit_tracer<T>{wall}, room.vis), T(0.5));
  CHECK(finite_nonneg(k));
  CHECK(luminance(k) > T(0));
}

TEMPLATE_TEST_CASE("clamp compensation hard case: grazing directions and a gather point grazing a wall", "[hardcases]",
                   float, double) {
  using T = TestType;
  const lit_room<T> room(32);
  const auto tracer = with_light_visibility(room.tracer, room.vis);
  // directions within 1e-6 of the horizon, from a floor point 0.01 from the red wall
  const gather_point<T> gp{vec3<T>(T(-1.99), T(0), T(0.5)), vec3<T>(T(0), T(1), T(0)), vec3<T>(T(0.7))};
  const orthonormal_basis<T> frame = make_orthonormal_basis(gp.normal);
  for (const T z : {T(0), T(1e-7), T(1e-6), T(1e-4)})
    for (int k = 0; k < 16; ++k) {
      const T a = T(2) * vpl_pi<T> * T(k) / T(16), r = std::sqrt(glm::max(T(0), T(1) - z * z));
      const vec3<T> v = clamp_compensation_sample(gp, room.view, frame, vec3<T>(r * std::cos(a), r * std::sin(a), z),
                                                  tracer, T(0.3), T(0));
      INFO("z " << z << " azimuth " << a);
      CHECK(finite_nonneg(v));
      if (z == T(0)) CHECK(v == vec3<T>(T(0)));  // on the horizon: no direction
    }
  // normals tilted to within 1e-6 of the wall's plane, and a shading normal far from the geometric one
  for (const T tilt : {T(1e-6), T(1e-3), T(0.3)}) {
    const gather_point<T> g{vec3<T>(T(-1.99), T(0), T(0.5)), vec3<T>(-T(1), tilt, T(0)), vec3<T>(T(0.7)),
                            vec3<T>(T(1), T(1), T(0))};
    INFO("tilt " << tilt);
    CHECK(finite_nonneg(compensation(g, room.view, tracer, T(0.3))));
  }
}

TEMPLATE_TEST_CASE("clamp compensation hard case: dmin = 0, denormal, negative, huge, infinite and NaN", "[hardcases]",
                   float, double) {
  using T = TestType;
  const lit_room<T> room(32);
  const auto tracer = with_light_visibility(room.tracer, room.vis);
  const T inf = std::numeric_limits<T>::infinity(), nan = std::numeric_limits<T>::quiet_NaN();
  for (const auto& g : room.gps) {
    INFO(g.name);
    CHECK(compensation(g.gp, room.view, tracer, T(0)) == vec3<T>(T(0)));
    CHECK(compensation(g.gp, room.view, tracer, nan) == vec3<T>(T(0)));
    CHECK(compensation(g.gp, room.view, tracer, std::numeric_limits<T>::denorm_min()) == vec3<T>(T(0)));
    // the clamp squares dmin: a negative one acts as its absolute value
    CHECK(compensation(g.gp, room.view, tracer, T(-0.5)) == compensation(g.gp, room.view, tracer, T(0.5)));
    // dmin^2 = Inf (an infinite dmin, or one whose square overflows): every VPL contributes 0 and the
    // compensation is plain gathering, with the same stream
    counter_rng a = make_counter_rng(11u, 7u), b = a;
    const vec3<T> gather = estimate_gathering(g.gp, room.view, a, 64, tracer, T(0));
    CHECK(compensation(g.gp, room.view, tracer, inf) == gather);
    CHECK(compensation(g.gp, room.view, tracer, std::numeric_limits<T>::max()) == gather);
    CHECK(vpl_contribution(g.gp, room.view.vpl_at(100), inf) == vec3<T>(T(0)));
    (void)b;
  }
}

TEMPLATE_TEST_CASE("clamp compensation hard case: NaN and Inf inputs give 0 or a finite value", "[hardcases]", float,
                   double) {
  using T = TestType;
  const lit_room<T> room(32);
  const auto tracer = with_light_visibility(room.tracer, room.vis);
  const T inf = std::numeric_limits<T>::infinity(), nan = std::numeric_limits<T>::quiet_NaN();
  const gather_point<T> ok{vec3<T>(T(1.9), T(0), T(-1.9)), vec3<T>(T(0), T(1), T(0)), vec3<T>(T(0.7))};
  // invalid gather points: 0, and no random numbers drawn
  for (const gather_point<T>& gp : {gather_point<T>{vec3<T>(nan, T(0), T(0)), ok.normal, ok.albedo},
                                   gather_point<T>{vec3<T>(inf, T(0), T(0)), ok.normal, ok.albedo},
                                   gather_point<T>{ok.position, vec3<T>(nan), ok.albedo},
                                   gather_point<T>{ok.position, vec3<T>(T(0)), ok.albedo}}) {
    counter_rng rng = make_counter_rng(1u, 1u);
    CHECK(estimate_clamp_compensation(gp, room.view, rng, 8, tracer, T(0.5), T(0)) == vec3<T>(T(0)));
    CHECK(rng.counter == 0u);
  }
  // NaN or infinite albedo: the per-sample guard keeps the estimate finite
  for (const vec3<T>& albedo : {vec3<T>(nan), vec3<T>(inf)}) {
    const gather_point<T> gp{ok.position, ok.normal, albedo};
    CHECK(finite_nonneg(compensation(gp, room.view, tracer, T(0.5))));
  }
  // a tracer reporting NaN, infinite or far hits
  for (const vec3<T>& y : {vec3<T>(nan), vec3<T>(inf, T(0), T(0)), vec3<T>(T(1e30))}) {
    ray_hit<T> h;
    h.hit = true;
    h.position = y;
    h.normal = vec3<T>(T(0), T(1), T(0));
    CHECK(compensation(ok, room.view, with_light_visibility(fixed_hit_tracer<T>{h}, room.vis), T(0.5)) == vec3<T>(T(0)));
  }
  // NaN and negative depth tolerances (the DPRSM's lit test: nothing is lit), infinite ones
  const exact_tracer<T> plain{&room.scene};  // its lit test is the DPRSM's plane
  CHECK(compensation(ok, room.view, plain, T(0.5), nan) == vec3<T>(T(0)));
  CHECK(compensation(ok, room.view, plain, T(0.5), T(-1)) == vec3<T>(T(0)));
  CHECK(finite_nonneg(compensation(ok, room.view, plain, T(0.5), inf)));
  // a light at NaN or infinite intensity
  for (const vec3<T>& I : {vec3<T>(nan), vec3<T>(inf)}) {
    dprsm_view<T> v = room.view;
    v.light.intensity = I;
    CHECK(finite_nonneg(compensation(ok, v, tracer, T(0.5))));
  }
  // NaN directions in the sample
  const orthonormal_basis<T> frame = make_orthonormal_basis(ok.normal);
  CHECK(clamp_compensation_sample(ok, room.view, frame, vec3<T>(nan), tracer, T(0.5), T(0)) == vec3<T>(T(0)));
  CHECK(finite_nonneg(clamp_compensation_sample(ok, room.view, frame, vec3<T>(nan, nan, T(1)), tracer, T(0.5), T(0))));
}
