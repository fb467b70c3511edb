// SPDX-License-Identifier: MIT
// The crease rule of every gathering strategy (vpl_hit_on_own_plane; docs/math.md, "The clamp's
// compensation", "A hit on x's own plane sends nothing") in gathering and in MIS's gathering
// strategy: a gather point on a crease (a floor point on the plane of a wall), coincident
// surfaces, a hit exactly on x's plane against one just off it, and the predicate at its
// tolerance.
#include <synthetic_scene.hpp>

#include <vplkit/distribution/discrete_cdf.hpp>
#include <vplkit/estimators/gathering_estimator.hpp>
#include <vplkit/estimators/mis_estimator.hpp>
#include <vplkit/visibility/light_visibility.hpp>
#include <vplkit/vpl/luminance.hpp>
#include <vplkit/vpl/vpl.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <vector>

using namespace vplkit;
using namespace vplkit_test;

namespace {

template <class T>
std::vector<T> flux_weights(const dprsm_view<T>& view) {
  std::vector<T> w(std::size_t(view.texel_count()));
  for (int t = 0; t < view.texel_count(); ++t) w[std::size_t(t)] = luminance(view.vpl_at(t).flux);
  return w;
}

// A tracer that reports one fixed hit for every ray.
template <class T>
struct fixed_hit_tracer {
  ray_hit<T> h;
  ray_hit<T> operator()(vec3<T>, vec3<T>, vec3<T>) const { return h; }
};

// The synthetic room's exact tracer, and the same tracer blind to the wall x = +2: the rays from a
// point on that wall's plane that meet it do so where their lifted origin crosses it.
template <class T>
struct crease_setup {
  synthetic_scene<T> s;
  dprsm_data<T> d = s.make_dprsm(16);
  exact_tracer<T> tr{&s};
  static bool on_wall(const ray_hit<T>& h) { return h.hit && h.normal.x < T(-0.99); }
  ray_hit<T> without_wall(vec3<T> o, vec3<T> n, vec3<T> dir) const {
    const ray_hit<T> h = tr(o, n, dir);
    return on_wall(h) ? ray_hit<T>{} : h;
  }
  // Rays of `n` cosine directions at gp that the exact tracer sends into the wall, lit on its
  // DPRSM texel (so that, without the rule, they would add the wall's L_o).
  int lit_wall_hits(const gather_point<T>& gp, int n, T tol) const {
    counter_rng rng = make_counter_rng(5u, 0u);
    const orthonormal_basis<T> frame = make_orthonormal_basis(gp.normal);
    int lit = 0;
    for (int k = 0; k < n; ++k) {
      const T u0 = rng_next_unit<T>(rng), u1 = rng_next_unit<T>(rng);
      const ray_hit<T> h = tr(gp.position, gp.normal, to_world(frame, sample_cosine_hemisphere(vec2<T>(u0, u1))));
      if (on_wall(h)) lit += dprsm_lookup(d.view(), h.position, tol).lit;
    }
    return lit;
  }
};

}  // namespace

