// SPDX-License-Identifier: MIT
// docs/math.md section 10 for the CDF builders: empty inputs, empty DPRSMs, degenerate tracers, bad
// weights. One TEST_CASE per hard case; nothing may produce NaN or Inf.
#include <vplkit/builders/gather_subset.hpp>
#include <vplkit/builders/gbg_weights.hpp>
#include <vplkit/builders/global_weights.hpp>
#include <vplkit/builders/local_weights.hpp>
#include <vplkit/builders/vpl_distribution.hpp>
#include <vplkit/core/error.hpp>

#include <synthetic_scene.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

using vplkit::vec3;

namespace {

template <class T>
void require_all_zero(const std::vector<T>& w) {
  for (std::size_t i = 0; i < w.size(); ++i) {
    INFO("texel " << i);
    REQUIRE(w[i] == T(0));
    REQUIRE(!std::signbit(w[i]));
  }
}

template <class T>
void require_finite_nonnegative(const std::vector<T>& w) {
  for (std::size_t i = 0; i < w.size(); ++i) {
    INFO("texel " << i);
    REQUIRE(std::isfinite(w[i]));
    REQUIRE(w[i] >= T(0));
  }
}

template <class T>
vplkit::gbg_params<T> gbg(int n_dirs = 4, T tol = T(0.3)) {
  vplkit::gbg_params<T> p;
  p.n_dirs = n_dirs;
  p.depth_tolerance = tol;
  p.dmin = T(0);
  return p;
}

template <class T>
void make_background(vplkit_test::gbuffer_data<T>& gb) {
  for (auto& n : gb.normal) n = vec3<T>(T(0));
}

// What an estimator does with a distribution: draw, divide by the pmf, skip pmf 0.
template <class T>
T one_sample_estimate(const vplkit::defensive_mixture<T>& m, const vplkit::dprsm_view<T>& view,
                      const vplkit::gather_point<T>& g, T u) {
  const vplkit::discrete_sample<T> s = m.sample(u);
  if (!(s.pmf > T(0))) return T(0);
  return vplkit::luminance(
             vplkit::vpl_contribution(g.position, g.normal, g.albedo, view.vpl_at(int(s.index)), T(0))) /
         s.pmf;
}

}  // namespace

TEMPLATE_TEST_CASE("builders hard case: every gather point is background", "[builders][hardcase]",
                   float, double) {
  using T = TestType;
  const vplkit_test::synthetic_scene<T> s;
  const auto d = s.make_dprsm(8);
  auto gb = s.make_gbuffer(9, 7);
  make_background(gb);
  const auto view = d.view();
  // subsets come back empty: every stratum drops
  const std::vector<int> subset = vplkit::stratified_gather_subset(gb.view(), {0, 0, 9, 7}, 16, 1u);
  REQUIRE(subset.empty());
  const std::vector<T> global = vplkit::build_global_weights(gb.view(), subset, view, T(0));
  require_all_zero(global);
  const std::vector<T> local =
      vplkit::build_local_weights(gb.view(), vplkit::image_regions(9, 7, 2, 2), 8, 1u, view, T(0));
  require_all_zero(local);
  vplkit::gbg_stats st;
  const vplkit_test::exact_tracer<T> tr{&s};
  const std::vector<T> g = vplkit::build_gbg_weights(gb.view(), view, tr, gbg<T>(), &st);
  require_all_zero(g);
  REQUIRE(st.gather_points == 0);
  REQUIRE(st.rays == 0);
  REQUIRE(st.filled == 0);
  // eps = 0: an empty distribution whose sample() has pmf 0; eps > 0: uniform over the VPLs
  const auto m0 = vplkit::make_vpl_distribution(global, view, T(0));
  REQUIRE(m0.empty());
  REQUIRE(m0.sample(T(0.5)).pmf == T(0));
  const auto m1 = vplkit::make_vpl_distribution(global, view, T(0.1));
  REQUIRE(!m1.empty());
  REQUIRE(m1.effective_eps() == T(1));
}

