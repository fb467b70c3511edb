// SPDX-License-Identifier: MIT
// RIS as the VPL strategy of MIS (estimators/ris_mis_estimator.hpp) on the synthetic room (real
// occluders, exact ray-traced visibility and tracer, so only estimator bias is tested):
//   point VPLs, n_dirs = n_ris = 4, M = 16, three candidate sources (a defensive mixture whose
//     learned CDF has holes, the flux CDF, uniform)  -> estimate_mis's exact expectation E
//     (mis_expectation: quadrature of the gathering samples + the exact sum of the VPL samples)
//     with the weights' n2 = ris_mis_vpl_samples(4, 16) = 32: every RIS sample estimates
//     sum_t h(t) V(t) = n2 sum_t pmf(t) [MIS VPL sample at t], which is the VPL part of E for any
//     distribution, holes included (h vanishes with pmf). With point VPLs E depends on the weights
//     (gathering's hits are surface points, the VPL samples texel points), so a wrong n2 in either
//     the estimator or E shows here; with patch VPLs it does not (both sample the surfaces)
//   n_dirs = 0 (RIS of the unclamped contribution)   -> the exhaustive VPL sum with dmin = 0
//     (point), VPL sampling's patch integral with dmin = 0 (patch, two-sample)
//   n_ris = 0 (gathering alone)                       -> the gathering integral
//   patch VPLs, n_dirs = n_ris = 4                    -> estimate_mis with patch VPLs (two-sample)
//   pixels of a 20 x 20 G-buffer at depth edges and inside surfaces -> E at that pixel (point),
//     estimate_mis there (patch)
//   spatial reuse (ris_mis_spatial_reuse.hpp) at those pixels, pairwise and balance MIS, with and
//     without rejection, neighbours drawing from another distribution than the receiver (the CDF
//     with holes against flux)                    -> E of the receiver's distribution (point),
//     estimate_mis there (patch)
// Criterion: the mean of K independent estimates within 4 standard errors of the reference on every
// channel (plus the quadrature's accuracy for E). Run the program to see the tables.
// estimators_patch_room_test.cpp checks ris-mis against the exhaustive patch references of the room
// and of the empty room.
#include <estimators_reference.hpp>
#include <synthetic_scene.hpp>

#include <vplkit/builders/flux_weights.hpp>
#include <vplkit/builders/vpl_distribution.hpp>
#include <vplkit/distribution/defensive_mixture.hpp>
#include <vplkit/distribution/discrete_cdf.hpp>
#include <vplkit/estimators/gathering_estimator.hpp>
#include <vplkit/estimators/mis_estimator.hpp>
#include <vplkit/estimators/ris_mis_estimator.hpp>
#include <vplkit/estimators/ris_mis_spatial_reuse.hpp>
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
constexpr double depth_tol = 0.2;
constexpr int quad_m = 256;

struct fixture {
  lit_room<double> room{R};
  gbuffer_data<double> gb = room.scene.make_gbuffer(20, 20);
  defensive_mixture<double> mixture;  // importance weights with the back face zeroed, eps 0.1
  defensive_mixture<double> flux;
  discrete_cdf<double> uniform;
  discrete_cdf<double> holes;  // importance weights with the back face zeroed, no defensive part
  fixture() {
    const dprsm_view<double>& view = room.view;
    std::vector<double> w = importance_weights(view, plain_points(room.gps), 0.0);
    for (std::size_t t = std::size_t(R) * R; t < w.size(); ++t) w[t] = 0.0;
    mixture = make_vpl_distribution(w, view, 0.1);
    holes = discrete_cdf<double>(w);
    flux = make_vpl_distribution(build_flux_weights(view), view, 0.0);
    uniform = discrete_cdf<double>(uniform_valid_weights(view));
  }
};

const fixture& fx() {
  static const fixture f;
  return f;
}

void print_row(const std::string& what, const std::string& gp, const run_stats& r, vec3<double> ref) {
  std::printf("  %-30s %-22s mean %.6f +- %.6f  ref %.6f  z %.2f  var %.3e\n", what.c_str(), gp.c_str(), r.lum_mean,
              r.lum_sem, luminance(ref), z_score(r, ref), r.lum_var);
}

