// SPDX-License-Identifier: MIT
// Defensive mixing (docs/math.md section 3, defensive mixing): a CDF with zero weight on VPLs that
// contribute gives a biased estimate (it converges to the sum over the VPLs it covers); mixing in
// eps > 0 of a uniform distribution over the valid texels removes the bias; eps = 0 reproduces the
// plain CDF exactly. Here the CDF's back paraboloid (the ceiling and the upper walls) is zeroed, as
// a badly filled GBG CDF or a builder ignoring part of the map would leave it.
#include <estimators_reference.hpp>
#include <synthetic_scene.hpp>

#include <vplkit/distribution/defensive_mixture.hpp>
#include <vplkit/distribution/discrete_cdf.hpp>
#include <vplkit/estimators/vpl_sampling_estimator.hpp>
#include <vplkit/estimators/vpl_sum.hpp>

#include <catch2/catch.hpp>

#include <cstdio>
#include <vector>

using namespace vplkit;
using namespace vplkit_test;

TEST_CASE("a CDF with holes is biased, the defensive mixture is not") {
  const synthetic_scene<double> scene;
  const int R = 32;
  const dprsm_data<double> d = scene.make_dprsm(R);
  const dprsm_view<double> view = d.view();
  const exact_visibility<double> vis{&scene};
  const auto gps = scene.gather_points();
  std::vector<double> w = importance_weights(view, plain_points(gps), 0.02);
  for (std::size_t t = std::size_t(R) * R; t < w.size(); ++t) w[t] = 0.0;  // back face: holes
  const discrete_cdf<double> holed(w);
  const std::vector<double> uni = uniform_valid_weights(view);
  const defensive_mixture<double> mix(discrete_cdf<double>(w), discrete_cdf<double>(uni), 0.1);
  const defensive_mixture<double> mix0(discrete_cdf<double>(w), discrete_cdf<double>(uni), 0.0);
  const int runs = 1000, n = 16;
  std::printf("defensive mixing, back face zeroed, %d runs x %d samples\n", runs, n);
  for (int gi : {0, 3, 5}) {  // floor_open, wall_red: lit by the ceiling; block_bottom: not
    const auto& g = gps[std::size_t(gi)];
    const vec3<double> ref = exhaustive_vpl_sum(g.gp, view, vis, 0.0);
    // what the holed CDF converges to: the sum over the texels it covers
    vec3<double> covered(0.0);
    for (int t = 0; t < view.texel_count(); ++t)
      if (holed.pmf(std::size_t(t)) > 0.0) covered += vpl_visible_contribution(g.gp, view, t, vis, 0.0);
    const run_stats h = repeat_estimates(runs, 91u, [&](counter_rng& rng) {
      return estimate_vpl_sampling(g.gp, view, holed, rng, n, vis, 0.0);
    });
    const run_stats m = repeat_estimates(runs, 92u, [&](counter_rng& rng) {
      return estimate_vpl_sampling(g.gp, view, mix, rng, n, vis, 0.0);
    });
    std::printf("  %-14s ref %.6f covered %.6f | holed CDF %.6f +- %.6f (z %.1f) | defensive eps=0.1 %.6f +- %.6f (z %.1f)\n",
                g.name.c_str(), luminance(ref), luminance(covered), h.lum_mean, h.lum_sem, z_score(h, ref), m.lum_mean,
                m.lum_sem, z_score(m, ref));
    INFO(g.name);
    CHECK(within_sigma(h, covered, 4.0, 1e-9 * covered));  // converges to the covered part ...
    CHECK(within_sigma(m, ref, 4.0, 1e-9 * ref));          // the mixture to the whole sum
    const double missing = 1.0 - luminance(covered) / luminance(ref);
    if (gi == 5) {
      CHECK(missing < 1e-12);  // block_bottom sees only the floor: no bias to show
    } else {
      CHECK(missing > 0.05);
      CHECK(z_score(h, ref) > 10.0);  // ... which is measurably off the reference
    }
    // eps = 0 is the plain CDF, sample for sample
    counter_rng r1 = make_counter_rng(7u, std::uint32_t(gi)), r2 = r1;
    const vec3<double> e_holed = estimate_vpl_sampling(g.gp, view, holed, r1, n, vis, 0.0);
    const vec3<double> e_mix0 = estimate_vpl_sampling(g.gp, view, mix0, r2, n, vis, 0.0);
    CHECK(e_holed == e_mix0);
  }
}
