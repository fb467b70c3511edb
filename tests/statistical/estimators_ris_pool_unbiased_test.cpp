// SPDX-License-Identifier: MIT
// ris-mis with presampled candidates (estimators/ris_candidate_pool.hpp) on the synthetic room of
// estimators_ris_mis_unbiased_test.cpp (R = 32, real occluders, exact visibility and tracer, so only
// estimator bias is tested). As a renderer does per frame, each of K independent pools (its own
// seed) is read by every gather point, with S per-pixel streams each; the pools are shared by the
// points and the streams, so the K per-pool means (over the S streams) are the independent samples
// and the standard error is theirs (the K S estimates are not independent: treating them so would
// understate it, the more the smaller the pool). References, those of the ris-mis test:
//   point VPLs, n_dirs = 0 (RIS of the unclamped contribution)  -> the exhaustive VPL sum, dmin 0
//   point VPLs, n_dirs = n_ris = 4                              -> estimate_mis's exact expectation E
//   patch VPLs, n_dirs = 0    -> the exhaustive patch sum at the same depth tolerance (two-sample)
//   patch VPLs, n_dirs = n_ris = 4                              -> estimate_mis, patch VPLs (two-sample)
// Criterion: the mean within 4 standard errors of the reference on every channel (plus the
// quadrature's accuracy for E). And the kind of the pool's variance: given one pool the estimate is
// unbiased for that pool's own value (1/P) sum_e h_e V_e / pmf_e (the candidates are uniform over
// the entries), which misses the reference by many standard errors of the per-pixel mean; over
// pools those values average to the reference with the variance of a P-sample VPL-sampling
// estimate, Var(L/pmf) / P. Run the program to see the tables.
#include <estimators_reference.hpp>
#include <synthetic_scene.hpp>

#include <vplkit/builders/flux_weights.hpp>
#include <vplkit/builders/vpl_distribution.hpp>
#include <vplkit/distribution/defensive_mixture.hpp>
#include <vplkit/distribution/discrete_cdf.hpp>
#include <vplkit/estimators/mis_estimator.hpp>
#include <vplkit/estimators/ris_candidate_pool.hpp>
#include <vplkit/estimators/vpl_sum.hpp>
#include <vplkit/vpl/luminance.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

using namespace vplkit;
using namespace vplkit_test;

namespace {

constexpr int R = 32;
constexpr double depth_tol = 0.2;
constexpr int quad_m = 256;

struct fixture {
  lit_room<double> room{R};
  defensive_mixture<double> mixture;  // importance weights with the back face zeroed, eps 0.1
  defensive_mixture<double> flux;
  discrete_cdf<double> uniform;
  fixture() {
    const dprsm_view<double>& view = room.view;
    std::vector<double> w = importance_weights(view, plain_points(room.gps), 0.0);
    for (std::size_t t = std::size_t(R) * R; t < w.size(); ++t) w[t] = 0.0;
    mixture = make_vpl_distribution(w, view, 0.1);
    flux = make_vpl_distribution(build_flux_weights(view), view, 0.0);
    uniform = discrete_cdf<double>(uniform_valid_weights(view));
  }
};

const fixture& fx() {
  static const fixture f;
  return f;
}

template <class D>
std::vector<ris_pool_entry<double>> make_pool(const dprsm_view<double>& view, const D& dist, std::uint32_t n,
                                              std::uint32_t seed, vpl_mode mode) {
  std::vector<ris_pool_entry<double>> pool(n);
  for (std::uint32_t i = 0; i < n; ++i) pool[i] = ris_pool_draw_entry(view, dist, seed, i, mode, depth_tol);
  return pool;
}

// run_stats of independent values (repeat_estimates' formulas).
run_stats stats_of(const std::vector<vec3<double>>& values) {
  std::size_t k = 0;
  return repeat_estimates(int(values.size()), 0u, [&](counter_rng&) { return values[k++]; });
}

// For each gather point, the statistics of the per-pool means: pool k (seed pool_seed + k) is read
// by every point, `streams` estimates each (stream s of point g: make_counter_rng(stream_seed + k,
// g streams + s)). estimate(g, pool, rng) -> vec3<double>.
template <class D, class Estimate>
std::vector<run_stats> over_pools(const fixture& f, const D& dist, int pools, int streams, std::uint32_t pool_size,
                                  std::uint32_t pool_seed, std::uint32_t stream_seed, vpl_mode mode,
                                  Estimate&& estimate, std::vector<run_stats>* naive = nullptr) {
  const std::size_t n = f.room.gps.size();
  std::vector<std::vector<vec3<double>>> means(n), all(n);
  for (int k = 0; k < pools; ++k) {
    const std::vector<ris_pool_entry<double>> pool = make_pool(f.room.view, dist, pool_size, pool_seed + k, mode);
    for (std::size_t g = 0; g < n; ++g) {
      vec3<double> sum(0.0);
      for (int s = 0; s < streams; ++s) {
        counter_rng rng = make_counter_rng(stream_seed + std::uint32_t(k), std::uint32_t(g * streams + s));
        const vec3<double> e = estimate(g, pool, rng);
        sum += e;
        if (naive) all[g].push_back(e);
      }
      means[g].push_back(sum / double(streams));
    }
  }
  std::vector<run_stats> out;
  for (std::size_t g = 0; g < n; ++g) {
    out.push_back(stats_of(means[g]));
    if (naive) naive->push_back(stats_of(all[g]));
  }
  return out;
}

void print_row(const std::string& what, const std::string& gp, const run_stats& r, vec3<double> ref) {
  std::printf("  %-30s %-20s mean %.6f +- %.6f  ref %.6f  z %.2f\n", what.c_str(), gp.c_str(), r.lum_mean, r.lum_sem,
              luminance(ref), z_score(r, ref));
}

// The pool's own value at gp for n_dirs = 0: with the candidates uniform over the P entries (exact
// for P a power of 2: every entry takes 2^24 / P of the stream's numbers), E[F | pool] is
// (1/P) sum_e h_e V_e / pmf_e (RIS's E[f(Y) W] = E[(1/M) sum_i f(X_i) / pmf(X_i)], for any
// candidate distribution), h_e / pmf_e the unclamped contribution of the entry's point.
vec3<double> pool_value(const fixture& f, const gather_point<double>& gp, const std::vector<ris_pool_entry<double>>& pool) {
  const mis_receiver<double> rx = make_mis_receiver(gp);
  vec3<double> sum(0.0);
  for (const ris_pool_entry<double>& e : pool) {
    const vec3<double> h = ris_pool_unshadowed(gp, rx, e, 0.0, 2.0);
    if (luminance(h) > 0.0 && f.room.vis(gp.position, gp.normal, e.position, e.normal)) sum += h / e.pmf;
  }
  return sum / double(pool.size());
}

}  // namespace

