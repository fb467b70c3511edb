// SPDX-License-Identifier: MIT
// docs/math.md section 10 for the resampled estimator and its spatial reuse, each case its own test:
// all candidates zero, one candidate (a distribution over one texel), NaN and infinite targets and
// weights, empty distributions and indices outside the view, M = 0 and 1, and for the reuse a
// canonical reservoir without a sample, neighbours without samples, confidences of zero and more
// neighbours than the bound. Nothing may be NaN or Inf, in float and double.
#include <estimator_checks.hpp>
#include <synthetic_scene.hpp>

#include <vplkit/builders/flux_weights.hpp>
#include <vplkit/builders/vpl_distribution.hpp>
#include <vplkit/distribution/discrete_cdf.hpp>
#include <vplkit/distribution/weighted_reservoir.hpp>
#include <vplkit/estimators/ris_estimator.hpp>
#include <vplkit/estimators/ris_spatial_reuse.hpp>
#include <vplkit/estimators/vpl_sum.hpp>
#include <vplkit/vpl/luminance.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <vector>

using namespace vplkit;
using namespace vplkit_test;

namespace {

template <class T>
struct room {
  lit_room<T> r{16};
  defensive_mixture<T> flux = make_vpl_distribution(build_flux_weights(r.view), r.view, T(0));
  int lit_texel() const {  // a texel whose VPL lights floor_open
    for (int t = 0; t < r.view.texel_count(); ++t)
      if (luminance(vpl_visible_contribution(r.gps[0].gp, r.view, t, r.vis, T(0))) > T(0)) return t;
    return -1;
  }
};

}  // namespace

TEMPLATE_TEST_CASE("ris hard case: every candidate has target 0", "[hardcases][ris]", float, double) {
  using T = TestType;
  const room<T> f;
  gather_point<T> gp = f.r.gps[0].gp;
  gp.normal = -gp.normal;  // floor_open facing into the floor: no VPL above it
  for (const vpl_mode mode : {vpl_mode::point, vpl_mode::patch}) {
    counter_rng rng = make_counter_rng(1u, 0u);
    const ris_reservoir<T> r = ris_resample(gp, f.r.view, f.flux, rng, 32, T(0), mode);
    CHECK(r.kept.texel == -1);
    CHECK(r.weight_sum == T(0));
    CHECK(r.confidence == T(32));
    CHECK_FALSE(ris_reservoir_has_sample(r));
    CHECK(ris_contribution_weight(r) == T(0));
    CHECK(ris_shade(gp, f.r.view, r, f.r.vis, T(0), mode) == vec3<T>(T(0)));
    CHECK(estimate_ris(gp, f.r.view, f.flux, rng, 4, 16, f.r.vis, T(0), mode) == vec3<T>(T(0)));
  }
  // Zero intensity: every flux is 0, so is every target.
  dprsm_view<T> dark = f.r.view;
  dark.light.intensity = vec3<T>(T(0));
  counter_rng rng = make_counter_rng(1u, 0u);
  CHECK(estimate_ris(f.r.gps[0].gp, dark, f.flux, rng, 4, 16, f.r.vis, T(0)) == vec3<T>(T(0)));
}

TEMPLATE_TEST_CASE("ris hard case: one candidate texel gives that texel's term exactly", "[hardcases][ris]", float,
                   double) {
  using T = TestType;
  const room<T> f;
  const int t = f.lit_texel();
  REQUIRE(t >= 0);
  const gather_point<T>& gp = f.r.gps[0].gp;
  const fixed_draw<T> one{std::size_t(t), T(1)};
  const vec3<T> term = vpl_visible_contribution(gp, f.r.view, t, f.r.vis, T(0));
  for (const int m : {1, 7, 64}) {
    counter_rng rng = make_counter_rng(2u, 0u);
    const vec3<T> e = estimate_ris(gp, f.r.view, one, rng, 3, m, f.r.vis, T(0));
    INFO("M = " << m);
    // W = (1/M) (M p_hat) / p_hat: the term up to the rounding of the sum and two divisions.
    const T tol = std::is_same<T, float>::value ? T(1e-5) : T(1e-13);
    for (int c = 0; c < 3; ++c) CHECK(std::abs(e[c] - term[c]) <= tol * term[c]);
  }
}

