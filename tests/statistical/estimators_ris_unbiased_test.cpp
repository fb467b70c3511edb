// SPDX-License-Identifier: MIT
// The resampled estimator (estimators/ris_estimator.hpp) and its spatial reuse
// (estimators/ris_spatial_reuse.hpp) are unbiased on the synthetic room (real occluders, exact
// ray-traced visibility, so only estimator bias is tested):
//   RIS, point VPLs (dmin 0.05), three candidate sources (a defensive mixture whose learned CDF has holes, the
//     flux CDF, uniform) and M = 1, 4, 32          -> the exhaustive VPL sum
//   keep k = 4 from one candidate set               -> the exhaustive VPL sum
//   RIS with patch VPLs                             -> VPL sampling with patch VPLs (two-sample test)
//   spatial reuse on a 20 x 20 G-buffer, pairwise and balance MIS, with and without the rejection
//     of dissimilar neighbours, neighbours drawing from other sources, at pixels on depth edges and
//     inside surfaces                                -> the exhaustive VPL sum at that pixel
// Criterion: the mean of K independent estimates lies within 4 standard errors of the reference
// on every channel. Without rejection the reuse takes neighbours across every depth edge: an
// unbiased reuse must still converge there. Run the program to see the tables.
#include <estimators_reference.hpp>
#include <synthetic_scene.hpp>

#include <vplkit/builders/flux_weights.hpp>
#include <vplkit/builders/vpl_distribution.hpp>
#include <vplkit/distribution/defensive_mixture.hpp>
#include <vplkit/distribution/discrete_cdf.hpp>
#include <vplkit/estimators/ris_estimator.hpp>
#include <vplkit/estimators/ris_spatial_reuse.hpp>
#include <vplkit/estimators/vpl_sampling_estimator.hpp>
#include <vplkit/estimators/vpl_sum.hpp>

#include <catch2/catch.hpp>

#include <cstdio>
#include <limits>
#include <string>
#include <vector>

using namespace vplkit;
using namespace vplkit_test;

