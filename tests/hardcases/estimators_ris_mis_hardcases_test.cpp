// SPDX-License-Identifier: MIT
// RIS as the VPL strategy of MIS (estimators/ris_mis_estimator.hpp), each hard case its own test:
// all candidates zero, one candidate texel, NaN and infinite inputs (pmfs, albedos, the light),
// empty distributions and indices outside the view, an invalid gather point, counts of zero or
// below. Nothing may be NaN or Inf, in float and double, and the random numbers drawn follow the
// layout whatever the scene (n_ris M (2, or 4 with patch VPLs) + 2 n_dirs).
#include <estimator_checks.hpp>
#include <synthetic_scene.hpp>

#include <vplkit/builders/flux_weights.hpp>
#include <vplkit/builders/vpl_distribution.hpp>
#include <vplkit/distribution/discrete_cdf.hpp>
#include <vplkit/estimators/mis_estimator.hpp>
#include <vplkit/estimators/ris_mis_estimator.hpp>
#include <vplkit/estimators/vpl_sum.hpp>
#include <vplkit/vpl/luminance.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <type_traits>
#include <vector>

using namespace vplkit;
using namespace vplkit_test;

namespace {

template <class T>
struct room {
  lit_room<T> r{16};
  defensive_mixture<T> flux = make_vpl_distribution(build_flux_weights(r.view), r.view, T(0));
  T tol = T(0.2);
  int lit_texel() const {  // a texel whose VPL lights floor_open
    for (int t = 0; t < r.view.texel_count(); ++t)
      if (luminance(vpl_visible_contribution(r.gps[0].gp, r.view, t, r.vis, T(0))) > T(0)) return t;
    return -1;
  }
};

template <class T>
std::uint32_t layout_count(int n_dirs, int n_ris, int m, vpl_mode mode) {
  return std::uint32_t(n_ris * m) * (mode == vpl_mode::patch ? 4u : 2u) + 2u * std::uint32_t(n_dirs);
}

}  // namespace

TEMPLATE_TEST_CASE("ris-mis hard case: every candidate has target 0", "[hardcases][ris-mis]", float, double) {
  using T = TestType;
  const room<T> f;
  gather_point<T> gp = f.r.gps[0].gp;
  gp.normal = -gp.normal;  // floor_open facing into the floor: no VPL above it
  for (const vpl_mode mode : {vpl_mode::point, vpl_mode::patch}) {
    INFO("mode " << int(mode));
    counter_rng rng = make_counter_rng(1u, 0u);
    const ris_reservoir<T> r = ris_mis_resample(gp, f.r.view, f.flux, rng, 32, T(4), T(4), mode, f.tol);
    CHECK_FALSE(ris_reservoir_has_sample(r));
    CHECK(r.weight_sum == T(0));
    CHECK(r.confidence == T(32));
    CHECK(ris_mis_shade(gp, f.r.view, f.flux, r, f.r.vis, T(4), T(4), mode, f.tol) == vec3<T>(T(0)));
    counter_rng a = make_counter_rng(1u, 1u);
    CHECK(estimate_ris_mis(gp, f.r.view, f.flux, a, 0, 4, 16, f.r.tracer, f.r.vis, f.tol, mode) == vec3<T>(T(0)));
    CHECK(a.counter == layout_count<T>(0, 4, 16, mode));
    CHECK(finite_nonneg(estimate_ris_mis(gp, f.r.view, f.flux, a, 4, 4, 16, f.r.tracer, f.r.vis, f.tol, mode)));
  }
  // Zero intensity: every flux is 0, so is every target and every gathering hit's radiance.
  dprsm_view<T> dark = f.r.view;
  dark.light.intensity = vec3<T>(T(0));
  counter_rng rng = make_counter_rng(1u, 2u);
  CHECK(estimate_ris_mis(f.r.gps[0].gp, dark, f.flux, rng, 4, 4, 16, f.r.tracer, f.r.vis, f.tol) == vec3<T>(T(0)));
}