TEMPLATE_TEST_CASE("ris hard case: NaN and infinite targets and weights are skipped", "[hardcases][ris]", float,
                   double) {
  using T = TestType;
  const T nan = std::numeric_limits<T>::quiet_NaN(), inf = std::numeric_limits<T>::infinity();
  // The reservoir itself.
  weighted_reservoir<T> r;
  CHECK_FALSE(reservoir_update(r, 0u, nan, T(0.5)));
  CHECK_FALSE(reservoir_update(r, 1u, inf, T(0.5)));
  CHECK_FALSE(reservoir_update(r, 2u, -T(1), T(0.5)));
  CHECK_FALSE(reservoir_update(r, 3u, T(0), T(0.5)));
  CHECK(reservoir_empty_of(r));
  CHECK(r.weight_sum == T(0));
  CHECK(reservoir_update(r, 4u, std::numeric_limits<T>::max(), T(0.999)));  // the first usable is kept
  CHECK_FALSE(reservoir_update(r, 5u, std::numeric_limits<T>::max(), T(0)));  // would overflow the sum
  CHECK(r.index == 4u);
  CHECK(r.weight_sum == std::numeric_limits<T>::max());
  weighted_reservoir<T> d;  // the smallest normal weight is kept too, whatever u
  CHECK(reservoir_update(d, 7u, std::numeric_limits<T>::min(), T(0.9)));
  CHECK(d.index == 7u);
  // Denormal weights count as 0 (the normal-range contract, docs/math.md, "GPU arithmetic model"):
  // a GPU may flush them, so no device keeps them.
  weighted_reservoir<T> dn;
  CHECK_FALSE(reservoir_update(dn, 8u, std::numeric_limits<T>::denorm_min(), T(0)));
  CHECK_FALSE(reservoir_update(dn, 9u, std::numeric_limits<T>::min() / T(4), T(0)));
  CHECK(reservoir_empty_of(dn));
  CHECK(dn.weight_sum == T(0));
  weighted_reservoir<T> u;  // u outside [0, 1): NaN, negative and >= 1 are clamped
  CHECK(reservoir_update(u, 0u, T(1), nan));
  CHECK(reservoir_update(u, 1u, T(1), -T(3)));   // u 0: kept
  CHECK_FALSE(reservoir_update(u, 2u, T(1), T(7)));  // u just below 1: 3 (1 - eps) > 1
  CHECK(u.index == 1u);
  // A denormal pmf counts as 0 (estimator_pmf), so the candidate adds nothing: denorm_min, whose
  // p_hat / p would overflow, and min / 4, whose p_hat / p would be a finite weight.
  const room<T> f;
  const int t = f.lit_texel();
  const gather_point<T>& gp = f.r.gps[0].gp;
  for (const T p : {std::numeric_limits<T>::denorm_min(), std::numeric_limits<T>::min() / T(4)}) {
    INFO("pmf " << p);
    const fixed_draw<T> tiny{std::size_t(t), p};
    counter_rng rng = make_counter_rng(3u, 0u);
    const ris_reservoir<T> res = ris_resample(gp, f.r.view, tiny, rng, 8, T(0));
    CHECK_FALSE(ris_reservoir_has_sample(res));
    CHECK(finite_nonneg(estimate_ris(gp, f.r.view, tiny, rng, 2, 8, f.r.vis, T(0))));
  }
  counter_rng rng = make_counter_rng(3u, 0u);
  // NaN and infinite albedo at the gather point: NaN / infinite targets, skipped.
  for (const T a : {nan, inf}) {
    gather_point<T> g = gp;
    g.albedo = vec3<T>(a, T(0.5), T(0.5));
    const ris_reservoir<T> q = ris_resample(g, f.r.view, f.flux, rng, 16, T(0));
    CHECK_FALSE(ris_reservoir_has_sample(q));
    CHECK(finite_nonneg(estimate_ris(g, f.r.view, f.flux, rng, 2, 16, f.r.vis, T(0))));
    CHECK(ris_target(g, f.r.view.vpl_at(t), T(0)) == T(0));
  }
}