// Pixels of the G-buffer next to a depth edge (a 4-neighbour more than 0.3 away: the block's
// silhouette against the floor and the wall), or inside surfaces; at most four, spread out.
std::vector<int> test_pixels(const fixture& f, bool edge) {
  const gbuffer_view<double> g = f.gb.view();
  std::vector<int> out;
  for (int y = 2; y < g.height - 2; ++y)
    for (int x = 2; x < g.width - 2; ++x) {
      const int p = y * g.width + x;
      if (!gather_point_valid(g.at(p))) continue;
      double jump = 0.0;
      for (const int q : {p - 1, p + 1, p - g.width, p + g.width})
        jump = std::max(jump, glm::length(g.at(q).position - g.at(p).position));
      if ((jump > 0.3) == edge && (out.empty() || p - out.back() > 23)) out.push_back(p);
    }
  if (out.size() > 4) out.resize(4);
  return out;
}

}  // namespace

TEST_CASE("ris-mis has estimate_mis's expectation with every candidate source (point VPLs)") {
  const fixture& f = fx();
  const auto& [scene, dprsm, view, gps, vis, tracer] = f.room;
  const int runs = 2000, n = 4, m = 16;
  std::printf("ris-mis, %d runs x (%d dirs + %d RIS samples of M = %d), R = %d, point VPLs; ref = E of estimate_mis\n",
              runs, n, n, m, R);
  double var_ris_mis = 0.0, var_mis = 0.0;
  for (const auto& g : gps) {
    const auto check = [&](const char* source, const auto& dist, std::uint32_t seed) {
      const vec3<double> E = mis_expectation(scene, view, dist, g.gp, n, ris_mis_vpl_samples<double>(n, m), depth_tol,
                                             mis_mode::solid_angle, quad_m);
      const run_stats r = repeat_estimates(runs, seed, [&](counter_rng& rng) {
        return estimate_ris_mis(g.gp, view, dist, rng, n, n, m, tracer, vis, depth_tol);
      });
      print_row(source, g.name, r, E);
      INFO(g.name << " " << source);
      REQUIRE(luminance(E) > 0.0);
      // E's gathering part is a 256^2 quadrature (about 1e-3 relative, estimators_mis_test)
      CHECK(within_sigma(r, E, 4.0, 3e-3 * E));
      return r;
    };
    const run_stats a = check("mixture with holes", f.mixture, 1100u);
    check("flux", f.flux, 1200u);
    check("uniform", f.uniform, 1300u);
    check("CDF with holes (no eps)", f.holes, 1400u);
    // What the resampling buys at equal samples: estimate_mis with the same mixture.
    const run_stats plain = repeat_estimates(runs, 1500u, [&](counter_rng& rng) {
      return estimate_mis(g.gp, view, f.mixture, rng, n, n, tracer, vis, depth_tol);
    });
    std::printf("  %-30s %-22s mean %.6f +- %.6f  (ris-mis / mis standard error %.2f)\n", "estimate_mis, mixture",
                g.name.c_str(), plain.lum_mean, plain.lum_sem, a.lum_sem / plain.lum_sem);
    CHECK(runs_agree(a, plain, 4.0));
    var_ris_mis += a.lum_var;
    var_mis += plain.lum_var;
  }
  // Summed over the points: resampling 16 candidates per VPL sample lowers the variance (0.61 of
  // estimate_mis's measured; more at every point but floor_shadow, whose light comes through a gap).
  std::printf("  summed variance: ris-mis %.3e, mis %.3e\n", var_ris_mis, var_mis);
  CHECK(var_ris_mis < 0.8 * var_mis);
}