TEST_CASE("ris-mis pooled with n_dirs = 0 is unbiased for the exhaustive VPL sum, over pools and streams") {
  // A weight_sum not divided by M, a W of 1 / pmf without the resampling, or entries drawn with the
  // wrong pmf would miss the sum by far more than 4 standard errors.
  const fixture& f = fx();
  const auto& [scene, dprsm, view, gps, vis, tracer] = f.room;
  const int pools = 500, streams = 8, m = 16, n_ris = 2;
  const std::uint32_t P = 256;
  std::printf("ris-mis pooled, n_dirs = 0: %d pools of %u x %d streams x %d RIS samples of M = %d (point VPLs); "
              "ref = exhaustive VPL sum (dmin 0); sem over the pools (naive sem over all estimates)\n",
              pools, P, streams, n_ris, m);
  std::uint32_t seed = 61000;
  for (const char* source : {"flux", "uniform"}) {
    const bool use_flux = std::string(source) == "flux";
    std::vector<run_stats> naive;
    const auto estimate = [&](std::size_t g, const std::vector<ris_pool_entry<double>>& pool, counter_rng& rng) {
      return use_flux ? estimate_ris_mis_pooled(gps[g].gp, view, f.flux, pool.data(), P, rng, 0, n_ris, m, tracer,
                                                vis, depth_tol)
                      : estimate_ris_mis_pooled(gps[g].gp, view, f.uniform, pool.data(), P, rng, 0, n_ris, m, tracer,
                                                vis, depth_tol);
    };
    const std::vector<run_stats> r =
        use_flux ? over_pools(f, f.flux, pools, streams, P, seed, seed + 500u, vpl_mode::point, estimate, &naive)
                 : over_pools(f, f.uniform, pools, streams, P, seed, seed + 500u, vpl_mode::point, estimate, &naive);
    seed += 1000u;
    for (std::size_t g = 0; g < gps.size(); ++g) {
      const vec3<double> ref = exhaustive_vpl_sum(gps[g].gp, view, vis, 0.0);
      print_row(std::string("point, ") + source, gps[g].name, r[g], ref);
      std::printf("  %-30s %-20s (naive sem %.6f)\n", "", "", naive[g].lum_sem);
      INFO(gps[g].name << " " << source);
      REQUIRE(luminance(ref) > 0.0);
      CHECK(within_sigma(r[g], ref, 4.0, 1e-9 * ref));
    }
  }
}

