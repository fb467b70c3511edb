// SPDX-License-Identifier: MIT
// RIS as the VPL strategy of MIS (estimators/ris_mis_estimator.hpp), each hard case its own test:
// all candidates zero, one candidate texel, NaN and infinite inputs (pmfs, albedos, the light),
// empty distributions and indices outside the view, an invalid gather point, counts of zero or
// below; its spatial reuse with empty inputs, zero targets at the receiver and more neighbours than
// the bound. Nothing may be NaN or Inf, in float and double, and the random numbers drawn follow the
// layout whatever the scene (n_ris M (2, or 4 with patch VPLs) + 2 n_dirs).
#include <estimator_checks.hpp>
#include <synthetic_scene.hpp>

#include <vplkit/builders/flux_weights.hpp>
#include <vplkit/builders/vpl_distribution.hpp>
#include <vplkit/distribution/discrete_cdf.hpp>
#include <vplkit/estimators/mis_estimator.hpp>
#include <vplkit/estimators/ris_mis_estimator.hpp>
#include <vplkit/estimators/ris_mis_spatial_reuse.hpp>
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

// Spatial reuse (estimators/ris_mis_spatial_reuse.hpp): empty and zero-confidence inputs, targets
// that are 0 at the receiver (a receiver no VPL lights, a receiver whose own distribution cannot
// draw the neighbour's sample), more neighbours than the bound on a tiny image, NaN selection
// numbers. Never NaN or Inf, and the reuse draws 1 + 3K numbers whatever it finds.
TEMPLATE_TEST_CASE("ris-mis hard case: reuse with empty inputs and zero confidences", "[hardcases][ris-mis]", float,
                   double) {
  using T = TestType;
  const room<T> f;
  const auto& gps = f.r.gps;
  const gather_point<T>& q = gps[0].gp;  // floor_open
  const T n1 = T(4), n2 = T(4);
  const auto dist_of = [&](int) -> const defensive_mixture<T>& { return f.flux; };
  const ris_mis_target<T, decltype(dist_of)> target{&f.r.view, &dist_of, n1, n2, vpl_mode::point, f.tol};
  counter_rng rng = make_counter_rng(7u, 0u);
  const ris_reservoir<T> full = ris_mis_resample(gps[1].gp, f.r.view, f.flux, rng, 16, n1, n2, vpl_mode::point, f.tol);
  REQUIRE(ris_reservoir_has_sample(full));
  // The target at the neighbour's own point is what its candidate pass stored.
  CHECK(target(1, gps[1].gp, full.kept) == full.target);
  ris_reservoir<T> empty;
  empty.confidence = T(16);  // candidates seen, none kept
  const T u[ris_max_neighbours + 1] = {T(0.5), T(0.5), T(0.5)};
  const int pixels[2] = {0, 1};
  for (const ris_reuse_mis mis : {ris_reuse_mis::pairwise, ris_reuse_mis::balance}) {
    INFO("mis " << int(mis));
    // Canonical empty, one neighbour with a sample: the neighbour's sample, the receiver's target.
    const auto load_full = [&](int) { return ris_neighbour<T>{gps[1].gp, full}; };
    const ris_reservoir<T> a = ris_combine_with(q, 0, empty, pixels, 1, load_full, u, mis, target);
    CHECK(a.confidence == T(32));
    if (ris_reservoir_has_sample(a)) {
      CHECK(ris_same_sample(a.kept, full.kept));
      CHECK(a.target == target(0, q, full.kept));
      CHECK(finite_nonneg(ris_mis_shade(q, f.r.view, f.flux, a, f.r.vis, n1, n2, vpl_mode::point, f.tol)));
    } else {
      CHECK(target(0, q, full.kept) == T(0));  // only a zero target at q may drop it
    }
    // Everything empty: an empty reservoir, value 0.
    const auto load_empty = [&](int) { return ris_neighbour<T>{gps[1].gp, empty}; };
    const ris_reservoir<T> b = ris_combine_with(q, 0, empty, pixels, 2, load_empty, u, mis, target);
    CHECK_FALSE(ris_reservoir_has_sample(b));
    CHECK(ris_mis_shade(q, f.r.view, f.flux, b, f.r.vis, n1, n2, vpl_mode::point, f.tol) == vec3<T>(T(0)));
    // Zero confidences everywhere: empty, never a division by 0.
    const ris_reservoir<T> none;
    const auto load_none = [&](int) { return ris_neighbour<T>{gps[1].gp, none}; };
    const ris_reservoir<T> c = ris_combine_with(q, 0, none, pixels, 2, load_none, u, mis, target);
    CHECK_FALSE(ris_reservoir_has_sample(c));
    CHECK(c.confidence == T(0));
    // A background neighbour: its target is 0 everywhere (it adds only confidence); the canonical
    // keeps its sample with its whole weight.
    const gather_point<T> background{q.position, vec3<T>(T(0)), q.albedo};
    const ris_reservoir<T> own = ris_mis_resample(q, f.r.view, f.flux, rng, 16, n1, n2, vpl_mode::point, f.tol);
    REQUIRE(ris_reservoir_has_sample(own));
    CHECK(target(1, background, own.kept) == T(0));
    const auto load_bg = [&](int) { return ris_neighbour<T>{background, empty}; };
    const ris_reservoir<T> d = ris_combine_with(q, 0, own, pixels, 2, load_bg, u, mis, target);
    CHECK(ris_same_sample(d.kept, own.kept));
    CHECK(d.confidence == T(48));
    CHECK(finite_nonneg(ris_mis_shade(q, f.r.view, f.flux, d, f.r.vis, n1, n2, vpl_mode::point, f.tol)));
    // An invalid receiver: empty.
    const ris_reservoir<T> e = ris_combine_with(background, 0, own, pixels, 2, load_full, u, mis, target);
    CHECK_FALSE(ris_reservoir_has_sample(e));
  }
}