TEST_CASE("ris-mis with n_dirs = 0 is RIS of the unclamped contribution") {
  const fixture& f = fx();
  const auto& [scene, dprsm, view, gps, vis, tracer] = f.room;
  const int runs = 4000, m = 16;
  const double inf_tol = std::numeric_limits<double>::infinity();
  std::printf("ris-mis with n_dirs = 0, %d runs x 2 RIS samples of M = %d: point -> exhaustive VPL sum (dmin 0), "
              "patch -> VPL sampling (patch, dmin 0)\n",
              runs, m);
  for (const auto& g : gps) {
    const vec3<double> ref = exhaustive_vpl_sum(g.gp, view, vis, 0.0);
    for (const auto* source : {"flux", "uniform"}) {
      const bool use_flux = std::string(source) == "flux";
      const run_stats r = repeat_estimates(runs, use_flux ? 2100u : 2200u, [&](counter_rng& rng) {
        return use_flux ? estimate_ris_mis(g.gp, view, f.flux, rng, 0, 2, m, tracer, vis, depth_tol)
                        : estimate_ris_mis(g.gp, view, f.uniform, rng, 0, 2, m, tracer, vis, depth_tol);
      });
      print_row(std::string("point, ") + source, g.name, r, ref);
      INFO(g.name << " " << source);
      CHECK(within_sigma(r, ref, 4.0, 1e-9 * ref));
    }
    const run_stats p = repeat_estimates(runs, 2300u, [&](counter_rng& rng) {
      return estimate_ris_mis(g.gp, view, f.flux, rng, 0, 2, m, tracer, vis, inf_tol, vpl_mode::patch);
    });
    const run_stats v = repeat_estimates(runs, 2400u, [&](counter_rng& rng) {
      return estimate_vpl_sampling(g.gp, view, f.flux, rng, 8, vis, 0.0, vpl_mode::patch, inf_tol);
    });
    std::printf("  %-30s %-22s RIS %.6f +- %.6f  VPL sampling %.6f +- %.6f\n", "patch, flux", g.name.c_str(),
                p.lum_mean, p.lum_sem, v.lum_mean, v.lum_sem);
    INFO(g.name << " patch");
    CHECK(runs_agree(p, v, 4.0));
  }
}

TEST_CASE("ris-mis with n_ris = 0 or no candidates is gathering") {
  const fixture& f = fx();
  const auto& [scene, dprsm, view, gps, vis, tracer] = f.room;
  const int runs = 2000;
  std::printf("ris-mis with n_ris = 0 (and M = 0), %d runs x 8 dirs -> the gathering integral\n", runs);
  for (const auto& g : gps) {
    const vec3<double> I = gathering_integral(scene, view, g.gp, depth_tol, quad_m);
    const run_stats r = repeat_estimates(runs, 3100u, [&](counter_rng& rng) {
      return estimate_ris_mis(g.gp, view, f.flux, rng, 8, 0, 16, tracer, vis, depth_tol);
    });
    const run_stats r0 = repeat_estimates(runs, 3200u, [&](counter_rng& rng) {
      return estimate_ris_mis(g.gp, view, f.flux, rng, 8, 8, 0, tracer, vis, depth_tol);
    });
    print_row("n_ris = 0", g.name, r, I);
    print_row("M = 0", g.name, r0, I);
    INFO(g.name);
    CHECK(within_sigma(r, I, 4.0, 3e-3 * I));
    CHECK(within_sigma(r0, I, 4.0, 3e-3 * I));
  }
}

TEST_CASE("ris-mis with patch VPLs converges to estimate_mis's patch estimand") {
  const fixture& f = fx();
  const auto& [scene, dprsm, view, gps, vis, tracer] = f.room;
  const int runs = 2000, n = 4, m = 16;
  std::printf("ris-mis patch VPLs (%d + %d, M = %d) against estimate_mis patch VPLs (%d + %d), %d runs each\n", n, n, m,
              n, n, runs);
  for (const auto& g : gps) {
    const run_stats r = repeat_estimates(runs, 4100u, [&](counter_rng& rng) {
      return estimate_ris_mis(g.gp, view, f.mixture, rng, n, n, m, tracer, vis, depth_tol, vpl_mode::patch);
    });
    const run_stats v = repeat_estimates(runs, 4200u, [&](counter_rng& rng) {
      return estimate_mis(g.gp, view, f.mixture, rng, n, n, tracer, vis, depth_tol, mis_mode::solid_angle,
                          vpl_mode::patch);
    });
    std::printf("  %-22s ris-mis %.6f +- %.6f  mis %.6f +- %.6f\n", g.name.c_str(), r.lum_mean, r.lum_sem, v.lum_mean,
                v.lum_sem);
    INFO(g.name);
    CHECK(runs_agree(r, v, 4.0));
  }
}