TEMPLATE_TEST_CASE("builders hard case: a light whose DPRSM is all zero", "[builders][hardcase]",
                   float, double) {
  using T = TestType;
  const vplkit_test::synthetic_scene<T> s;
  auto d = s.make_dprsm(8);
  for (auto& a : d.albedo) a = vec3<T>(T(0));  // the light sees nothing (e.g. it is outside)
  const auto view = d.view();
  const auto gb = s.make_gbuffer(6, 6);
  const std::vector<int> subset = vplkit::stratified_gather_subset(gb.view(), {0, 0, 6, 6}, 8, 2u);
  REQUIRE(subset.size() == 8);
  require_all_zero(vplkit::build_global_weights(gb.view(), subset, view, T(0)));
  require_all_zero(vplkit::build_local_weights(gb.view(), vplkit::image_regions(6, 6), 4, 2u, view, T(0)));
  vplkit::gbg_stats st;
  const vplkit_test::exact_tracer<T> tr{&s};
  const std::vector<T> g = vplkit::build_gbg_weights(gb.view(), view, tr, gbg<T>(), &st);
  require_all_zero(g);
  REQUIRE(st.hits == st.rays);
  REQUIRE(st.lit_hits == 0);  // nothing is lit
  REQUIRE(st.holes == 0);     // and nothing is a hole: no texel carries a VPL
  // no VPL at all: the fallback is empty too, so even eps > 0 gives an empty distribution
  REQUIRE(vplkit::make_vpl_fallback(view).empty());
  for (T eps : {T(0), T(0.5), T(1)}) {
    const auto m = vplkit::make_vpl_distribution(g, view, eps);
    REQUIRE(m.empty());
    REQUIRE(m.sample(T(0.3)).pmf == T(0));
  }
}

TEST_CASE("builders hard case: n_dirs = 0 (and negative) is rejected", "[builders][hardcase]") {
  const vplkit_test::synthetic_scene<double> s;
  const auto d = s.make_dprsm(4);
  const auto gb = s.make_gbuffer(4, 4);
  const vplkit_test::exact_tracer<double> tr{&s};
  for (int n : {0, -1}) {
    try {
      vplkit::build_gbg_weights(gb.view(), d.view(), tr, gbg<double>(n));
      FAIL("n_dirs = " << n << " accepted");
    } catch (const vplkit::invalid_input& e) {
      CHECK(std::string(e.what()).find("n_dirs") != std::string::npos);
    }
  }
}

TEMPLATE_TEST_CASE("builders hard case: a region with no valid pixel", "[builders][hardcase]",
                   float, double) {
  using T = TestType;
  const vplkit_test::synthetic_scene<T> s;
  const auto d = s.make_dprsm(8);
  const auto view = d.view();
  auto gb = s.make_gbuffer(10, 8);
  // the top-left region (x < 5, y < 4) is background
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 5; ++x) gb.normal[std::size_t(y * 10 + x)] = vec3<T>(T(0));
  const vplkit::image_regions regions(10, 8);
  const auto subsets = vplkit::local_gather_subsets(gb.view(), regions, 6, 4u);
  REQUIRE(subsets[0].empty());
  std::vector<T> flat(4 * std::size_t(view.texel_count()));
  int used[4];
  vplkit::build_local_weights(gb.view(), regions, subsets, view, T(0), flat.data(), flat.size(), used);
  REQUIRE(used[0] == 0);
  for (int i = 1; i < 4; ++i) REQUIRE(used[i] == 6);
  require_finite_nonnegative(flat);

  const auto m0 = vplkit::make_local_vpl_distributions(flat, 4, view, T(0));
  REQUIRE(m0[0].empty());
  for (int i = 1; i < 4; ++i) REQUIRE(!m0[std::size_t(i)].empty());
  const auto m1 = vplkit::make_local_vpl_distributions(flat, 4, view, T(0.05));
  REQUIRE(!m1[0].empty());
  REQUIRE(m1[0].effective_eps() == T(1));  // nothing learned: all mass on the uniform fallback
  // the estimator copes: the empty region contributes 0 (eps = 0) or a finite value (eps > 0)
  const vplkit::gather_point<T> g = gb.view().at(6 * 10 + 7);
  for (T u : {T(0), T(0.25), T(0.999), T(1)}) {
    REQUIRE(one_sample_estimate(m0[0], view, g, u) == T(0));
    const T e = one_sample_estimate(m1[0], view, g, u);
    REQUIRE(std::isfinite(e));
    REQUIRE(e >= T(0));
  }
}

