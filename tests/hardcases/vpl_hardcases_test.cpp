// SPDX-License-Identifier: MIT
// docs/math.md section 10, contribution: d2 -> 0, back-facing, unnormalised normals (and zero
// normals); the same care in reflected_radiance and vpl_patch_area. Nothing may come out NaN or
// Inf.
#include <fp_mode.hpp>
#include <estimator_checks.hpp>
#include <synthetic_scene.hpp>

#include <vplkit/vpl/direct_light.hpp>
#include <vplkit/vpl/dprsm_view.hpp>
#include <vplkit/vpl/vpl.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

using vplkit::vec3;
using vplkit_test::finite_nonneg;

TEMPLATE_TEST_CASE("hard case: contribution as d2 -> 0 stays finite", "[vpl][hardcase]", float,
                   double) {
  using T = TestType;
  // x on a floor, VPL on a wall meeting it, sliding toward x along the corner diagonal: the
  // classic VPL singularity (G ~ 1/d2^2).
  const vec3<T> n_x(0, 0, 1), n_t(-1, 0, 0), rho(T(0.8)), flux(T(1e3));
  for (const vec3<T>& x : {vec3<T>(0), vec3<T>(T(1e3), T(-2e3), T(5e2))}) {
    T previous = 0;
    for (int k = 0; k <= 320; ++k) {
      const T d = T(std::pow(10.0, -0.125 * k));  // 1 down to 1e-40 (below float's normals)
      const vplkit::vpl<T> v{x + vec3<T>(d, 0, d), n_t, flux};
      for (T dmin : {T(0), T(0.1)}) {
        const vec3<T> L = vplkit::vpl_contribution(x, n_x, rho, v, dmin);
        INFO("d " << d << " dmin " << dmin);
        REQUIRE(finite_nonneg(L));
        if (dmin > T(0)) {
          // clamped: bounded by (rho / pi) Phi / (pi dmin^2)
          REQUIRE(double(L.x) <= 0.8 / 3.14159 * 1e3 / (3.14159 * 0.01) * 1.001);
        } else if (L.x > T(0)) {
          // grows like 1/d^2 until the points coincide; on the floor's plateau (d2^2 raised to
          // vpl_distance_sq_floor) only the cosines' rounding moves it
          REQUIRE(L.x >= previous * (T(1) - T(4) * std::numeric_limits<T>::epsilon()));
          previous = std::max(previous, L.x);
        }
      }
    }
  }
}

TEMPLATE_TEST_CASE("hard case: contribution at x == y is 0 also with dmin = 0", "[vpl][hardcase]",
                   float, double) {
  using T = TestType;
  const T eps = std::numeric_limits<T>::epsilon();
  for (const vec3<T>& x : {vec3<T>(0), vec3<T>(1, 2, 3), vec3<T>(T(-1e6), 0, T(1e-3))}) {
    const vplkit::vpl<T> v{x, vec3<T>(0, 0, -1), vec3<T>(5)};
    for (T dmin : {T(0), T(0.01)}) {
      REQUIRE(vplkit::vpl_contribution(x, vec3<T>(0, 0, 1), vec3<T>(1), v, dmin) == vec3<T>(0));
      // a separation at the level of the coordinates' rounding is the same point
      const vplkit::vpl<T> w{x + vec3<T>(0, 0, T(4) * eps * vplkit::max_abs_component(x)),
                             vec3<T>(0, 0, -1), vec3<T>(5)};
      REQUIRE(vplkit::vpl_contribution(x, vec3<T>(0, 0, 1), vec3<T>(1), w, dmin) == vec3<T>(0));
    }
  }
  // the smallest normal separation near the origin: not the same point, still finite
  const T mn = std::numeric_limits<T>::min();
  const vplkit::vpl<T> v{vec3<T>(0, 0, mn), vec3<T>(0, 0, -1), vec3<T>(5)};
  const vec3<T> L = vplkit::vpl_contribution(vec3<T>(0), vec3<T>(0, 0, 1), vec3<T>(1), v, T(0));
  REQUIRE(finite_nonneg(L));
  REQUIRE(L.x > T(0));  // head-on: the floor on d2^2 caps it, it does not vanish
  // a denormal separation has no direction (docs/math.md, "GPU arithmetic model": a GPU may flush it): 0
  const T dn = std::numeric_limits<T>::denorm_min();
  const vplkit::vpl<T> w{vec3<T>(0, 0, dn), vec3<T>(0, 0, -1), vec3<T>(5)};
  REQUIRE(vplkit::vpl_contribution(vec3<T>(0), vec3<T>(0, 0, 1), vec3<T>(1), w, T(0)) == vec3<T>(0));
}