TEST_CASE("ris-mis is unbiased at pixels on depth edges and inside surfaces") {
  const fixture& f = fx();
  const auto& [scene, dprsm, view, gps, vis, tracer] = f.room;
  const gbuffer_view<double> g = f.gb.view();
  const std::vector<int> edges = test_pixels(f, true), inside = test_pixels(f, false);
  REQUIRE(edges.size() == 4);
  REQUIRE(inside.size() == 4);
  const int runs = 2000, n = 4, m = 16;
  std::printf("ris-mis at G-buffer pixels (20 x 20), %d runs x (%d + %d, M = %d): point -> E of estimate_mis, "
              "patch -> estimate_mis\n",
              runs, n, n, m);
  std::uint32_t seed = 5000;
  for (const bool edge : {true, false})
    for (const int pixel : edge ? edges : inside) {
      const gather_point<double> gp = g.at(pixel);
      const std::string where = (edge ? "edge pixel " : "pixel ") + std::to_string(pixel);
      const vec3<double> E = mis_expectation(scene, view, f.flux, gp, n, ris_mis_vpl_samples<double>(n, m), depth_tol,
                                             mis_mode::solid_angle, quad_m);
      const run_stats r = repeat_estimates(runs, ++seed, [&](counter_rng& rng) {
        return estimate_ris_mis(gp, view, f.flux, rng, n, n, m, tracer, vis, depth_tol);
      });
      print_row("point, flux", where, r, E);
      const run_stats p = repeat_estimates(runs, ++seed, [&](counter_rng& rng) {
        return estimate_ris_mis(gp, view, f.flux, rng, n, n, m, tracer, vis, depth_tol, vpl_mode::patch);
      });
      const run_stats q = repeat_estimates(runs, ++seed, [&](counter_rng& rng) {
        return estimate_mis(gp, view, f.flux, rng, n, n, tracer, vis, depth_tol, mis_mode::solid_angle,
                            vpl_mode::patch);
      });
      std::printf("  %-30s %-22s ris-mis %.6f +- %.6f  mis %.6f +- %.6f\n", "patch, flux", where.c_str(), p.lum_mean,
                  p.lum_sem, q.lum_mean, q.lum_sem);
      INFO(where);
      CHECK(within_sigma(r, E, 4.0, 3e-3 * E));
      CHECK(runs_agree(p, q, 4.0));
    }
}