TEST_CASE("builders hard case: NaN, infinite, negative or mis-sized weights are rejected",
          "[builders][hardcase]") {
  const vplkit_test::synthetic_scene<float> s;
  const auto d = s.make_dprsm(4);
  const auto view = d.view();
  const std::size_t n = std::size_t(view.texel_count());
  const float bad[] = {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity(),
                       -1.0f, -std::numeric_limits<float>::denorm_min()};
  for (float b : bad) {
    std::vector<float> w(n, 1.0f);
    w[5] = b;
    for (float eps : {0.0f, 0.2f}) {
      try {
        vplkit::make_vpl_distribution(w, view, eps);
        FAIL("weight " << b << " accepted");
      } catch (const vplkit::invalid_input& e) {
        const std::string what = e.what();
        CHECK(what.find("make_vpl_distribution") != std::string::npos);
        CHECK(what.find("weight[5]") != std::string::npos);
      }
    }
  }
  for (std::size_t m : {std::size_t(0), n - 1, n + 1, 2 * n}) {
    const std::vector<float> w(m, 1.0f);
    CHECK_THROWS_AS(vplkit::make_vpl_distribution(w, view, 0.1f), vplkit::invalid_input);
  }
  // a -0.0 weight is a valid zero
  std::vector<float> w(n, 1.0f);
  w[3] = -0.0f;
  CHECK(vplkit::make_vpl_distribution(w, view, 0.0f).pmf(3) == 0.0f);
  // the fill refuses NaN too
  std::vector<float> nan_w(n, 0.0f);
  nan_w[7] = std::numeric_limits<float>::quiet_NaN();
  CHECK_THROWS_AS(vplkit::gbg_fill_holes(nan_w, view), vplkit::invalid_input);
}

TEST_CASE("builders hard case: eps outside [0, 1] or NaN is rejected", "[builders][hardcase]") {
  const vplkit_test::synthetic_scene<double> s;
  const auto d = s.make_dprsm(4);
  const std::vector<double> w(std::size_t(d.view().texel_count()), 1.0);
  for (double eps : {-0.1, 1.5, std::numeric_limits<double>::quiet_NaN(),
                     std::numeric_limits<double>::infinity()})
    CHECK_THROWS_AS(vplkit::make_vpl_distribution(w, d.view(), eps), vplkit::invalid_input);
  CHECK_NOTHROW(vplkit::make_vpl_distribution(w, d.view(), 1.0));
}

TEMPLATE_TEST_CASE("builders hard case: a gather point on top of a VPL with dmin = 0",
                   "[builders][hardcase]", float, double) {
  using T = TestType;
  const vplkit_test::synthetic_scene<T> s;
  const auto d = s.make_dprsm(8);
  const auto view = d.view();
  // gather points placed exactly at texel positions (d2 = 0) and next to them (d2 ~ 1e-6)
  vplkit_test::gbuffer_data<T> gb;
  gb.width = 4;
  gb.height = 1;
  int k = 0;
  for (int t = 0; t < view.texel_count() && k < 4; t += 17) {
    if (!vplkit::vpl_has_flux(view.vpl_at(t))) continue;
    const vec3<T> off = k % 2 == 0 ? vec3<T>(T(0)) : vec3<T>(T(1e-6), T(0), T(1e-6));
    gb.position.push_back(view.position[t] + off);
    gb.normal.push_back(view.normal[t]);
    gb.albedo.push_back(vec3<T>(T(0.5)));
    ++k;
  }
  REQUIRE(k == 4);
  const std::vector<T> w = vplkit::build_global_weights(gb.view(), {0, 1, 2, 3}, view, T(0));
  require_finite_nonnegative(w);
  REQUIRE(vplkit::make_vpl_distribution(w, view, T(0.1)).size() == w.size());
  // GBG from those points with a tracer that hits the gather point itself (zero-length ray)
  auto self_hit = [](vec3<T> x, vec3<T>, vec3<T>) { return vplkit::ray_hit<T>{true, x}; };
  for (auto acc : {vplkit::gbg_accumulator::paper, vplkit::gbg_accumulator::gathering})
    for (T tol : {T(0), T(0.3)}) {
      auto p = gbg<T>(8, tol);
      p.accumulator = acc;
      require_finite_nonnegative(vplkit::build_gbg_weights(gb.view(), view, self_hit, p));
    }
}