TEMPLATE_TEST_CASE("ris hard case: empty distributions and indices outside the view", "[hardcases][ris]", float,
                   double) {
  using T = TestType;
  const room<T> f;
  const gather_point<T>& gp = f.r.gps[0].gp;
  const discrete_cdf<T> empty(std::vector<T>(std::size_t(f.r.view.texel_count()), T(0)));
  const discrete_cdf<T> none;
  const fixed_draw<T> outside{std::size_t(f.r.view.texel_count()), T(1)};
  for (const vpl_mode mode : {vpl_mode::point, vpl_mode::patch}) {
    counter_rng a = make_counter_rng(4u, 0u), b = a, c = a;
    CHECK(estimate_ris(gp, f.r.view, empty, a, 3, 8, f.r.vis, T(0), mode) == vec3<T>(T(0)));
    CHECK(estimate_ris(gp, f.r.view, none, b, 3, 8, f.r.vis, T(0), mode) == vec3<T>(T(0)));
    CHECK(estimate_ris(gp, f.r.view, outside, c, 3, 8, f.r.vis, T(0), mode) == vec3<T>(T(0)));
    // The numbers are drawn all the same: the stream layout does not depend on the scene.
    const std::uint32_t per = mode == vpl_mode::patch ? 4u : 2u;
    CHECK(a.counter == 3u * 8u * per);
    CHECK(b.counter == a.counter);
    CHECK(c.counter == a.counter);
  }
}

TEMPLATE_TEST_CASE("ris hard case: M = 0 and M = 1", "[hardcases][ris]", float, double) {
  using T = TestType;
  const room<T> f;
  const gather_point<T>& gp = f.r.gps[0].gp;
  counter_rng rng = make_counter_rng(5u, 0u);
  const ris_reservoir<T> zero = ris_resample(gp, f.r.view, f.flux, rng, 0, T(0));
  CHECK(zero.confidence == T(0));
  CHECK_FALSE(ris_reservoir_has_sample(zero));
  CHECK(estimate_ris(gp, f.r.view, f.flux, rng, 4, 0, f.r.vis, T(0)) == vec3<T>(T(0)));
  CHECK(rng.counter == 0u);
  ris_reservoir<T> res[ris_max_kept];
  ris_resample_candidates(gp, f.r.view, f.flux, rng, 8, res, 0, T(0));  // keep none
  CHECK(rng.counter == 0u);
  // M = 1: the candidate is kept whenever its weight is usable; W = 1 / p.
  int kept = 0;
  for (std::uint32_t s = 0; s < 64; ++s) {
    counter_rng r = make_counter_rng(6u, s);
    const ris_reservoir<T> one = ris_resample(gp, f.r.view, f.flux, r, 1, T(0));
    if (!ris_reservoir_has_sample(one)) continue;
    ++kept;
    const T w = ris_contribution_weight(one);
    const T p = f.flux.pmf(std::size_t(one.kept.texel));
    CHECK(std::abs(w * p - T(1)) <= T(1e-5));
  }
  CHECK(kept > 10);
}

