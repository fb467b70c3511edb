// SPDX-License-Identifier: MIT
// Local CDFs at a seam (docs/math.md section 4): two image regions, one seeing only the floor, the
// other only the ceiling. Each region's CDF (built like the global builder from that region's
// points, V = 1) gives weight 0 to VPLs that cannot reach its own points -- the floor CDF misses
// the floor and the block top (coplanar or facing away), the ceiling CDF misses the ceiling -- yet
// points on the walls between the regions receive light from all of them.
//   holes:   average (as published) is biased (each CDF's missing share is lost), balance is not;
//   covered: with a small flux floor every CDF covers every VPL; both are unbiased, and balance has
//            the smaller variance (a VPL rare under one CDF is divided by the SUM of the pmfs).
// Variances of one estimate are printed.
#include <estimators_reference.hpp>
#include <synthetic_scene.hpp>

#include <vplkit/distribution/discrete_cdf.hpp>
#include <vplkit/estimators/local_estimator.hpp>
#include <vplkit/estimators/vpl_sum.hpp>

#include <catch2/catch.hpp>

#include <cstdio>
#include <vector>

using namespace vplkit;
using namespace vplkit_test;

namespace {

// A 6 x 6 grid of points on the floor (y = 0) or on the ceiling (y = 3).
std::vector<gather_point<double>> region_points(const synthetic_scene<double>& s, bool ceiling) {
  std::vector<gather_point<double>> pts;
  const double y = ceiling ? 3.0 : 0.0;
  const vec3<double> n(0.0, ceiling ? -1.0 : 1.0, 0.0);
  for (int i = 0; i < 6; ++i)
    for (int j = 0; j < 6; ++j) {
      const vec3<double> p(-1.75 + 0.7 * i, y, -1.75 + 0.7 * j);
      pts.push_back(gather_point<double>{p, n, s.intersect(p + 0.01 * n, -n).albedo});
    }
  return pts;
}

}  // namespace

TEST_CASE("local balance vs average at a seam: bias with holes, variance without") {
  const synthetic_scene<double> scene;
  const dprsm_data<double> d = scene.make_dprsm(32);
  const dprsm_view<double> view = d.view();
  const exact_visibility<double> vis{&scene};
  const auto floor_pts = region_points(scene, false), ceil_pts = region_points(scene, true);
  const auto gps = scene.gather_points();
  const int runs = 2000, rounds = 4;

  for (double floor_eps : {0.0, 0.01}) {
    const discrete_cdf<double> cdfs[2] = {discrete_cdf<double>(importance_weights(view, floor_pts, floor_eps)),
                                          discrete_cdf<double>(importance_weights(view, ceil_pts, floor_eps))};
    // how much of the picture each CDF misses
    int holes[2] = {0, 0};
    for (int t = 0; t < view.texel_count(); ++t)
      for (int i = 0; i < 2; ++i)
        if (luminance(view.vpl_at(t).flux) > 0.0 && cdfs[i].pmf(std::size_t(t)) == 0.0) ++holes[i];
    std::printf("%s: floor CDF misses %d lit VPLs, ceiling CDF %d (R = 32, %d runs x %d rounds x 2 CDFs)\n",
                floor_eps > 0 ? "covered" : "holes", holes[0], holes[1], runs, rounds);
    if (floor_eps == 0.0) {
      REQUIRE(holes[0] > 100);
      REQUIRE(holes[1] > 100);
    } else {
      REQUIRE(holes[0] == 0);
      REQUIRE(holes[1] == 0);
    }
    // wall points between the regions, lit by floor and ceiling VPLs
    const named_gather_point<double> wall_green{
        "wall_green", gather_point<double>{vec3<double>(2, 1.5, 0), vec3<double>(-1, 0, 0), vec3<double>(0.2, 0.8, 0.2)},
        false};
    for (const named_gather_point<double>& g : {gps[3], wall_green}) {
      const vec3<double> ref = exhaustive_vpl_sum(g.gp, view, vis, 0.0);
      const run_stats b = repeat_estimates(runs, 81u, [&](counter_rng& rng) {
        return estimate_local(g.gp, view, cdfs, 2, rng, rounds, vis, 0.0, local_combination::balance);
      });
      const run_stats a = repeat_estimates(runs, 82u, [&](counter_rng& rng) {
        return estimate_local(g.gp, view, cdfs, 2, rng, rounds, vis, 0.0, local_combination::average);
      });
      const double lr = luminance(ref);
      const double mse_b = b.lum_var + (b.lum_mean - lr) * (b.lum_mean - lr);
      const double mse_a = a.lum_var + (a.lum_mean - lr) * (a.lum_mean - lr);
      std::printf("  %-12s ref %.6f | balance %.6f +- %.6f var %.3e mse %.3e | average %.6f +- %.6f var %.3e mse %.3e\n",
                  g.name.c_str(), lr, b.lum_mean, b.lum_sem, b.lum_var, mse_b, a.lum_mean, a.lum_sem, a.lum_var, mse_a);
      INFO(g.name << (floor_eps > 0 ? " covered" : " holes"));
      CHECK(within_sigma(b, ref, 4.0, 1e-9 * ref));
      CHECK(mse_b < mse_a);
      if (floor_eps == 0.0) {
        CHECK(z_score(a, ref) > 10.0);  // average loses the share of the missing VPLs
      } else {
        CHECK(within_sigma(a, ref, 4.0, 1e-9 * ref));
        CHECK(b.lum_var < a.lum_var);
      }
    }
  }
}

TEST_CASE("local balance equals average when all CDFs are the same") {
  const synthetic_scene<double> scene;
  const dprsm_data<double> d = scene.make_dprsm(32);
  const dprsm_view<double> view = d.view();
  const exact_visibility<double> vis{&scene};
  const auto gps = scene.gather_points();
  const std::vector<double> w = importance_weights(view, plain_points(gps), 0.02);
  const discrete_cdf<double> cdfs[3] = {discrete_cdf<double>(w), discrete_cdf<double>(w), discrete_cdf<double>(w)};
  for (const auto& g : gps) {
    counter_rng r1 = make_counter_rng(5u, 9u), r2 = r1;
    const vec3<double> b = estimate_local(g.gp, view, cdfs, 3, r1, 5, vis, 0.0, local_combination::balance);
    const vec3<double> a = estimate_local(g.gp, view, cdfs, 3, r2, 5, vis, 0.0, local_combination::average);
    INFO(g.name);
    for (int c = 0; c < 3; ++c) CHECK(b[c] == Approx(a[c]).epsilon(1e-12));
  }
}