TEMPLATE_TEST_CASE("builders hard case: a tracer that misses or returns non-finite points",
                   "[builders][hardcase]", float, double) {
  using T = TestType;
  const vplkit_test::synthetic_scene<T> s;
  const auto d = s.make_dprsm(8);
  const auto gb = s.make_gbuffer(5, 5);
  const T inf = std::numeric_limits<T>::infinity(), nan = std::numeric_limits<T>::quiet_NaN();
  auto miss = [](vec3<T>, vec3<T>, vec3<T>) { return vplkit::ray_hit<T>{}; };
  vplkit::gbg_stats st;
  require_all_zero(vplkit::build_gbg_weights(gb.view(), d.view(), miss, gbg<T>(), &st));
  REQUIRE(st.hits == 0);
  const vec3<T> bad_points[] = {vec3<T>(nan), vec3<T>(inf, T(0), T(0)), vec3<T>(T(0), -inf, nan),
                                d.light.position};
  for (const vec3<T>& b : bad_points) {
    auto garbage = [b](vec3<T>, vec3<T>, vec3<T>) { return vplkit::ray_hit<T>{true, b}; };
    require_all_zero(vplkit::build_gbg_weights(gb.view(), d.view(), garbage, gbg<T>(), &st));
    REQUIRE(st.hits == st.rays);
    REQUIRE(st.lit_hits == 0);
  }
}

TEST_CASE("builders hard case: bad depth tolerance or dmin is rejected", "[builders][hardcase]") {
  const vplkit_test::synthetic_scene<double> s;
  const auto d = s.make_dprsm(4);
  const auto gb = s.make_gbuffer(4, 4);
  const vplkit_test::exact_tracer<double> tr{&s};
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  for (double tol : {-0.1, nan, inf})
    CHECK_THROWS_AS(vplkit::build_gbg_weights(gb.view(), d.view(), tr, gbg<double>(4, tol)),
                    vplkit::invalid_input);
  for (double dmin : {-0.1, nan, inf}) {
    auto p = gbg<double>();
    p.dmin = dmin;
    CHECK_THROWS_AS(vplkit::build_gbg_weights(gb.view(), d.view(), tr, p), vplkit::invalid_input);
  }
  std::vector<double> w(std::size_t(d.view().texel_count()) + 1);
  CHECK_THROWS_AS(vplkit::build_gbg_weights(gb.view(), d.view(), tr, gbg<double>(), w.data(), w.size()),
                  vplkit::invalid_input);
}

TEST_CASE("builders hard case: a 1 x 1 DPRSM and a 1 x 1 image", "[builders][hardcase]") {
  const vplkit_test::synthetic_scene<double> s;
  const auto d = s.make_dprsm(1);  // one texel per face, both valid (the centre of the disk)
  const auto view = d.view();
  const auto gb = s.make_gbuffer(1, 1);
  REQUIRE(view.texel_count() == 2);
  const auto subset = vplkit::stratified_gather_subset(gb.view(), {0, 0, 1, 1}, 5, 0u);
  REQUIRE(subset == std::vector<int>{0});
  const auto w = vplkit::build_global_weights(gb.view(), subset, view, 0.0);
  require_finite_nonnegative(w);
  const vplkit_test::exact_tracer<double> tr{&s};
  const auto g = vplkit::build_gbg_weights(gb.view(), view, tr, gbg<double>(16, 10.0));
  require_finite_nonnegative(g);
  const auto local = vplkit::build_local_weights(gb.view(), vplkit::image_regions(1, 1, 1, 1), 3, 0u, view, 0.0);
  REQUIRE(local == w);
}