TEST_CASE("gathering and MIS hard case: a gather point on a crease sees the wall through it edge-on", "[hardcases]") {
  // float, the renderer's type: a G-buffer point a rounding step off the wall's plane, whose rays
  // into the wall the exact tracer reports at distances ~1e-6 (exactly on the plane, this tracer
  // reports none: its lifted origin lies on the wall and the ray leaves through the edge).
  using T = float;
  const crease_setup<T> c;
  const auto view = c.d.view();
  const discrete_cdf<T> cdf(flux_weights(view));
  const exact_visibility<T> vis{&c.s};
  const T tol = T(0.05);
  const auto blind = [&](vec3<T> o, vec3<T> n, vec3<T> dir) { return c.without_wall(o, n, dir); };
  // Floor points on the wall's plane within the coordinates' rounding (1e-6 and 2e-6 off it, below
  // the tolerance 16 eps * 2 = 3.8e-6) and off it (1e-3, 1e-5: the rule stays away).
  const vec3<T> up(T(0), T(1), T(0));
  for (const T off : {T(1e-6), T(2e-6)}) {
    const gather_point<T> gp{vec3<T>(T(2) - off, T(0), T(0.1)), up, vec3<T>(T(0.5))};
    INFO("x " << off << " from the wall's plane");
    // The situation is real: the exact tracer's lifted origin meets the wall, lit, on many rays.
    REQUIRE(c.lit_wall_hits(gp, 256, tol) > 20);
    counter_rng r1 = make_counter_rng(9u, 1u), r2 = r1;
    const vec3<T> g = estimate_gathering(gp, view, r1, 256, c.tr, tol);
    CHECK(g == estimate_gathering(gp, view, r2, 256, blind, tol));
    CHECK(luminance(g) > T(0));  // the rest of the room still counts
    for (const mis_mode mode : {mis_mode::solid_angle, mis_mode::as_published}) {
      for (const vpl_mode vmode : {vpl_mode::point, vpl_mode::patch}) {
        counter_rng m1 = make_counter_rng(9u, 2u), m2 = m1;
        const vec3<T> m = estimate_mis(gp, view, cdf, m1, 128, 64, c.tr, vis, tol, mode, vmode);
        CHECK(m == estimate_mis(gp, view, cdf, m2, 128, 64, blind, vis, tol, mode, vmode));
        CHECK(luminance(m) > T(0));
      }
    }
  }
  for (const T off : {T(1e-3), T(1e-5)}) {
    // Off the plane the wall is a real near field: no hit is dropped, the wall's rays count.
    const gather_point<T> gp{vec3<T>(T(2) - off, T(0), T(0.1)), up, vec3<T>(T(0.5))};
    INFO("x " << off << " from the wall's plane");
    counter_rng rng = make_counter_rng(5u, 0u);
    const orthonormal_basis<T> frame = make_orthonormal_basis(gp.normal);
    int on_plane = 0, on_wall = 0;
    for (int k = 0; k < 256; ++k) {
      const T u0 = rng_next_unit<T>(rng), u1 = rng_next_unit<T>(rng);
      const ray_hit<T> h = c.tr(gp.position, gp.normal, to_world(frame, sample_cosine_hemisphere(vec2<T>(u0, u1))));
      on_plane += vpl_hit_on_own_plane(gp.position, h);
      on_wall += crease_setup<T>::on_wall(h);
    }
    CHECK(on_plane == 0);
    CHECK(on_wall > 50);
    counter_rng r1 = make_counter_rng(9u, 1u), r2 = r1;
    CHECK(luminance(estimate_gathering(gp, view, r1, 256, c.tr, tol)) >
          T(1.1) * luminance(estimate_gathering(gp, view, r2, 256, blind, tol)));  // measured 1.17
  }
}