TEMPLATE_TEST_CASE("hard case: back-facing VPL or gather point gives 0", "[vpl][hardcase]", float,
                   double) {
  using T = TestType;
  const vec3<T> x(0), n_x(0, 0, 1), rho(1);
  const vec3<T> flux(1);
  // (VPL position, VPL normal): every combination where one of the two faces away
  const vec3<T> cases[][2] = {{{0, 0, 1}, {0, 0, 1}},     // VPL faces away from x
                              {{0, 0, -1}, {0, 0, 1}},    // VPL behind x's surface
                              {{1, 0, 1}, {1, 0, 0}},     // VPL on a wall, facing out
                              {{1, 0, 0}, {-1, 0, 0}},    // VPL in x's tangent plane
                              {{0, 0, 1}, {1, 0, 0}},     // VPL edge-on
                              {{0, 0, -1}, {0, 0, -1}}};  // both back to back
  for (const auto& c : cases)
    for (T dmin : {T(0), T(0.5)}) {
      const vplkit::vpl<T> v{c[0], c[1], flux};
      REQUIRE(vplkit::vpl_contribution(x, n_x, rho, v, dmin) == vec3<T>(0));
      REQUIRE(vplkit::vpl_geometry_term(x, n_x, c[0], c[1], dmin) == T(0));
    }
  // the lit side of a single-sided surface: reflected radiance 0 when the light is behind it
  REQUIRE(vplkit::reflected_radiance(vec3<T>(0, 0, -1), vec3<T>(1), x, n_x, rho) == vec3<T>(0));
  REQUIRE(vplkit::vpl_cos_alpha(vec3<T>(0, 0, -1), x, n_x) == T(0));
}

TEMPLATE_TEST_CASE("hard case: unnormalised normals are normalised", "[vpl][hardcase]", float,
                   double) {
  using T = TestType;
  const vec3<T> x(0), rho(T(0.5));
  const vplkit::vpl<T> unit{vec3<T>(1, 0, 1), vec3<T>(-1, 0, 0), vec3<T>(2)};
  const vec3<T> ref = vplkit::vpl_contribution(x, vec3<T>(0, 0, 1), rho, unit, T(0));
  REQUIRE(ref.x > T(0));
  const T tiny = std::numeric_limits<T>::min(), dn = std::numeric_limits<T>::denorm_min();
  const T big = std::numeric_limits<T>::max();
  // A denormal scale is a zero normal (docs/math.md, "GPU arithmetic model"): no contribution.
  {
    const vplkit::vpl<T> v{unit.position, unit.normal * dn, unit.flux};
    REQUIRE(vplkit::vpl_contribution(x, vec3<T>(0, 0, dn), rho, v, T(0)) == vec3<T>(0));
  }
  for (T s : {tiny, T(1e-20), T(0.001), T(3), T(1e20), big}) {
    const vplkit::vpl<T> v{unit.position, unit.normal * s, unit.flux};
    const vec3<T> L = vplkit::vpl_contribution(x, vec3<T>(0, 0, s), rho, v, T(0));
    INFO("normal scale " << s);
    REQUIRE(finite_nonneg(L));
    REQUIRE(L.x == Approx(ref.x).epsilon(1e-5));
    const vec3<T> Lo =
        vplkit::reflected_radiance(vec3<T>(0, 0, 2), vec3<T>(1), x, vec3<T>(0, 0, s), rho);
    REQUIRE(Lo.x == Approx(0.5 / (3.14159265358979323846 * 4)).epsilon(1e-5));
  }
}