TEMPLATE_TEST_CASE("ris-mis hard case: one candidate texel gives estimate_mis's value there", "[hardcases][ris-mis]",
                   float, double) {
  using T = TestType;
  const room<T> f;
  const int t = f.lit_texel();
  REQUIRE(t >= 0);
  const gather_point<T>& gp = f.r.gps[0].gp;
  const T rel = std::is_same<T, float>::value ? T(1e-5) : T(1e-12);
  for (const T p : {T(1), T(0.25)}) {
    const fixed_draw<T> one{std::size_t(t), p};
    // n_dirs = 0: the unclamped contribution over the pmf (W = 1 / pmf whatever M), as VPL sampling.
    const vec3<T> term = vpl_visible_contribution(gp, f.r.view, t, f.r.vis, T(0)) / p;
    REQUIRE(luminance(term) > T(0));
    for (const int m : {1, 7, 64}) {
      counter_rng rng = make_counter_rng(2u, 0u);
      const vec3<T> e = estimate_ris_mis(gp, f.r.view, one, rng, 0, 3, m, f.r.tracer, f.r.vis, f.tol);
      INFO("pmf " << p << " M = " << m);
      for (int c = 0; c < 3; ++c) CHECK(std::abs(e[c] - term[c]) <= T(4) * rel * term[c]);
      // With directions: each RIS sample is estimate_mis's VPL sample at t.
      counter_rng q = make_counter_rng(2u, 1u);
      const ris_reservoir<T> res = ris_mis_resample(gp, f.r.view, one, q, m, T(4), T(3), vpl_mode::point, f.tol);
      const vec3<T> v = ris_mis_shade(gp, f.r.view, one, res, f.r.vis, T(4), T(3), vpl_mode::point, f.tol) / T(3);
      const vec3<T> w = mis_vpl_sample(gp, f.r.view, one, T(0.5), f.r.vis, T(4), T(3), mis_mode::solid_angle);
      REQUIRE(luminance(w) > T(0));
      for (int c = 0; c < 3; ++c) CHECK(std::abs(v[c] - w[c]) <= T(4) * rel * w[c]);
    }
  }
}

TEMPLATE_TEST_CASE("ris-mis hard case: NaN and infinite pmfs, albedos and light", "[hardcases][ris-mis]", float, double) {
  using T = TestType;
  const T nan = std::numeric_limits<T>::quiet_NaN(), inf = std::numeric_limits<T>::infinity();
  const room<T> f;
  const int t = f.lit_texel();
  const gather_point<T>& gp = f.r.gps[0].gp;
  for (const vpl_mode mode : {vpl_mode::point, vpl_mode::patch}) {
    INFO("mode " << int(mode));
    // pmfs that are NaN, infinite, negative or denormal (counted as 0: estimator_pmf): no sample kept.
    for (const T p : {nan, inf, -T(1), std::numeric_limits<T>::denorm_min(), std::numeric_limits<T>::min() / T(4)}) {
      INFO("pmf " << p);
      const fixed_draw<T> bad{std::size_t(t), p};
      counter_rng rng = make_counter_rng(3u, 0u);
      const ris_reservoir<T> res = ris_mis_resample(gp, f.r.view, bad, rng, 8, T(2), T(2), mode, f.tol);
      if (!(p == inf)) CHECK_FALSE(ris_reservoir_has_sample(res));
      counter_rng a = make_counter_rng(3u, 1u);
      CHECK(finite_nonneg(estimate_ris_mis(gp, f.r.view, bad, a, 2, 2, 8, f.r.tracer, f.r.vis, f.tol, mode)));
      CHECK(a.counter == layout_count<T>(2, 2, 8, mode));
    }
    // NaN and infinite albedo in one channel at the gather point: balance_combined makes that
    // channel's value 0 (as in estimate_mis), so the targets are the other channels' luminance,
    // finite, and the estimate is finite with that channel 0.
    for (const T a : {nan, inf}) {
      gather_point<T> g = gp;
      g.albedo = vec3<T>(a, T(0.5), T(0.5));
      counter_rng rng = make_counter_rng(3u, 2u);
      const ris_reservoir<T> q = ris_mis_resample(g, f.r.view, f.flux, rng, 16, T(2), T(2), mode, f.tol);
      CHECK(std::isfinite(q.target));
      CHECK(std::isfinite(q.weight_sum));
      const vec3<T> e = estimate_ris_mis(g, f.r.view, f.flux, rng, 2, 2, 16, f.r.tracer, f.r.vis, f.tol, mode);
      CHECK(finite_nonneg(e));
      CHECK(e.x == T(0));
      // Every channel not finite: nothing is kept.
      g.albedo = vec3<T>(a);
      const ris_reservoir<T> z = ris_mis_resample(g, f.r.view, f.flux, rng, 16, T(2), T(2), mode, f.tol);
      CHECK_FALSE(ris_reservoir_has_sample(z));
      CHECK(estimate_ris_mis(g, f.r.view, f.flux, rng, 2, 2, 16, f.r.tracer, f.r.vis, f.tol, mode) == vec3<T>(T(0)));
    }
    // An infinite light: infinite targets (not usable weights) and radiances, never an infinite value.
    dprsm_view<T> hot = f.r.view;
    hot.light.intensity = vec3<T>(inf);
    counter_rng rng = make_counter_rng(3u, 3u);
    CHECK(finite_nonneg(estimate_ris_mis(gp, hot, f.flux, rng, 2, 2, 16, f.r.tracer, f.r.vis, f.tol, mode)));
    // Numbers outside [0, 1) from the stream cannot occur; a NaN depth tolerance must not leak either.
    counter_rng b = make_counter_rng(3u, 4u);
    CHECK(finite_nonneg(estimate_ris_mis(gp, f.r.view, f.flux, b, 2, 2, 16, f.r.tracer, f.r.vis, nan, mode)));
  }
}