TEMPLATE_TEST_CASE("gathering and MIS hard case: coincident surfaces, a hit exactly on x's plane and one just off it",
                   "[hardcases]", float, double) {
  using T = TestType;
  const lit_room<T> room(32);
  const discrete_cdf<T> cdf(flux_weights(room.view));
  const vec3<T> up(T(0), T(1), T(0));
  const gather_point<T> gp{vec3<T>(T(1.2), T(0), T(1.0)), up, vec3<T>(T(0.7))};
  const orthonormal_basis<T> frame = make_orthonormal_basis(up);
  const vec3<T> local = glm::normalize(vec3<T>(T(0.3), T(0.2), T(0.9)));
  // One direction's value with a tracer that reports the hit h for every ray.
  const auto gather = [&](const ray_hit<T>& h) {
    return gathering_sample(gp, room.view, frame, local, with_light_visibility(fixed_hit_tracer<T>{h}, room.vis), T(0));
  };
  const auto mis = [&](const ray_hit<T>& h) {
    return mis_gathering_sample(gp, room.view, cdf, frame, local,
                                with_light_visibility(fixed_hit_tracer<T>{h}, room.vis), T(0), T(1), T(1),
                                mis_mode::solid_angle);
  };
  ray_hit<T> coincident;  // a second floor in the first's plane, 1e-3 away along it
  coincident.hit = true;
  coincident.position = gp.position + vec3<T>(T(1e-3), T(0), T(0));
  coincident.normal = up;
  CHECK(gather(coincident) == vec3<T>(T(0)));
  CHECK(mis(coincident) == vec3<T>(T(0)));
  // A wall through x (x on its plane, the crease), hit 1e-3 above x: exactly on x's plane ...
  const vec3<T> n_wall(T(-1), T(0), T(0));
  ray_hit<T> crease;
  crease.hit = true;
  crease.position = gp.position + vec3<T>(T(0), T(1e-3), T(1e-3));
  crease.normal = n_wall;
  CHECK(gather(crease) == vec3<T>(T(0)));
  CHECK(mis(crease) == vec3<T>(T(0)));
  // ... at the tolerance (16 eps of the largest coordinate) off it, still on it ...
  const T tolerance = vpl_coincidence_tolerance(gp.position, crease.position);
  ray_hit<T> at_tol = crease;
  at_tol.position.x = gp.position.x + tolerance / T(2);
  REQUIRE(std::abs(at_tol.position.x - gp.position.x) <= tolerance);
  CHECK(gather(at_tol) == vec3<T>(T(0)));
  // ... and four tolerances off it: a surface x sees (at a grazing angle), counted.
  ray_hit<T> just_off = crease;
  just_off.position.x = gp.position.x + T(4) * tolerance;
  CHECK(luminance(gather(just_off)) > T(0));
  CHECK(luminance(mis(just_off)) > T(0));
}

TEMPLATE_TEST_CASE("vpl_point_on_plane: the decision at the tolerance, unnormalised, zero and NaN normals",
                   "[hardcases]", float, double) {
  using T = TestType;
  const T eps = std::numeric_limits<T>::epsilon();
  const vec3<T> x(T(1), T(0), T(0));
  const vec3<T> n(T(1), T(0), T(0));
  // y on x's plane up to k ulps of 1 (the tolerance is 16 eps times the largest coordinate, 1 + k eps)
  for (int k = 0; k <= 16; ++k) {
    INFO("k " << k);
    CHECK(vpl_point_on_plane(x, vec3<T>(T(1) + T(k) * eps, T(0.5), T(0)), n));
    CHECK(vpl_point_on_plane(x, vec3<T>(T(1) + T(k) * eps, T(0.5), T(0)), n * T(1e-20)));  // any length
  }
  for (int k : {17, 32, 1000}) {
    INFO("k " << k);
    CHECK_FALSE(vpl_point_on_plane(x, vec3<T>(T(1) + T(k) * eps, T(0.5), T(0)), n));
    CHECK_FALSE(vpl_point_on_plane(x, vec3<T>(T(1) + T(k) * eps, T(0.5), T(0)), -n * T(1e20)));
  }
  // scale-relative: the same relative offsets at 1e6
  CHECK(vpl_point_on_plane(x * T(1e6), vec3<T>(T(1e6) * (T(1) + T(8) * eps), T(3), T(0)), n));
  CHECK_FALSE(vpl_point_on_plane(x * T(1e6), vec3<T>(T(1e6) * (T(1) + T(64) * eps), T(3), T(0)), n));
  // no normal: the predicate says "on it", and the hit form never tests such a hit
  CHECK(vpl_point_on_plane(x, vec3<T>(T(2), T(0), T(0)), vec3<T>(T(0))));
  ray_hit<T> h;
  h.hit = true;
  h.position = x;
  CHECK_FALSE(vpl_hit_on_own_plane(x, h));
  h.normal = n;
  CHECK(vpl_hit_on_own_plane(x, h));
  const T nan = std::numeric_limits<T>::quiet_NaN();
  CHECK(vpl_point_on_plane(x, vec3<T>(T(2), T(0), T(0)), vec3<T>(nan, T(0), T(1))));  // unit_or_zero: 0
}