TEMPLATE_TEST_CASE("hard case: zero or NaN normals and NaN positions give 0", "[vpl][hardcase]",
                   float, double) {
  using T = TestType;
  const T nan = std::numeric_limits<T>::quiet_NaN();
  const vec3<T> x(0), rho(1);
  for (const vec3<T>& bad : {vec3<T>(0), vec3<T>(nan), vec3<T>(nan, 0, 1)}) {
    const vplkit::vpl<T> v_bad{vec3<T>(1, 0, 1), bad, vec3<T>(1)};
    const vplkit::vpl<T> v_good{vec3<T>(1, 0, 1), vec3<T>(-1, 0, 0), vec3<T>(1)};
    for (T dmin : {T(0), T(0.5)}) {
      REQUIRE(vplkit::vpl_contribution(x, vec3<T>(0, 0, 1), rho, v_bad, dmin) == vec3<T>(0));
      REQUIRE(vplkit::vpl_contribution(x, bad, rho, v_good, dmin) == vec3<T>(0));
    }
    REQUIRE(vplkit::reflected_radiance(vec3<T>(0, 0, 1), vec3<T>(1), x, bad, rho) == vec3<T>(0));
    REQUIRE(vplkit::vpl_cos_alpha(vec3<T>(0, 0, 1), x, bad) == T(0));
  }
  // NaN coordinates in either position
  const vplkit::vpl<T> v{vec3<T>(1, 0, 1), vec3<T>(-1, 0, 0), vec3<T>(1)};
  const vplkit::vpl<T> v_nan{vec3<T>(1, nan, 1), vec3<T>(-1, 0, 0), vec3<T>(1)};
  for (T dmin : {T(0), T(0.5)}) {
    REQUIRE(vplkit::vpl_contribution(vec3<T>(nan, 0, 0), vec3<T>(0, 0, 1), rho, v, dmin) ==
            vec3<T>(0));
    REQUIRE(vplkit::vpl_contribution(x, vec3<T>(0, 0, 1), rho, v_nan, dmin) == vec3<T>(0));
  }
  REQUIRE(vplkit::reflected_radiance(vec3<T>(0, nan, 1), vec3<T>(1), x, vec3<T>(0, 0, 1), rho) ==
          vec3<T>(0));
  REQUIRE(vplkit::reflected_radiance(vec3<T>(0, 0, 1), vec3<T>(1), vec3<T>(nan), vec3<T>(0, 0, 1),
                                     rho) == vec3<T>(0));
}

TEMPLATE_TEST_CASE("hard case: reflected radiance with the light on the surface", "[vpl][hardcase]",
                   float, double) {
  using T = TestType;
  const vec3<T> n(0, 0, 1), rho(1), I(1);
  REQUIRE(vplkit::reflected_radiance(vec3<T>(1, 1, 1), I, vec3<T>(1, 1, 1), n, rho) == vec3<T>(0));
  for (int k = 0; k <= 320; ++k) {
    const T d = T(std::pow(10.0, -0.125 * k));
    const vec3<T> L = vplkit::reflected_radiance(vec3<T>(0, 0, d), I, vec3<T>(0), n, rho);
    REQUIRE(finite_nonneg(L));
  }
}

TEMPLATE_TEST_CASE("hard case: patch area at grazing incidence", "[vpl][hardcase]", float, double) {
  using T = TestType;
  const T dn = std::numeric_limits<T>::denorm_min();
  for (T c : {T(0), -T(0), dn, T(-1), T(1e-30), std::numeric_limits<T>::quiet_NaN()}) {
    const T a = vplkit::vpl_patch_area(T(1e-5), T(10), c);
    REQUIRE(std::isfinite(a));
    REQUIRE(a == Approx(1e-3 / 1e-6));
  }
  // the full chain from geometry: light exactly in the surface's plane
  const T cos_a = vplkit::vpl_cos_alpha(vec3<T>(5, 0, 0), vec3<T>(0), vec3<T>(0, 0, 1));
  REQUIRE(cos_a == T(0));
  REQUIRE(std::isfinite(vplkit::vpl_patch_area(T(1e-5), T(5), cos_a)));
}

