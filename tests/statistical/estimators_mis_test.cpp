// SPDX-License-Identifier: MIT
// mis_mode::as_published (the paper's eq. 7-15 and Alg. 4-6, evaluated as published) is biased;
// mis_mode::solid_angle (docs/math.md section 5) is not. Same scene, CDF, sample counts and
// reference:
//   I = the continuous one-bounce integral seen through the DPRSM (512^2 midpoint quadrature),
//   E = each mode's exact expectation (quadrature of its gathering samples + exact sum of its VPL
//       samples), which the sample mean must match: the bias is the estimator's, not noise.
// Printed: mean +- standard error, I, E, and the significance z = |mean - I| / sigma_mean.
#include <estimators_reference.hpp>
#include <synthetic_scene.hpp>

#include <vplkit/distribution/discrete_cdf.hpp>
#include <vplkit/estimators/mis_estimator.hpp>
#include <vplkit/estimators/vpl_sum.hpp>

#include <catch2/catch.hpp>

#include <cstdio>
#include <vector>

using namespace vplkit;
using namespace vplkit_test;

namespace {
constexpr double depth_tol = 0.2;
constexpr int quad_m = 512;
}  // namespace

TEST_CASE("MIS as_published is biased, MIS solid_angle is not") {
  const lit_room<double> room(64);
  const auto& [scene, dprsm, view, gps, vis, tracer] = room;
  const discrete_cdf<double> cdf(importance_weights(view, plain_points(gps), 0.02));
  const int runs = 2000, n = 8;  // n_dirs = n_vpls = 8 (the paper: 800 and 800)
  std::printf("MIS, %d runs x (%d dirs + %d VPLs), R = 64; values are luminances\n", runs, n, n);
  std::printf("  %-20s %-10s %-22s %-9s %-9s %-8s %-8s\n", "gather point", "mode", "mean +- sigma", "I", "E",
              "(m-I)/I", "z(I)");
  int biased_points = 0;
  for (const auto& g : gps) {
    const vec3<double> I = gathering_integral(scene, view, g.gp, depth_tol, quad_m);
    const double li = luminance(I);
    for (mis_mode mode : {mis_mode::solid_angle, mis_mode::as_published}) {
      const bool pub = mode == mis_mode::as_published;
      const vec3<double> E = mis_expectation(scene, view, cdf, g.gp, n, n, depth_tol, mode, quad_m);
      const run_stats r = repeat_estimates(runs, pub ? 72u : 71u, [&](counter_rng& rng) {
        return estimate_mis(g.gp, view, cdf, rng, n, n, tracer, vis, depth_tol, mode);
      });
      const double z = std::abs(r.lum_mean - li) / r.lum_sem;
      std::printf("  %-20s %-10s %.6f +- %.6f  %.6f  %.6f  %+6.1f%%  %7.1f\n", g.name.c_str(),
                  pub ? "published" : "solid", r.lum_mean, r.lum_sem, li, luminance(E),
                  100.0 * (r.lum_mean / li - 1.0), z);
      INFO(g.name << (pub ? " as_published" : " solid_angle"));
      // each mode converges to its own expectation (quadrature accuracy of E: ~2e-3 relative for
      // the paper's 1/sin(theta) integrand)
      CHECK(within_sigma(r, E, 4.0, 3e-3 * E));
      if (!pub) {
        // discretisation only (up to 1.01 %, at wall_red: estimators_unbiased_test gives the reason)
        CHECK(std::abs(luminance(E) / li - 1.0) < 0.015);
        CHECK(z < 4.0 + 0.01 * li / r.lum_sem);
      } else {
        // the paper's estimator is off by more than 10 % and more than 5 sigma (two-sided
        // p < 6e-7) at every point
        CHECK(std::abs(luminance(E) / li - 1.0) > 0.10);
        CHECK(z > 5.0);
        if (z > 5.0) ++biased_points;
      }
    }
  }
  CHECK(biased_points == int(gps.size()));
}