TEMPLATE_TEST_CASE("ris-mis hard case: reuse where the receiver's target is 0", "[hardcases][ris-mis]", float, double) {
  using T = TestType;
  const room<T> f;
  const auto& gps = f.r.gps;
  const T n1 = T(4), n2 = T(4);
  counter_rng rng = make_counter_rng(8u, 0u);
  const ris_reservoir<T> full = ris_mis_resample(gps[1].gp, f.r.view, f.flux, rng, 16, n1, n2, vpl_mode::point, f.tol);
  REQUIRE(ris_reservoir_has_sample(full));
  const auto load = [&](int) { return ris_neighbour<T>{gps[1].gp, full}; };
  const T u[ris_max_neighbours + 1] = {T(0.5), T(0.5), T(0.5)};
  const int pixels[2] = {1, 1};
  for (const ris_reuse_mis mis : {ris_reuse_mis::pairwise, ris_reuse_mis::balance}) {
    INFO("mis " << int(mis));
    // A receiver no VPL lights (floor_open facing into the floor): every target at q is 0.
    gather_point<T> dark = gps[0].gp;
    dark.normal = -dark.normal;
    const auto flux_of = [&](int) -> const defensive_mixture<T>& { return f.flux; };
    const ris_mis_target<T, decltype(flux_of)> t_flux{&f.r.view, &flux_of, n1, n2, vpl_mode::point, f.tol};
    const ris_reservoir<T> own = ris_mis_resample(dark, f.r.view, f.flux, rng, 16, n1, n2, vpl_mode::point, f.tol);
    CHECK_FALSE(ris_reservoir_has_sample(own));
    const ris_reservoir<T> a = ris_combine_with(dark, 0, own, pixels, 2, load, u, mis, t_flux);
    CHECK_FALSE(ris_reservoir_has_sample(a));
    CHECK(a.confidence == T(48));
    CHECK(ris_mis_shade(dark, f.r.view, f.flux, a, f.r.vis, n1, n2, vpl_mode::point, f.tol) == vec3<T>(T(0)));
    // A receiver whose own distribution cannot draw the neighbour's texel (pmf 0 there): h_q = 0, so
    // the neighbour's sample is never taken, whatever its weight at the neighbour.
    std::vector<T> w = build_flux_weights(f.r.view);
    w[std::size_t(full.kept.texel)] = T(0);
    const discrete_cdf<T> holed(w);
    const auto mixed_pmf = [&](int p) {
      struct either {
        const defensive_mixture<T>* a;
        const discrete_cdf<T>* b;
        T pmf(std::size_t i) const { return a ? a->pmf(i) : b->pmf(i); }
      };
      return p == 0 ? either{nullptr, &holed} : either{&f.flux, nullptr};
    };
    const ris_mis_target<T, decltype(mixed_pmf)> t_mixed{&f.r.view, &mixed_pmf, n1, n2, vpl_mode::point, f.tol};
    CHECK(t_mixed(0, gps[0].gp, full.kept) == T(0));
    CHECK(t_mixed(1, gps[1].gp, full.kept) == full.target);
    ris_reservoir<T> empty;
    empty.confidence = T(16);
    const ris_reservoir<T> b = ris_combine_with(gps[0].gp, 0, empty, pixels, 2, load, u, mis, t_mixed);
    CHECK_FALSE(ris_reservoir_has_sample(b));
    CHECK(b.weight_sum == T(0));
  }
}

