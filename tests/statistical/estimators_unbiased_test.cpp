// SPDX-License-Identifier: MIT
// Every estimator converges to its own reference on the synthetic scene (real occluders, exact
// ray-traced visibility on both sides, so only estimator bias is tested):
//   VPL sampling (discrete_cdf, alias_table, defensive mixture, face roulette), local (balance,
//   average)                 -> the exhaustive VPL sum
//   gathering, MIS (solid angle) -> the continuous one-bounce integral seen through the DPRSM
//                               (midpoint quadrature, 512^2 directions, relative accuracy ~5e-4)
// Criterion: the mean of K independent estimates (streams 0..K-1 of a fixed seed) lies within
// 4 standard errors of the reference on every channel (+ the reference's own accuracy).
// The tables are printed; run the program directly to see them.
#include <estimators_reference.hpp>
#include <synthetic_scene.hpp>

#include <vplkit/distribution/alias_table.hpp>
#include <vplkit/distribution/defensive_mixture.hpp>
#include <vplkit/distribution/discrete_cdf.hpp>
#include <vplkit/distribution/face_roulette.hpp>
#include <vplkit/estimators/gathering_estimator.hpp>
#include <vplkit/estimators/local_estimator.hpp>
#include <vplkit/estimators/mis_estimator.hpp>
#include <vplkit/estimators/vpl_sampling_estimator.hpp>
#include <vplkit/estimators/vpl_sum.hpp>
#include <vplkit/visibility/visibility_callables.hpp>

#include <catch2/catch.hpp>

#include <cstdio>
#include <vector>

using namespace vplkit;
using namespace vplkit_test;

namespace {

constexpr int R = 64;
constexpr double depth_tol = 0.2;
constexpr int quad_m = 512;
constexpr double quad_rel = 1e-3;  // quadrature accuracy claimed (measured ~2e-4 at 512^2)

struct fixture {
  synthetic_scene<double> scene;
  dprsm_data<double> dprsm = scene.make_dprsm(R);
  dprsm_view<double> view = dprsm.view();
  std::vector<named_gather_point<double>> gps = scene.gather_points();
  exact_visibility<double> vis{&scene};
  exact_tracer<double> tracer{&scene};
  // Importance weights from the gather points themselves plus a flux floor: covers every VPL.
  std::vector<double> weights = importance_weights(view, plain_points(gps), 0.02);
};

const fixture& fx() {
  static const fixture f;
  return f;
}

void print_row(const char* what, const std::string& gp, const run_stats& r, vec3<double> ref) {
  std::printf("  %-22s %-20s mean %.6f +- %.6f  ref %.6f  z %.2f\n", what, gp.c_str(), r.lum_mean, r.lum_sem,
              luminance(ref), z_score(r, ref));
}

}  // namespace

TEST_CASE("VPL sampling (discrete_cdf, alias_table, defensive mixture, face roulette) is unbiased for the VPL sum") {
  const fixture& f = fx();
  const vpl_sampling_distributions<double> dists(f.weights, f.view);
  const int runs = 1000, n = 16;
  std::printf("VPL sampling, %d runs x %d samples, R = %d, exact visibility, dmin = 0\n", runs, n, R);
  for (const auto& g : f.gps) {
    const vec3<double> ref = exhaustive_vpl_sum(g.gp, f.view, f.vis, 0.0);
    REQUIRE(luminance(ref) > 0.0);
    const run_stats a = repeat_estimates(runs, 11u, [&](counter_rng& rng) {
      return estimate_vpl_sampling(g.gp, f.view, dists.cdf, rng, n, f.vis, 0.0);
    });
    const run_stats b = repeat_estimates(runs, 12u, [&](counter_rng& rng) {
      return estimate_vpl_sampling(g.gp, f.view, dists.alias, rng, n, f.vis, 0.0);
    });
    const run_stats c = repeat_estimates(runs, 13u, [&](counter_rng& rng) {
      return estimate_vpl_sampling(g.gp, f.view, dists.mix, rng, n, f.vis, 0.0);
    });
    const run_stats d = repeat_estimates(runs, 14u, [&](counter_rng& rng) {
      return estimate_vpl_sampling(g.gp, f.view, dists.roulette, rng, n, f.vis, 0.0);
    });
    print_row("discrete_cdf", g.name, a, ref);
    print_row("alias_table", g.name, b, ref);
    print_row("defensive eps=0.1", g.name, c, ref);
    print_row("face_roulette", g.name, d, ref);
    INFO(g.name);
    const vec3<double> slack = 1e-9 * ref;
    CHECK(within_sigma(a, ref, 4.0, slack));
    CHECK(within_sigma(b, ref, 4.0, slack));
    CHECK(within_sigma(c, ref, 4.0, slack));
    CHECK(within_sigma(d, ref, 4.0, slack));
    // meaningful precision: the standard error is a small fraction of the value
    CHECK(a.lum_sem < 0.05 * luminance(ref));
  }
}