TEMPLATE_TEST_CASE("hard case: DPRSM texels with no geometry or outside the disk give no VPL",
                   "[vpl][hardcase]", float, double) {
  using T = TestType;
  const int R = 4;
  std::vector<vec3<T>> P(32, vec3<T>(0)), N(32, vec3<T>(0)), A(32, vec3<T>(0));
  // a texel that "saw" the light's own position with a real albedo: coincident, no flux
  A[5] = vec3<T>(1);
  N[5] = vec3<T>(0, 0, 1);
  // an invalid corner texel with data: ignored
  A[0] = vec3<T>(1);
  N[0] = vec3<T>(0, 0, 1);
  P[0] = vec3<T>(0, 0, 1);
  const auto light = vplkit::make_point_light(vec3<T>(0), vec3<T>(1));
  const vplkit::dprsm_view<T> view{R, P.data(), N.data(), A.data(), light};
  REQUIRE_NOTHROW(view.validate());
  REQUIRE_FALSE(view.texel_valid(0));
  for (int i = 0; i < view.texel_count(); ++i) {
    const vplkit::vpl<T> v = view.vpl_at(i);
    REQUIRE(v.flux == vec3<T>(0));
    // and such VPLs contribute nothing anywhere
    REQUIRE(vplkit::vpl_contribution(vec3<T>(0, 0, 1), vec3<T>(0, 0, -1), vec3<T>(1), v, T(0)) ==
            vec3<T>(0));
  }
}

TEMPLATE_TEST_CASE("hard case: direct light closer to the light than 2^-63 is the same with denormals flushed",
                   "[vpl][hardcase]", float, double) {
  using T = TestType;
  // The synthetic room's DPRSM with its light moved to the origin, so that the coordinates are as
  // small as the distances (otherwise the points coincide with the light). Below 2^-63 (float;
  // 2^-511 in double) the squared distance is a denormal: a length() of it is a small positive
  // distance with IEEE arithmetic and 0 where denormals are flushed (a GPU, -ffast-math, FTZ|DAZ),
  // and the squares of components just above 2^-63 are denormals too. Scaled first, the distance
  // is the same either way, and the point is lit as any other (its distance is still a normal float).
  const vplkit_test::lit_room<T> room(32);
  vplkit::dprsm_view<T> view = room.view;
  view.light.position = vec3<T>(T(0));
  view.light.frame.position = vec3<T>(T(0));
  const int e0 = (std::numeric_limits<T>::min_exponent - 1) / 2;  // the squares of 2^e0 are normal
  const vec3<T> dirs[] = {vec3<T>(0, -1, 0), vec3<T>(T(0.25), -1, T(0.5)), vec3<T>(T(-0.5), -1, T(-0.125)),
                          vec3<T>(1, -1, 1)};
  int lit_below = 0, lit_above = 0;
  for (int k = e0 - 4; k <= e0 + 2; ++k) {
    for (const vec3<T> dir : dirs) {
      const T s = vplkit::exp2i<T>(k);
      vplkit::gather_point<T> gp{dir * s, -dir, vec3<T>(T(0.8))};  // facing the light
      INFO("distance scale 2^" << k << ", direction (" << dir.x << ", " << dir.y << ", " << dir.z << ")");
      const vec3<T> ieee = vplkit::direct_light(gp, view);
      vec3<T> flushed;
      {
        const vplkit_test::fp_mode_scope ftz(true);
        flushed = vplkit::direct_light(gp, view);
      }
      INFO("IEEE (" << ieee.x << ", " << ieee.y << ", " << ieee.z << "), flushed (" << flushed.x << ", "
                    << flushed.y << ", " << flushed.z << ")");
      CHECK(finite_nonneg(ieee));
      CHECK(ieee == flushed);
      if (ieee.x > T(0)) ++(k < e0 ? lit_below : lit_above);
    }
  }
  CHECK(lit_below >= 8);  // the lookup sees the room's floor below the light
  CHECK(lit_above >= 8);
}