TEMPLATE_TEST_CASE("ris-mis hard case: reuse with more neighbours than the bound, tiny images, NaN numbers",
                   "[hardcases][ris-mis]", float, double) {
  using T = TestType;
  const room<T> f;
  const gbuffer_data<T> gb = f.r.scene.make_gbuffer(3, 2);
  const auto g = gb.view();
  const T n1 = T(2), n2 = T(3);
  std::vector<ris_reservoir<T>> res(std::size_t(g.pixel_count()));
  for (int p = 0; p < g.pixel_count(); ++p) {
    counter_rng r = make_counter_rng(8u, std::uint32_t(p));
    res[std::size_t(p)] = ris_mis_resample(g.at(p), f.r.view, f.flux, r, 4, n1, n2, vpl_mode::patch, f.tol);
  }
  const auto load = [&](int p) { return ris_neighbour<T>{g.at(p), res[std::size_t(p)]}; };
  const auto dist_of = [&](int) -> const defensive_mixture<T>& { return f.flux; };
  ris_spatial_settings<T> s;
  s.neighbours = 1000;
  s.radius = 100;
  s.min_normal_cos = T(-2);
  s.max_plane_slope = std::numeric_limits<T>::infinity();
  for (int p = 0; p < g.pixel_count(); ++p) {
    counter_rng rng = make_counter_rng(9u, std::uint32_t(p));
    const ris_reservoir<T> out = ris_mis_spatial_reuse(g.at(p), p, g.width, g.height, f.r.view, res[std::size_t(p)],
                                                       load, s, rng, dist_of, n1, n2, vpl_mode::patch, f.tol);
    CHECK(rng.counter == std::uint32_t(1 + 3 * ris_max_neighbours));
    CHECK(finite_nonneg(ris_mis_shade(g.at(p), f.r.view, f.flux, out, f.r.vis, n1, n2, vpl_mode::patch, f.tol)));
    CHECK(out.confidence <= T(4 * (1 + ris_max_neighbours)));
  }
  const T nan = std::numeric_limits<T>::quiet_NaN();
  const T u[3] = {nan, T(-1), T(5)};
  const int pixels[2] = {1, 2};
  const ris_mis_target<T, decltype(dist_of)> target{&f.r.view, &dist_of, n1, n2, vpl_mode::patch, f.tol};
  const ris_reservoir<T> out = ris_combine_with(g.at(0), 0, res[0], pixels, 2, load, u, ris_reuse_mis::pairwise, target);
  CHECK(finite_nonneg(ris_mis_shade(g.at(0), f.r.view, f.flux, out, f.r.vis, n1, n2, vpl_mode::patch, f.tol)));
}