namespace {

// ris-mis with spatial reuse at one pixel of the fixture's G-buffer, one round of the renderer's
// (render/cpu/ris_render.hpp): every pixel the reuse asks for gets its reservoir of m candidates
// (ris_mis_resample with its own distribution, dist_of(p)) from its own stream of that run; then
// the reuse at `pixel` (ris_mis_spatial_reuse) with the run's stream, the shade h_q V W with the
// receiver's distribution (one RIS sample: the 1/n2 of n2 = 1 such rounds), and n1 gathering
// directions weighed against n2.
template <class DistOf>
vec3<double> reuse_ris_mis_estimate(const fixture& f, int pixel, std::uint32_t run_seed, counter_rng& rng, int m,
                                    int n1, int n2, const ris_spatial_settings<double>& settings,
                                    const DistOf& dist_of, vpl_mode mode) {
  const auto& view = f.room.view;
  const gbuffer_view<double> g = f.gb.view();
  std::vector<int> made(std::size_t(g.pixel_count()), 0);
  std::vector<ris_reservoir<double>> res(std::size_t(g.pixel_count()));
  const auto reservoir = [&](int p) -> const ris_reservoir<double>& {
    if (!made[std::size_t(p)]) {
      counter_rng r = make_counter_rng(run_seed, std::uint32_t(p));
      res[std::size_t(p)] = dist_of(p).resample(g.at(p), r, m, n1, n2, mode);
      made[std::size_t(p)] = 1;
    }
    return res[std::size_t(p)];
  };
  const auto load = [&](int p) { return ris_neighbour<double>{g.at(p), reservoir(p)}; };
  const gather_point<double> gp = g.at(pixel);
  const ris_reservoir<double> out = ris_mis_spatial_reuse(gp, pixel, g.width, g.height, view, reservoir(pixel), load,
                                                          settings, rng, dist_of, double(n1), double(n2), mode,
                                                          depth_tol);
  vec3<double> sum = dist_of(pixel).shade(gp, out, double(n1), double(n2), mode);
  const orthonormal_basis<double> frame = make_orthonormal_basis(gather_point_shading_normal(gp));
  for (int j = 0; j < n1; ++j) {
    const double u0 = rng_next_unit<double>(rng), u1 = rng_next_unit<double>(rng);
    sum += dist_of(pixel).gather(gp, frame, sample_cosine_hemisphere(vec2<double>(u0, u1)), double(n1), double(n2),
                                 mode);
  }
  return sum;
}

// One candidate distribution with the calls the reuse estimate makes (the pmf for the target).
template <class Dist>
struct ris_mis_source {
  const fixture* f;
  const Dist* dist;
  double pmf(std::size_t i) const { return dist->pmf(i); }
  ris_reservoir<double> resample(const gather_point<double>& gp, counter_rng& rng, int m, int n1, int n2,
                                 vpl_mode mode) const {
    return ris_mis_resample(gp, f->room.view, *dist, rng, m, double(n1), double(n2), mode, depth_tol);
  }
  vec3<double> shade(const gather_point<double>& gp, const ris_reservoir<double>& r, double n1, double n2,
                     vpl_mode mode) const {
    return ris_mis_shade(gp, f->room.view, *dist, r, f->room.vis, n1, n2, mode, depth_tol);
  }
  vec3<double> gather(const gather_point<double>& gp, const orthonormal_basis<double>& frame, vec3<double> dir,
                      double n1, double n2, vpl_mode mode) const {
    return mis_gathering_sample(gp, f->room.view, *dist, frame, dir, f->room.tracer, depth_tol, n1, n2,
                                mis_mode::solid_angle, mode);
  }
};

// The pixel's candidate distribution: flux everywhere, or (mixed) the CDF with holes (no defensive
// part: pmf 0 on the back face) on even pixels and flux on odd ones, so that a neighbour's pmf
// differs from the receiver's (as with --candidate-source local across a region boundary) and a
// neighbour's sample may lie where the receiver's pmf, hence its target, is 0.
struct dist_by_pixel {
  ris_mis_source<discrete_cdf<double>> mixture;
  ris_mis_source<defensive_mixture<double>> flux;
  bool mixed;
  struct either {
    const dist_by_pixel* d;
    bool use_mixture;
    double pmf(std::size_t i) const { return use_mixture ? d->mixture.pmf(i) : d->flux.pmf(i); }
    ris_reservoir<double> resample(const gather_point<double>& gp, counter_rng& rng, int m, int n1, int n2,
                                   vpl_mode mode) const {
      return use_mixture ? d->mixture.resample(gp, rng, m, n1, n2, mode) : d->flux.resample(gp, rng, m, n1, n2, mode);
    }
    vec3<double> shade(const gather_point<double>& gp, const ris_reservoir<double>& r, double n1, double n2,
                       vpl_mode mode) const {
      return use_mixture ? d->mixture.shade(gp, r, n1, n2, mode) : d->flux.shade(gp, r, n1, n2, mode);
    }
    vec3<double> gather(const gather_point<double>& gp, const orthonormal_basis<double>& frame, vec3<double> dir,
                        double n1, double n2, vpl_mode mode) const {
      return use_mixture ? d->mixture.gather(gp, frame, dir, n1, n2, mode) : d->flux.gather(gp, frame, dir, n1, n2, mode);
    }
  };
  either operator()(int p) const { return {this, mixed && p % 2 == 0}; }
};

}  // namespace