TEST_CASE("VPL sampling with a clamp is unbiased for the clamped VPL sum (float too)") {
  const fixture& f = fx();
  const discrete_cdf<double> cdf(f.weights);
  const auto& g = f.gps[2];  // floor_corner: VPLs on the walls 0.1 away, where dmin bites
  const double dmin = 0.25;
  const vec3<double> ref = exhaustive_vpl_sum(g.gp, f.view, f.vis, dmin);
  const vec3<double> unclamped = exhaustive_vpl_sum(g.gp, f.view, f.vis, 0.0);
  const run_stats a = repeat_estimates(1000, 21u, [&](counter_rng& rng) {
    return estimate_vpl_sampling(g.gp, f.view, cdf, rng, 16, f.vis, dmin);
  });
  print_row("discrete_cdf dmin=0.25", g.name, a, ref);
  std::printf("  (unclamped VPL sum %.6f: the clamp removes %.1f%%)\n", luminance(unclamped),
              100.0 * (1.0 - luminance(ref) / luminance(unclamped)));
  CHECK(within_sigma(a, ref, 4.0, 1e-9 * ref));
  CHECK(luminance(ref) < 0.98 * luminance(unclamped));

  // float: the scene, DPRSM, weights and estimator in float, against the double reference
  // (exact visibility in float: same geometry)
  const synthetic_scene<float> sf;
  const dprsm_data<float> df = sf.make_dprsm(R);
  const dprsm_view<float> vf = df.view();
  std::vector<float> wf(f.weights.begin(), f.weights.end());
  const discrete_cdf<float> cdf_f(wf);
  const exact_visibility<float> vis_f{&sf};
  for (int i : {0, 1, 4}) {
    const auto& gd = f.gps[std::size_t(i)];
    const gather_point<float> gpf{vec3<float>(gd.gp.position), vec3<float>(gd.gp.normal), vec3<float>(gd.gp.albedo)};
    const vec3<double> refd = exhaustive_vpl_sum(gd.gp, f.view, f.vis, 0.0);
    const vec3<double> reff(exhaustive_vpl_sum(gpf, vf, vis_f, 0.0f));
    const run_stats r = repeat_estimates(1000, 22u, [&](counter_rng& rng) {
      return vec3<double>(estimate_vpl_sampling(gpf, vf, cdf_f, rng, 16, vis_f, 0.0f));
    });
    print_row("float discrete_cdf", gd.name, r, reff);
    INFO(gd.name);
    CHECK(within_sigma(r, reff, 4.0, 1e-5 * reff));
    CHECK(std::abs(luminance(reff) - luminance(refd)) < 1e-3 * luminance(refd));  // float vs double DPRSM
  }
}