TEMPLATE_TEST_CASE("ris hard case: reuse with empty inputs and zero confidences", "[hardcases][ris]", float, double) {
  using T = TestType;
  const room<T> f;
  const auto& gps = f.r.gps;
  const gather_point<T>& q = gps[0].gp;  // floor_open
  counter_rng rng = make_counter_rng(7u, 0u);
  const ris_reservoir<T> full = ris_resample(gps[1].gp, f.r.view, f.flux, rng, 16, T(0));  // floor_shadow's
  REQUIRE(ris_reservoir_has_sample(full));
  ris_reservoir<T> empty;
  empty.confidence = T(16);  // candidates seen, none kept
  const T u[ris_max_neighbours + 1] = {T(0.5), T(0.5), T(0.5)};
  const int pixels[2] = {0, 1};
  for (const ris_reuse_mis mis : {ris_reuse_mis::pairwise, ris_reuse_mis::balance}) {
    INFO("mis " << int(mis));
    // Canonical empty, one neighbour with a sample: the output holds the neighbour's sample with
    // the receiver's target.
    const auto load_full = [&](int) { return ris_neighbour<T>{gps[1].gp, full}; };
    const ris_reservoir<T> a = ris_combine(q, f.r.view, empty, pixels, 1, load_full, u, mis, T(0));
    CHECK(a.confidence == T(32));
    REQUIRE(ris_reservoir_has_sample(a));  // floor_shadow's sample lights floor_open too
    CHECK(ris_same_sample(a.kept, full.kept));
    CHECK(a.target == ris_target(q, f.r.view.vpl_at(full.kept.texel), T(0)));
    CHECK(std::isfinite(ris_contribution_weight(a)));
    // Everything empty: an empty reservoir, value 0.
    const auto load_empty = [&](int) { return ris_neighbour<T>{gps[1].gp, empty}; };
    const ris_reservoir<T> b = ris_combine(q, f.r.view, empty, pixels, 2, load_empty, u, mis, T(0));
    CHECK_FALSE(ris_reservoir_has_sample(b));
    CHECK(ris_shade(q, f.r.view, b, f.r.vis, T(0)) == vec3<T>(T(0)));
    // Zero confidences everywhere (no candidates at all): empty, never a division by 0.
    const ris_reservoir<T> none;
    const auto load_none = [&](int) { return ris_neighbour<T>{gps[1].gp, none}; };
    const ris_reservoir<T> c = ris_combine(q, f.r.view, none, pixels, 2, load_none, u, mis, T(0));
    CHECK_FALSE(ris_reservoir_has_sample(c));
    CHECK(c.confidence == T(0));
    // A background neighbour: its target at the canonical sample is 0 (it adds only confidence).
    const gather_point<T> background{q.position, vec3<T>(T(0)), q.albedo};
    const ris_reservoir<T> own = ris_resample(q, f.r.view, f.flux, rng, 16, T(0));
    const auto load_bg = [&](int) { return ris_neighbour<T>{background, empty}; };
    const ris_reservoir<T> d = ris_combine(q, f.r.view, own, pixels, 2, load_bg, u, mis, T(0));
    CHECK(finite_nonneg(ris_shade(q, f.r.view, d, f.r.vis, T(0))));
    CHECK(d.confidence == T(48));
    // An invalid receiver: empty, no neighbour asked.
    const ris_reservoir<T> e = ris_combine(background, f.r.view, own, pixels, 2, load_full, u, mis, T(0));
    CHECK_FALSE(ris_reservoir_has_sample(e));
  }
}

TEMPLATE_TEST_CASE("ris hard case: more neighbours than the bound, tiny images, NaN numbers", "[hardcases][ris]",
                   float, double) {
  using T = TestType;
  const room<T> f;
  const gbuffer_data<T> gb = f.r.scene.make_gbuffer(3, 2);
  const auto g = gb.view();
  std::vector<ris_reservoir<T>> res(std::size_t(g.pixel_count()));
  for (int p = 0; p < g.pixel_count(); ++p) {
    counter_rng r = make_counter_rng(8u, std::uint32_t(p));
    res[std::size_t(p)] = ris_resample(g.at(p), f.r.view, f.flux, r, 4, T(0));
  }
  const auto load = [&](int p) { return ris_neighbour<T>{g.at(p), res[std::size_t(p)]}; };
  ris_spatial_settings<T> s;
  s.neighbours = 1000;
  s.radius = 100;
  s.min_normal_cos = T(-2);
  s.max_plane_slope = std::numeric_limits<T>::infinity();
  for (int p = 0; p < g.pixel_count(); ++p) {
    counter_rng rng = make_counter_rng(9u, std::uint32_t(p));
    const ris_reservoir<T> out = ris_spatial_reuse(g.at(p), p, g.width, g.height, f.r.view, res[std::size_t(p)], load, s,
                                                   rng, T(0));
    CHECK(rng.counter == std::uint32_t(1 + 3 * ris_max_neighbours));
    CHECK(finite_nonneg(ris_shade(g.at(p), f.r.view, out, f.r.vis, T(0))));
    CHECK(out.confidence <= T(4 * (1 + ris_max_neighbours)));
  }
  // Selection numbers that are NaN or out of range are clamped by the reservoir.
  const T nan = std::numeric_limits<T>::quiet_NaN();
  const T u[3] = {nan, T(-1), T(5)};
  const int pixels[2] = {1, 2};
  const ris_reservoir<T> out = ris_combine(g.at(0), f.r.view, res[0], pixels, 2, load, u, ris_reuse_mis::pairwise, T(0));
  CHECK(finite_nonneg(ris_shade(g.at(0), f.r.view, out, f.r.vis, T(0))));
}