TEST_CASE("ris-mis pooled with n_dirs = n_ris = 4 has estimate_mis's expectation (point VPLs)") {
  // The directions' MIS weights read the distribution the pool came from: weighing them against
  // another n2 or pmf would move the mean by the VPL share.
  const fixture& f = fx();
  const auto& [scene, dprsm, view, gps, vis, tracer] = f.room;
  const int pools = 300, streams = 8, n = 4, m = 16;
  const std::uint32_t P = 256;
  std::printf("ris-mis pooled, %d pools of %u x %d streams x (%d dirs + %d RIS samples of M = %d), point VPLs; "
              "ref = E of estimate_mis\n",
              pools, P, streams, n, n, m);
  const auto run = [&](const char* source, const auto& dist, std::uint32_t seed) {
    const std::vector<run_stats> r = over_pools(
        f, dist, pools, streams, P, seed, seed + 500u, vpl_mode::point,
        [&](std::size_t g, const std::vector<ris_pool_entry<double>>& pool, counter_rng& rng) {
          return estimate_ris_mis_pooled(gps[g].gp, view, dist, pool.data(), P, rng, n, n, m, tracer, vis, depth_tol);
        });
    for (std::size_t g = 0; g < gps.size(); ++g) {
      const vec3<double> E =
          mis_expectation(scene, view, dist, gps[g].gp, n, ris_mis_vpl_samples<double>(n, m), depth_tol,
                          mis_mode::solid_angle, quad_m);
      print_row(source, gps[g].name, r[g], E);
      INFO(gps[g].name << " " << source);
      REQUIRE(luminance(E) > 0.0);
      // E's gathering part is a 256^2 quadrature (about 1e-3 relative, estimators_mis_test)
      CHECK(within_sigma(r[g], E, 4.0, 3e-3 * E));
    }
  };
  run("mixture with holes", f.mixture, 63000u);
  run("flux", f.flux, 64000u);
}

TEST_CASE("ris-mis pooled with patch VPLs converges to the patch sum (n_dirs = 0) and to estimate_mis's patch "
          "estimand") {
  // n_dirs = 0 takes the points moved to their texel's centre too (n1 = 0), as the patch sum does;
  // with directions they are gathering's, as in estimate_mis. An entry with the texel centre's area
  // or without its jitter would miss either.
  const fixture& f = fx();
  const auto& [scene, dprsm, view, gps, vis, tracer] = f.room;
  const int pools = 400, streams = 4, n = 4, m = 16;
  const std::uint32_t P = 256;
  std::printf("ris-mis pooled, patch VPLs, %d pools of %u x %d streams: n_dirs = 0 (2 RIS samples of M = %d) "
              "against the exhaustive patch sum (8 seeds x 2 x 2 strata), %d + %d against estimate_mis (%d runs)\n",
              pools, P, streams, m, n, n, pools * streams);
  const std::vector<run_stats> vpl_only = over_pools(
      f, f.flux, pools, streams, P, 65000u, 65500u, vpl_mode::patch,
      [&](std::size_t g, const std::vector<ris_pool_entry<double>>& pool, counter_rng& rng) {
        return estimate_ris_mis_pooled(gps[g].gp, view, f.flux, pool.data(), P, rng, 0, 2, m, tracer, vis, depth_tol,
                                       vpl_mode::patch);
      });
  const std::vector<run_stats> both = over_pools(
      f, f.mixture, pools, streams, P, 66000u, 66500u, vpl_mode::patch,
      [&](std::size_t g, const std::vector<ris_pool_entry<double>>& pool, counter_rng& rng) {
        return estimate_ris_mis_pooled(gps[g].gp, view, f.mixture, pool.data(), P, rng, n, n, m, tracer, vis,
                                       depth_tol, vpl_mode::patch);
      });
  for (std::size_t g = 0; g < gps.size(); ++g) {
    const run_stats a = repeat_estimates(8, 201u, [&](counter_rng& rng) {
      return exhaustive_vpl_patch_sum(gps[g].gp, view, rng, 2, vis, 0.0, depth_tol);
    });
    const run_stats q = repeat_estimates(pools * streams, 67000u, [&](counter_rng& rng) {
      return estimate_mis(gps[g].gp, view, f.mixture, rng, n, n, tracer, vis, depth_tol, mis_mode::solid_angle,
                          vpl_mode::patch);
    });
    std::printf("  %-20s n_dirs 0: pooled %.6f +- %.6f  patch sum %.6f +- %.6f | %d + %d: pooled %.6f +- %.6f  "
                "mis %.6f +- %.6f\n",
                gps[g].name.c_str(), vpl_only[g].lum_mean, vpl_only[g].lum_sem, a.lum_mean, a.lum_sem, n, n,
                both[g].lum_mean, both[g].lum_sem, q.lum_mean, q.lum_sem);
    INFO(gps[g].name);
    REQUIRE(a.lum_mean > 0.0);
    CHECK(runs_agree(vpl_only[g], a, 4.0));
    CHECK(runs_agree(both[g], q, 4.0));
  }
}