TEST_CASE("local estimator: balance and average are unbiased where every CDF covers the VPLs") {
  const fixture& f = fx();
  // Four "region" CDFs from different subsets of the G-buffer (quadrants), each with a flux
  // floor so that every CDF covers every VPL: then both combinations are unbiased.
  const gbuffer_data<double> gb = f.scene.make_gbuffer(16, 16);
  std::vector<discrete_cdf<double>> cdfs;
  for (int q = 0; q < 4; ++q) {
    std::vector<gather_point<double>> pts;
    for (int y = (q / 2) * 8; y < (q / 2) * 8 + 8; y += 2)
      for (int x = (q % 2) * 8; x < (q % 2) * 8 + 8; x += 2) pts.push_back(gb.view().at(x, y));
    cdfs.emplace_back(importance_weights(f.view, pts, 0.02));
  }
  const int runs = 1000, rounds = 4;
  std::printf("local, 4 CDFs x %d rounds, %d runs\n", rounds, runs);
  for (const auto& g : f.gps) {
    const vec3<double> ref = exhaustive_vpl_sum(g.gp, f.view, f.vis, 0.0);
    const run_stats b = repeat_estimates(runs, 31u, [&](counter_rng& rng) {
      return estimate_local(g.gp, f.view, cdfs.data(), 4, rng, rounds, f.vis, 0.0, local_combination::balance);
    });
    const run_stats a = repeat_estimates(runs, 32u, [&](counter_rng& rng) {
      return estimate_local(g.gp, f.view, cdfs.data(), 4, rng, rounds, f.vis, 0.0, local_combination::average);
    });
    print_row("local balance", g.name, b, ref);
    print_row("local average", g.name, a, ref);
    INFO(g.name);
    CHECK(within_sigma(b, ref, 4.0, 1e-9 * ref));
    CHECK(within_sigma(a, ref, 4.0, 1e-9 * ref));
  }
}

TEST_CASE("gathering converges to the continuous integral, not to the VPL sum") {
  const fixture& f = fx();
  const int runs = 1000, n_dirs = 16;
  std::printf("gathering, %d runs x %d directions, depth tolerance %.2f, R = %d\n", runs, n_dirs, depth_tol, R);
  std::printf("  references: I = DPRSM-based integral (the estimand), S = VPL sum, P = physical integral\n");
  for (const auto& g : f.gps) {
    const vec3<double> I = gathering_integral(f.scene, f.view, g.gp, depth_tol, quad_m);
    const vec3<double> S = exhaustive_vpl_sum(g.gp, f.view, f.vis, 0.0);
    const vec3<double> P = physical_integral(f.scene, g.gp, quad_m);
    const run_stats r = repeat_estimates(runs, 41u, [&](counter_rng& rng) {
      return estimate_gathering(g.gp, f.view, rng, n_dirs, f.tracer, depth_tol);
    });
    print_row("gathering", g.name, r, I);
    std::printf("  %-22s %-20s I %.6f  S %.6f (S-I)/I %+.2f%%  P %.6f (P-I)/I %+.2f%%\n", "", g.name.c_str(),
                luminance(I), luminance(S), 100.0 * (luminance(S) / luminance(I) - 1.0), luminance(P),
                100.0 * (luminance(P) / luminance(I) - 1.0));
    INFO(g.name);
    CHECK(within_sigma(r, I, 4.0, quad_rel * I));
    // the discretisation of the VPL sum at R = 64 is a few percent here, not more
    CHECK(std::abs(luminance(S) / luminance(I) - 1.0) < 0.05);
  }
}

