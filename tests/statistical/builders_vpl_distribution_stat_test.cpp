// SPDX-License-Identifier: MIT
// make_vpl_distribution with eps > 0: every VPL with nonzero flux has a positive pmf, samples
// follow the pmf (chi-square), and the one-sample VPL estimator is unbiased where the plain CDF
// (eps = 0) of hole-ridden GBG weights is not.
#include <vplkit/builders/gbg_weights.hpp>
#include <vplkit/builders/global_weights.hpp>
#include <vplkit/builders/vpl_distribution.hpp>
#include <vplkit/sampling/rng.hpp>

#include <synthetic_scene.hpp>
#include <vplkit_test_support.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

using vplkit::vec3;

namespace {

struct fixture {
  vplkit_test::synthetic_scene<double> scene;
  vplkit_test::dprsm_data<double> dprsm = scene.make_dprsm(16);
  vplkit_test::gbuffer_data<double> gbuffer = scene.make_gbuffer(8, 8);
  // sparse GBG without filling: many VPLs keep weight 0
  std::vector<double> holes() const {
    vplkit::gbg_params<double> p;
    p.n_dirs = 4;
    p.depth_tolerance = 0.3;
    p.seed = 5u;
    p.fill_holes = false;
    return vplkit::build_gbg_weights(gbuffer.view(), dprsm.view(),
                                     vplkit_test::exact_tracer<double>{&scene}, p);
  }
};

}  // namespace

TEST_CASE("builders: with eps > 0 every VPL gets a positive pmf, and only VPLs do",
          "[builders][statistical]") {
  const fixture f;
  const auto view = f.dprsm.view();
  const std::vector<double> w = f.holes();
  int vpls = 0, zero_weight_vpls = 0;
  for (int t = 0; t < view.texel_count(); ++t) {
    if (!vplkit::vpl_has_flux(view.vpl_at(t))) continue;
    ++vpls;
    zero_weight_vpls += w[std::size_t(t)] == 0.0;
  }
  REQUIRE(zero_weight_vpls > vpls / 4);  // the case defensive sampling exists for

  const auto plain = vplkit::make_vpl_distribution(w, view, 0.0);
  int plain_zero = 0;
  for (int t = 0; t < view.texel_count(); ++t)
    if (vplkit::vpl_has_flux(view.vpl_at(t))) plain_zero += plain.pmf(std::size_t(t)) == 0.0;
  REQUIRE(plain_zero == zero_weight_vpls);
  // eps = 0 is the plain discrete_cdf, bit for bit
  const vplkit::discrete_cdf<double> cdf(w);
  for (double u : {0.0, 0.1, 0.5, 0.77, 0.999999})
    REQUIRE(plain.sample(u).index == cdf.sample(u).index);

  for (double eps : {1e-3, 0.1, 0.5, 1.0}) {
    const auto m = vplkit::make_vpl_distribution(w, view, eps);
    double sum = 0;
    for (int t = 0; t < view.texel_count(); ++t) {
      const double p = m.pmf(std::size_t(t));
      sum += p;
      if (vplkit::vpl_has_flux(view.vpl_at(t))) {
        REQUIRE(p >= eps / vpls * (1 - 1e-12));
      } else {
        REQUIRE(p == 0.0);
      }
    }
    REQUIRE(sum == Approx(1.0).epsilon(1e-12));
  }
}

TEST_CASE("builders: samples of the defensive mixture follow its pmf (chi-square)",
          "[builders][statistical]") {
  const fixture f;
  const auto view = f.dprsm.view();
  const auto m = vplkit::make_vpl_distribution(f.holes(), view, 0.3);
  const std::uint64_t n = 400000;
  std::vector<std::uint64_t> counts(m.size(), 0);
  vplkit::counter_rng rng = vplkit::make_counter_rng(77u, 0u);
  for (std::uint64_t i = 0; i < n; ++i) {
    const auto s = m.sample(vplkit::rng_next_double(rng));
    REQUIRE(s.pmf > 0.0);
    REQUIRE(vplkit::vpl_has_flux(view.vpl_at(int(s.index))));
    ++counts[s.index];
  }
  std::vector<double> probs(m.size());
  for (std::size_t i = 0; i < m.size(); ++i) probs[i] = m.pmf(i);
  int dof = 0;
  const double stat = vplkit_test::chi_square(counts, probs, n, &dof);
  INFO("chi2 " << stat << " dof " << dof);
  REQUIRE(dof > 100);
  CHECK(stat < vplkit_test::chi_square_critical(dof));
}

TEST_CASE("builders: the defensive estimator is unbiased where the plain CDF is not",
          "[builders][statistical]") {
  const fixture f;
  const auto view = f.dprsm.view();
  const std::vector<double> w = f.holes();
  const double dmin = 0.1;
  // a gather point in the block's shadow: lit only indirectly
  const auto named = f.scene.gather_points();
  const vplkit::gather_point<double> g = named[1].gp;
  REQUIRE(named[1].name == "floor_shadow");
  std::vector<double> L(std::size_t(view.texel_count()), 0.0);  // V * luminance(L_t(x))
  double reference = 0;
  for (int t = 0; t < view.texel_count(); ++t) {
    const auto v = view.vpl_at(t);
    const double c = vplkit::luminance(vplkit::vpl_contribution(g.position, g.normal, g.albedo, v, dmin));
    if (c > 0 && f.scene.visible(g.position, g.normal, v.position, v.normal)) L[std::size_t(t)] = c;
    reference += L[std::size_t(t)];
  }
  REQUIRE(reference > 0);

  // eps = 0: the mass of contributing VPLs with pmf 0 is lost -- computed exactly
  const auto plain = vplkit::make_vpl_distribution(w, view, 0.0);
  double missing = 0;
  for (std::size_t t = 0; t < L.size(); ++t)
    if (plain.pmf(t) == 0.0) missing += L[t];
  INFO("reference " << reference << ", mass the plain CDF cannot reach " << missing);
  CHECK(missing > 0.01 * reference);

  // eps > 0: the Monte Carlo mean of L_t / p(t) converges to the reference
  const auto m = vplkit::make_vpl_distribution(w, view, 0.2);
  const int n = 200000;
  double sum = 0, sum2 = 0;
  vplkit::counter_rng rng = vplkit::make_counter_rng(3u, 9u);
  for (int i = 0; i < n; ++i) {
    const auto s = m.sample(vplkit::rng_next_double(rng));
    const double e = s.pmf > 0 ? L[s.index] / s.pmf : 0.0;
    sum += e;
    sum2 += e * e;
  }
  const double mean = sum / n;
  const double se = std::sqrt((sum2 / n - mean * mean) / (n - 1));
  INFO("mean " << mean << " se " << se);
  CHECK(std::abs(mean - reference) < 4.0 * se);
  // the exact expectation of the defensive estimator is the reference (every L_t > 0 has p > 0)
  double expectation = 0;
  for (std::size_t t = 0; t < L.size(); ++t)
    if (L[t] > 0) {
      REQUIRE(m.pmf(t) > 0.0);
      expectation += m.pmf(t) * (L[t] / m.pmf(t));
    }
  CHECK(expectation == Approx(reference).epsilon(1e-12));
}