TEST_CASE("ris-mis with spatial reuse is unbiased, at depth edges too, with and without rejection") {
  const fixture& f = fx();
  const auto& [scene, dprsm, view, gps, vis, tracer] = f.room;
  const gbuffer_view<double> g = f.gb.view();
  const std::vector<int> edges = test_pixels(f, true), inside = test_pixels(f, false);
  REQUIRE(edges.size() == 4);
  REQUIRE(inside.size() == 4);
  const int runs = 2000, n1 = 4, n2 = 4, m = 8;
  struct config {
    const char* name;
    ris_reuse_mis mis;
    bool reject;
    bool mixed;
  };
  const config configs[] = {{"pairwise", ris_reuse_mis::pairwise, true, false},
                            {"pairwise, no rejection", ris_reuse_mis::pairwise, false, false},
                            {"balance, no rejection", ris_reuse_mis::balance, false, false},
                            {"pairwise, sources by pixel", ris_reuse_mis::pairwise, false, true}};
  std::printf("ris-mis with spatial reuse (K = 4, radius 3), %d runs x (%d dirs + 1 reused RIS sample of M = %d, "
              "weights of n2 = %d), 20 x 20 G-buffer; ref = E of estimate_mis with the receiver's distribution\n",
              runs, n1, m, n2);
  const ris_mis_source<discrete_cdf<double>> mixture{&f, &f.holes};
  const ris_mis_source<defensive_mixture<double>> flux{&f, &f.flux};
  std::uint32_t seed = 9000;
  for (const bool edge : {true, false})
    for (const int pixel : edge ? edges : inside) {
      const gather_point<double> gp = g.at(pixel);
      const std::string where = (edge ? "edge pixel " : "pixel ") + std::to_string(pixel);
      const vec3<double> e_flux = mis_expectation(scene, view, f.flux, gp, n1, n2, depth_tol, mis_mode::solid_angle,
                                                  quad_m);
      const vec3<double> e_mixture = mis_expectation(scene, view, f.holes, gp, n1, n2, depth_tol,
                                                     mis_mode::solid_angle, quad_m);
      for (const config& c : configs) {
        ris_spatial_settings<double> s;
        s.neighbours = 4;
        s.radius = 3;
        s.mis = c.mis;
        if (!c.reject) {
          s.min_normal_cos = -2.0;
          s.max_plane_slope = std::numeric_limits<double>::infinity();
        }
        const dist_by_pixel dist_of{mixture, flux, c.mixed};
        const vec3<double> E = c.mixed && pixel % 2 == 0 ? e_mixture : e_flux;
        ++seed;
        const run_stats r = repeat_estimates(runs, seed, [&](counter_rng& rng) {
          return reuse_ris_mis_estimate(f, pixel, seed * 7919u + rng.key, rng, m, n1, n2, s, dist_of,
                                        vpl_mode::point);
        });
        print_row(c.name, where, r, E);
        INFO(where << " " << c.name);
        REQUIRE(luminance(E) > 0.0);
        CHECK(within_sigma(r, E, 4.0, 3e-3 * E));
      }
    }
}

TEST_CASE("ris-mis with spatial reuse and patch VPLs converges to estimate_mis's patch estimand") {
  const fixture& f = fx();
  const auto& [scene, dprsm, view, gps, vis, tracer] = f.room;
  const gbuffer_view<double> g = f.gb.view();
  const int runs = 2000, n1 = 4, n2 = 4, m = 8;
  ris_spatial_settings<double> s;
  s.neighbours = 4;
  s.radius = 3;
  s.min_normal_cos = -2.0;
  s.max_plane_slope = std::numeric_limits<double>::infinity();
  const ris_mis_source<discrete_cdf<double>> mixture{&f, &f.holes};
  const ris_mis_source<defensive_mixture<double>> flux{&f, &f.flux};
  const dist_by_pixel dist_of{mixture, flux, true};
  std::printf("ris-mis with spatial reuse, patch VPLs, sources by pixel, %d runs: against estimate_mis\n", runs);
  for (const int pixel : test_pixels(f, true)) {
    const run_stats r = repeat_estimates(runs, 9801u, [&](counter_rng& rng) {
      return reuse_ris_mis_estimate(f, pixel, 0x98100u + rng.key, rng, m, n1, n2, s, dist_of, vpl_mode::patch);
    });
    const run_stats q = repeat_estimates(runs, 9802u, [&](counter_rng& rng) {
      const gather_point<double> gp = g.at(pixel);
      return pixel % 2 == 0 ? estimate_mis(gp, view, f.holes, rng, n1, n2, tracer, vis, depth_tol,
                                           mis_mode::solid_angle, vpl_mode::patch)
                            : estimate_mis(gp, view, f.flux, rng, n1, n2, tracer, vis, depth_tol,
                                           mis_mode::solid_angle, vpl_mode::patch);
    });
    std::printf("  edge pixel %-4d reuse %.6f +- %.6f  mis %.6f +- %.6f\n", pixel, r.lum_mean, r.lum_sem, q.lum_mean,
                q.lum_sem);
    INFO("pixel " << pixel);
    CHECK(runs_agree(r, q, 4.0));
  }
}