TEST_CASE("ris-mis pooled: one fixed pool converges to its own value, the pools' values to the reference") {
  // n_dirs = 0, point VPLs, flux. (a) One pool of 64 read by 4000 streams: the per-pixel mean is
  // unbiased for that pool's value (a selection that skipped an entry, or favoured one, would miss
  // it), and that value misses the exhaustive sum by many standard errors of the mean (the pool's
  // error does not average out over the pixels' streams). (b) Over 2000 pools the pool values average
  // to the exhaustive sum, and their variance is that of a P-sample VPL-sampling estimate,
  // Var(L_t / pmf_t) / P, computed exactly over the texels: the pool adds that much, no more.
  const fixture& f = fx();
  const auto& [scene, dprsm, view, gps, vis, tracer] = f.room;
  const int streams = 4000, pools = 2000, m = 16;
  const std::uint32_t P = 64;
  std::printf("ris-mis pooled, n_dirs = 0, pools of %u (flux): (a) one fixed pool, %d streams -> its own value; "
              "(b) %d pools' values -> the exhaustive sum, variance Var(L/pmf)/P\n",
              P, streams, pools);
  const std::vector<ris_pool_entry<double>> fixed = make_pool(view, f.flux, P, 68000u, vpl_mode::point);
  double worst_z = 0.0;
  for (std::size_t g = 0; g < gps.size(); ++g) {
    const gather_point<double>& gp = gps[g].gp;
    const vec3<double> ref = exhaustive_vpl_sum(gp, view, vis, 0.0);
    // (a)
    const vec3<double> own = pool_value(f, gp, fixed);
    const run_stats r = repeat_estimates(streams, 68100u + std::uint32_t(g), [&](counter_rng& rng) {
      return estimate_ris_mis_pooled(gp, view, f.flux, fixed.data(), P, rng, 0, 2, m, tracer, vis, depth_tol);
    });
    // (b) Var(L_t / pmf_t) over t ~ pmf, in luminance: sum_t lum(L_t)^2 / pmf_t - lum(ref)^2.
    double second = 0.0;
    for (int t = 0; t < view.texel_count(); ++t) {
      const double l = luminance(vpl_visible_contribution(gp, view, t, vis, 0.0));
      if (l > 0.0) second += l * l / f.flux.pmf(std::size_t(t));
    }
    const double var_one = second - luminance(ref) * luminance(ref);
    std::vector<vec3<double>> values;
    double m2 = 0.0, m4 = 0.0;
    for (int k = 0; k < pools; ++k)
      values.push_back(pool_value(f, gp, make_pool(view, f.flux, P, 69000u + std::uint32_t(k), vpl_mode::point)));
    const run_stats v = stats_of(values);
    for (const vec3<double>& x : values) {
      const double d = luminance(x) - v.lum_mean;
      m2 += d * d;
      m4 += d * d * d * d;
    }
    m2 /= pools;
    m4 /= pools;
    const double var_sem = std::sqrt(std::max(0.0, m4 - m2 * m2) / pools);  // standard error of the variance
    std::printf("  %-20s ref %.6f | (a) own %.6f  mean %.6f +- %.6f  z(own) %.2f  z(ref) %.1f | (b) mean %.6f +- "
                "%.6f  z %.2f  var %.3e (expected %.3e +- %.1e)\n",
                gps[g].name.c_str(), luminance(ref), luminance(own), r.lum_mean, r.lum_sem, z_score(r, own),
                z_score(r, ref), v.lum_mean, v.lum_sem, z_score(v, ref), v.lum_var, var_one / P, var_sem);
    INFO(gps[g].name);
    REQUIRE(luminance(ref) > 0.0);
    CHECK(within_sigma(r, own, 4.0, 1e-9 * own));
    worst_z = std::max(worst_z, std::abs(z_score(r, ref)));
    CHECK(within_sigma(v, ref, 4.0, 1e-9 * ref));
    CHECK(std::abs(v.lum_var - var_one / P) <= 4.0 * var_sem);
  }
  // The fixed pool's error, in standard errors of its 4000-stream mean, at the worst point.
  std::printf("  fixed pool: largest |z| against the exhaustive sum %.1f\n", worst_z);
  CHECK(worst_z > 8.0);
}