TEST_CASE("MIS in solid angle converges to its expectation, within the discretisation of the integral") {
  const fixture& f = fx();
  const discrete_cdf<double> cdf(f.weights);
  const int runs = 1000, n_dirs = 8, n_vpls = 8;
  std::printf("MIS solid angle, %d runs x (%d dirs + %d VPLs)\n", runs, n_dirs, n_vpls);
  for (const auto& g : f.gps) {
    const vec3<double> I = gathering_integral(f.scene, f.view, g.gp, depth_tol, quad_m);
    const vec3<double> S = exhaustive_vpl_sum(g.gp, f.view, f.vis, 0.0);
    const vec3<double> E =
        mis_expectation(f.scene, f.view, cdf, g.gp, n_dirs, n_vpls, depth_tol, mis_mode::solid_angle, quad_m);
    const run_stats r = repeat_estimates(runs, 51u, [&](counter_rng& rng) {
      return estimate_mis(g.gp, f.view, cdf, rng, n_dirs, n_vpls, f.tracer, f.vis, depth_tol);
    });
    print_row("MIS solid_angle", g.name, r, E);
    std::printf("  %-22s %-20s E %.6f  I %.6f (E-I)/I %+.2f%%  (S-I)/I %+.2f%%  z(I) %.2f\n", "", g.name.c_str(),
                luminance(E), luminance(I), 100.0 * (luminance(E) / luminance(I) - 1.0),
                100.0 * (luminance(S) / luminance(I) - 1.0), z_score(r, I));
    INFO(g.name);
    // unbiased for its exact expectation ...
    CHECK(within_sigma(r, E, 4.0, quad_rel * E));
    // ... which is the continuous integral up to the midpoint-rule discretisation of the VPL
    // samples (measured up to 1.01 % here, at wall_red, where the VPL sum itself is off by up to
    // 4 %; 0.8 % and 2.5 % with the former centre-depth lit test: the plane test moved I by +1.5 %
    // at wall_red and +1.6 % at ceiling_near_light, the point VPLs' part of E by less)
    CHECK(std::abs(luminance(E) / luminance(I) - 1.0) < 0.015);
    CHECK(r.lum_sem < 0.03 * luminance(I));
  }
}

TEST_CASE("voxel visibility on both sides: estimators are unbiased for the voxel references") {
  const fixture& f = fx();
  const voxel_grid<double> grid = f.scene.make_voxel_grid(32);
  const voxel_visibility<double> vvis{grid.view()};
  const voxel_tracer<double> vtrace{grid.view()};
  const double vtol = depth_tol + voxel_tracer_depth_tolerance(grid.view());
  const discrete_cdf<double> cdf(f.weights);
  std::printf("voxel visibility (32^3, two-sided) and voxel tracer (depth tolerance %.3f)\n", vtol);
  for (int i : {0, 1, 3, 6}) {
    const auto& g = f.gps[std::size_t(i)];
    const vec3<double> ref = exhaustive_vpl_sum(g.gp, f.view, vvis, 0.0);
    const vec3<double> ref_exact = exhaustive_vpl_sum(g.gp, f.view, f.vis, 0.0);
    const run_stats r = repeat_estimates(1000, 61u, [&](counter_rng& rng) {
      return estimate_vpl_sampling(g.gp, f.view, cdf, rng, 16, vvis, 0.0);
    });
    print_row("cdf, voxel V", g.name, r, ref);
    std::printf("  %-22s %-20s voxel VPL sum / exact VPL sum - 1 = %+.2f%%\n", "", g.name.c_str(),
                100.0 * (luminance(ref) / luminance(ref_exact) - 1.0));
    const vec3<double> I = cosine_quadrature(g.gp, quad_m, [&](const orthonormal_basis<double>& fr, vec3<double> l) {
      return gathering_sample(g.gp, f.view, fr, l, vtrace, vtol);
    });
    const run_stats q = repeat_estimates(1000, 62u, [&](counter_rng& rng) {
      return estimate_gathering(g.gp, f.view, rng, 16, vtrace, vtol);
    });
    print_row("gathering, voxel DDA", g.name, q, I);
    const vec3<double> I_exact = gathering_integral(f.scene, f.view, g.gp, depth_tol, quad_m);
    std::printf("  %-22s %-20s voxel integral / exact-tracer integral - 1 = %+.2f%%\n", "", g.name.c_str(),
                100.0 * (luminance(I) / luminance(I_exact) - 1.0));
    INFO(g.name);
    CHECK(within_sigma(r, ref, 4.0, 1e-9 * ref));
    CHECK(within_sigma(q, I, 4.0, quad_rel * I));
  }
}