TEMPLATE_TEST_CASE("ris-mis hard case: empty distributions and indices outside the view", "[hardcases][ris-mis]",
                   float, double) {
  using T = TestType;
  const room<T> f;
  const gather_point<T>& gp = f.r.gps[0].gp;
  const discrete_cdf<T> empty(std::vector<T>(std::size_t(f.r.view.texel_count()), T(0)));
  const discrete_cdf<T> none;
  const fixed_draw<T> outside{std::size_t(f.r.view.texel_count()), T(1)};
  for (const vpl_mode mode : {vpl_mode::point, vpl_mode::patch}) {
    INFO("mode " << int(mode));
    counter_rng a = make_counter_rng(4u, 0u), b = a, c = a;
    // Without directions nothing is left.
    CHECK(estimate_ris_mis(gp, f.r.view, empty, a, 0, 3, 8, f.r.tracer, f.r.vis, f.tol, mode) == vec3<T>(T(0)));
    CHECK(estimate_ris_mis(gp, f.r.view, none, b, 0, 3, 8, f.r.tracer, f.r.vis, f.tol, mode) == vec3<T>(T(0)));
    CHECK(estimate_ris_mis(gp, f.r.view, outside, c, 0, 3, 8, f.r.tracer, f.r.vis, f.tol, mode) == vec3<T>(T(0)));
    // The numbers are drawn all the same: the layout does not depend on the scene.
    CHECK(a.counter == layout_count<T>(0, 3, 8, mode));
    CHECK(b.counter == a.counter);
    CHECK(c.counter == a.counter);
    // With directions, gathering takes everything (p2 = 0): finite, and the same for both empties.
    counter_rng d = make_counter_rng(4u, 1u), e = d;
    const vec3<T> x = estimate_ris_mis(gp, f.r.view, empty, d, 4, 3, 8, f.r.tracer, f.r.vis, f.tol, mode);
    const vec3<T> y = estimate_ris_mis(gp, f.r.view, none, e, 4, 3, 8, f.r.tracer, f.r.vis, f.tol, mode);
    CHECK(finite_nonneg(x));
    CHECK(x == y);
    CHECK(d.counter == layout_count<T>(4, 3, 8, mode));
  }
}

TEMPLATE_TEST_CASE("ris-mis hard case: an invalid gather point and counts of zero draw nothing", "[hardcases][ris-mis]",
                   float, double) {
  using T = TestType;
  const T nan = std::numeric_limits<T>::quiet_NaN();
  const room<T> f;
  const gather_point<T>& gp = f.r.gps[0].gp;
  const gather_point<T> background{gp.position, vec3<T>(T(0)), gp.albedo};  // no surface
  const gather_point<T> nan_position{vec3<T>(nan, T(0), T(0)), gp.normal, gp.albedo};
  for (const gather_point<T>& bad : {background, nan_position}) {
    counter_rng rng = make_counter_rng(5u, 0u);
    CHECK(estimate_ris_mis(bad, f.r.view, f.flux, rng, 4, 4, 16, f.r.tracer, f.r.vis, f.tol) == vec3<T>(T(0)));
    CHECK(rng.counter == 0u);
    const ris_reservoir<T> r = ris_mis_resample(bad, f.r.view, f.flux, rng, 16, T(4), T(4), vpl_mode::point, f.tol);
    CHECK_FALSE(ris_reservoir_has_sample(r));
    CHECK(rng.counter == 0u);
  }
  // No samples, negative counts, M <= 0 (then n_ris counts as 0: gathering alone).
  counter_rng rng = make_counter_rng(5u, 1u);
  CHECK(estimate_ris_mis(gp, f.r.view, f.flux, rng, 0, 0, 16, f.r.tracer, f.r.vis, f.tol) == vec3<T>(T(0)));
  CHECK(estimate_ris_mis(gp, f.r.view, f.flux, rng, -3, -2, 16, f.r.tracer, f.r.vis, f.tol) == vec3<T>(T(0)));
  CHECK(estimate_ris_mis(gp, f.r.view, f.flux, rng, 0, 4, 0, f.r.tracer, f.r.vis, f.tol) == vec3<T>(T(0)));
  CHECK(estimate_ris_mis(gp, f.r.view, f.flux, rng, 0, 4, -5, f.r.tracer, f.r.vis, f.tol) == vec3<T>(T(0)));
  CHECK(rng.counter == 0u);
  CHECK(finite_nonneg(estimate_ris_mis(gp, f.r.view, f.flux, rng, 3, 4, 0, f.r.tracer, f.r.vis, f.tol)));
  CHECK(rng.counter == layout_count<T>(3, 0, 0, vpl_mode::point));
}