namespace {

constexpr int R = 32;
// The VPL clamp of the point-VPL cases: the clamped sum is their estimand, and the clamp bounds the
// 1/d^2 near field, whose heavy tail (at floor_corner, 0.1 from two walls) would otherwise make a
// standard error from a few thousand runs untrustworthy.
constexpr double dmin = 0.05;

struct fixture {
  synthetic_scene<double> scene;
  dprsm_data<double> dprsm = scene.make_dprsm(R);
  dprsm_view<double> view = dprsm.view();
  std::vector<named_gather_point<double>> gps = scene.gather_points();
  exact_visibility<double> vis{&scene};
  gbuffer_data<double> gb = scene.make_gbuffer(20, 20);
  defensive_mixture<double> mixture;  // importance weights with the back face zeroed, eps 0.1
  defensive_mixture<double> flux;     // the flux CDF (no fallback needed: it covers every VPL)
  discrete_cdf<double> uniform;
  fixture() {
    std::vector<double> w = importance_weights(view, plain_points(gps), 0.0);
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

void print_row(const std::string& what, const std::string& gp, const run_stats& r, vec3<double> ref) {
  std::printf("  %-34s %-22s mean %.6f +- %.6f  ref %.6f  z %.2f  var %.3e\n", what.c_str(), gp.c_str(), r.lum_mean,
              r.lum_sem, luminance(ref), z_score(r, ref), r.lum_var);
}

}  // namespace

TEST_CASE("RIS is unbiased for the VPL sum with every candidate source and M") {
  const fixture& f = fx();
  // floor_corner takes a quarter of its light from one texel of pmf 7e-4 under the flux CDF: a
  // heavy tail that a few thousand runs resolve only roughly.
  const int runs = 8000;
  std::printf("RIS, %d runs x 1 sample, R = %d, exact visibility, dmin = %.2f\n", runs, R, dmin);
  for (const auto& g : f.gps) {
    const vec3<double> ref = exhaustive_vpl_sum(g.gp, f.view, f.vis, dmin);
    REQUIRE(luminance(ref) > 0.0);
    for (const int m : {1, 4, 32}) {
      const auto check = [&](const char* source, const auto& dist, std::uint32_t seed) {
        const run_stats r = repeat_estimates(runs, seed, [&](counter_rng& rng) {
          return estimate_ris(g.gp, f.view, dist, rng, 1, m, f.vis, dmin);
        });
        print_row(std::string(source) + " M=" + std::to_string(m), g.name, r, ref);
        INFO(g.name << " " << source << " M = " << m);
        CHECK(within_sigma(r, ref, 4.0, 1e-9 * ref));
        return r;
      };
      const run_stats a = check("mixture with holes", f.mixture, 100u + std::uint32_t(m));
      check("flux", f.flux, 200u + std::uint32_t(m));
      check("uniform", f.uniform, 300u + std::uint32_t(m));
      if (m == 32 && g.name == "floor_open") {
        // What resampling buys: 32 candidates of the same mixture against one.
        const run_stats one = repeat_estimates(runs, 401u, [&](counter_rng& rng) {
          return estimate_vpl_sampling(g.gp, f.view, f.mixture, rng, 1, f.vis, dmin);
        });
        std::printf("  variance of one sample at floor_open: VPL sampling %.3e, RIS M=32 %.3e\n", one.lum_var, a.lum_var);
        CHECK(a.lum_var < 0.5 * one.lum_var);
      }
    }
  }
}

TEST_CASE("RIS keeping k samples of one candidate set is unbiased") {
  const fixture& f = fx();
  const int runs = 2000, k = 4, m = 16;
  std::printf("RIS keep %d of %d candidates, %d runs\n", k, m, runs);
  for (const auto& g : f.gps) {
    const vec3<double> ref = exhaustive_vpl_sum(g.gp, f.view, f.vis, dmin);
    const run_stats r = repeat_estimates(runs, 501u, [&](counter_rng& rng) {
      ris_reservoir<double> res[ris_max_kept];
      ris_resample_candidates(g.gp, f.view, f.mixture, rng, m, res, k, dmin);
      return ris_shade_kept(g.gp, f.view, res, k, f.vis, dmin);
    });
    print_row("keep 4 of 16", g.name, r, ref);
    INFO(g.name);
    CHECK(within_sigma(r, ref, 4.0, 1e-9 * ref));
  }
}

TEST_CASE("RIS with patch VPLs converges to VPL sampling's patch integral") {
  const fixture& f = fx();
  const int runs = 4000;
  const double tol = std::numeric_limits<double>::infinity();
  std::printf("RIS patch VPLs (M = 8) against VPL sampling patch VPLs (4 samples), %d runs each, dmin %.2f\n", runs,
              dmin);
  for (const auto& g : f.gps) {
    const run_stats r = repeat_estimates(runs, 601u, [&](counter_rng& rng) {
      return estimate_ris(g.gp, f.view, f.mixture, rng, 1, 8, f.vis, dmin, vpl_mode::patch, tol);
    });
    const run_stats v = repeat_estimates(runs, 602u, [&](counter_rng& rng) {
      return estimate_vpl_sampling(g.gp, f.view, f.mixture, rng, 4, f.vis, dmin, vpl_mode::patch, tol);
    });
    std::printf("  %-22s RIS %.6f +- %.6f  VPL sampling %.6f +- %.6f\n", g.name.c_str(), r.lum_mean, r.lum_sem,
                v.lum_mean, v.lum_sem);
    INFO(g.name);
    CHECK(runs_agree(r, v, 4.0));
  }
}

namespace {

// Spatial reuse at one pixel of the fixture's G-buffer: per run, every pixel the reuse asks for
// gets its reservoir of m candidates from its own stream of that run (seed, pixel), its source
// chosen by source_of(pixel); then the reuse at `pixel` with the run's stream, then the shade.
template <class SourceOf>
vec3<double> reuse_estimate(const fixture& f, int pixel, std::uint32_t run_seed, counter_rng& rng, int m,
                            const ris_spatial_settings<double>& settings, const SourceOf& source_of, vpl_mode mode,
                            double dmin) {
  const gbuffer_view<double> g = f.gb.view();
  const double tol = std::numeric_limits<double>::infinity();
  std::vector<int> made(std::size_t(g.pixel_count()), 0);
  std::vector<ris_reservoir<double>> res(std::size_t(g.pixel_count()));
  const auto reservoir = [&](int p) -> const ris_reservoir<double>& {
    if (!made[std::size_t(p)]) {
      counter_rng r = make_counter_rng(run_seed, std::uint32_t(p));
      res[std::size_t(p)] = source_of(p) == 0 ? ris_resample(g.at(p), f.view, f.mixture, r, m, dmin, mode, tol)
                                              : ris_resample(g.at(p), f.view, f.flux, r, m, dmin, mode, tol);
      made[std::size_t(p)] = 1;
    }
    return res[std::size_t(p)];
  };
  const auto load = [&](int p) { return ris_neighbour<double>{g.at(p), reservoir(p)}; };
  const ris_reservoir<double> out =
      ris_spatial_reuse(g.at(pixel), pixel, g.width, g.height, f.view, reservoir(pixel), load, settings, rng, dmin, mode, tol);
  return ris_shade(g.at(pixel), f.view, out, f.vis, dmin, mode, tol);
}

// Pixels of the G-buffer next to a depth edge (a 4-neighbour more than 0.3 away: the block's
// silhouette against the floor and the wall) and a few inside surfaces.
std::vector<int> test_pixels(const fixture& f, bool edge) {
  const gbuffer_view<double> g = f.gb.view();
  std::vector<int> out;
  for (int y = 2; y < g.height - 2; ++y)
    for (int x = 2; x < g.width - 2; ++x) {
      const int p = y * g.width + x;
      double jump = 0.0;
      for (const int q : {p - 1, p + 1, p - g.width, p + g.width})
        jump = std::max(jump, glm::length(g.at(q).position - g.at(p).position));
      if ((jump > 0.3) == edge && (out.empty() || p - out.back() > 23)) out.push_back(p);
    }
  if (out.size() > 4) out.resize(4);
  return out;
}

}  // namespace

TEST_CASE("spatial reuse is unbiased, at depth edges too, with and without rejection") {
  const fixture& f = fx();
  const int runs = 3000, m = 8;
  const std::vector<int> edges = test_pixels(f, true), inside = test_pixels(f, false);
  REQUIRE(edges.size() == 4);
  REQUIRE(inside.size() == 4);
  const gbuffer_view<double> g = f.gb.view();
  struct config {
    const char* name;
    ris_reuse_mis mis;
    bool reject;
    bool mixed_sources;
  };
  const config configs[] = {{"pairwise", ris_reuse_mis::pairwise, true, false},
                            {"pairwise, no rejection", ris_reuse_mis::pairwise, false, false},
                            {"balance", ris_reuse_mis::balance, true, false},
                            {"balance, no rejection", ris_reuse_mis::balance, false, false},
                            {"pairwise, sources by column", ris_reuse_mis::pairwise, false, true}};
  std::printf("spatial reuse, K = 4, radius 3, M = %d, %d runs, 20 x 20 G-buffer, R = %d, dmin = %.2f\n", m, runs, R,
              dmin);
  int rejected_somewhere = 0;
  for (const int pixel : edges)
    for (const int p2 : {pixel - 1, pixel + 1, pixel - g.width, pixel + g.width})
      rejected_somewhere += ris_neighbour_similar(g.at(pixel), g.at(p2), 0.9, 0.1) ? 0 : 1;
  CHECK(rejected_somewhere > 0);  // the edge pixels do have dissimilar neighbours
  std::uint32_t seed = 700;
  for (const bool edge : {true, false})
    for (const int pixel : edge ? edges : inside) {
      const vec3<double> ref = exhaustive_vpl_sum(g.at(pixel), f.view, f.vis, dmin);
      const std::string where = (edge ? "edge pixel " : "pixel ") + std::to_string(pixel);
      for (const config& c : configs) {
        ris_spatial_settings<double> s;
        s.neighbours = 4;
        s.radius = 3;
        s.mis = c.mis;
        if (!c.reject) {
          s.min_normal_cos = -2.0;
          s.max_plane_slope = std::numeric_limits<double>::infinity();
        }
        const auto source_of = [&](int p) { return c.mixed_sources ? (p % 2) : 0; };
        ++seed;
        const run_stats r = repeat_estimates(runs, seed, [&](counter_rng& rng) {
          return reuse_estimate(f, pixel, seed * 7919u + rng.key, rng, m, s, source_of, vpl_mode::point, dmin);
        });
        print_row(c.name, where, r, ref);
        INFO(where << " " << c.name);
        CHECK(within_sigma(r, ref, 4.0, 1e-9 * ref));
      }
    }
}

TEST_CASE("spatial reuse with patch VPLs converges to the patch integral") {
  const fixture& f = fx();
  const int runs = 3000, m = 8;
  const double tol = std::numeric_limits<double>::infinity();
  const gbuffer_view<double> g = f.gb.view();
  std::printf("spatial reuse with patch VPLs against VPL sampling, %d runs each, dmin %.2f\n", runs, dmin);
  ris_spatial_settings<double> s;
  s.neighbours = 4;
  s.radius = 3;
  s.min_normal_cos = -2.0;
  s.max_plane_slope = std::numeric_limits<double>::infinity();
  for (const int pixel : test_pixels(f, true)) {
    const run_stats r = repeat_estimates(runs, 801u, [&](counter_rng& rng) {
      return reuse_estimate(f, pixel, 0x80100u + rng.key, rng, m, s, [](int) { return 0; }, vpl_mode::patch, dmin);
    });
    const run_stats v = repeat_estimates(runs, 802u, [&](counter_rng& rng) {
      return estimate_vpl_sampling(g.at(pixel), f.view, f.mixture, rng, 4, f.vis, dmin, vpl_mode::patch, tol);
    });
    std::printf("  edge pixel %-4d reuse %.6f +- %.6f  VPL sampling %.6f +- %.6f\n", pixel, r.lum_mean, r.lum_sem,
                v.lum_mean, v.lum_sem);
    INFO("pixel " << pixel);
    CHECK(runs_agree(r, v, 4.0));
  }
}
