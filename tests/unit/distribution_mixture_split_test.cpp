// SPDX-License-Identifier: MIT
// mixture_split (the split of one u between a defensive mixture's two components) and
// defensive_mixture over components other than discrete_cdf (alias_table, flat_face_roulette).
#include <vplkit/distribution/alias_table.hpp>
#include <vplkit/distribution/defensive_mixture.hpp>
#include <vplkit/distribution/discrete_cdf.hpp>
#include <vplkit/distribution/face_roulette.hpp>
#include <vplkit/distribution/flat_face_roulette.hpp>
#include <vplkit/distribution/mixture_split.hpp>

#include <weight_generators.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace {

using vplkit_test::u01;

// us that probe the split: the ends of [0, 1), values around eps, and uniform draws.
template <class T>
std::vector<T> probe_us(T eps, unsigned seed, int draws) {
  std::vector<T> us = {T(0), std::numeric_limits<T>::denorm_min(), std::numeric_limits<T>::min(),
                       std::nextafter(T(1), T(0)), T(1), T(-1), std::numeric_limits<T>::infinity(),
                       std::numeric_limits<T>::quiet_NaN(), eps, std::nextafter(eps, T(0)),
                       std::nextafter(eps, T(1))};
  std::mt19937 rng(seed);
  for (int k = 0; k < draws; ++k) us.push_back(u01<T>(rng));
  return us;
}

// Weights with holes, and the 0/1 fallback over the "valid" entries (every fifth invalid).
std::vector<float> learned_weights(std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::exponential_distribution<double> ex(1.0);
  std::vector<float> w(n);
  for (std::size_t i = 0; i < n; ++i) w[i] = (i % 5 == 4 || i % 3 == 0) ? 0.0f : float(ex(rng));
  return w;
}
std::vector<float> valid_weights(std::size_t n) {
  std::vector<float> w(n);
  for (std::size_t i = 0; i < n; ++i) w[i] = i % 5 == 4 ? 0.0f : 1.0f;
  return w;
}

}  // namespace

TEMPLATE_TEST_CASE("mixture_split: eps = 0 gives the learned component u itself, eps = 1 the fallback",
                   "[distribution][mixture]", float, double) {
  using T = TestType;
  const vplkit::mixture_split<T> s0(T(0), false, false), s1(T(1), false, false);
  REQUIRE(s0.effective_eps() == T(0));
  REQUIRE(s0.fallback_scale() == T(0));
  REQUIRE(s0.learned_scale() == T(1));
  REQUIRE(s1.effective_eps() == T(1));
  REQUIRE(s1.fallback_scale() == T(1));
  REQUIRE(s1.learned_scale() == T(0));
  for (T u : probe_us<T>(T(0.5), 1u, 100000)) {
    const T clamped = vplkit::discrete_clamp_u(u);
    const auto a = s0.choose(u), b = s1.choose(u);
    REQUIRE(a.component == vplkit::mixture_learned);
    REQUIRE(a.u == clamped);
    REQUIRE(b.component == vplkit::mixture_fallback);
    REQUIRE(b.u == clamped);
  }
  for (T p : {T(0), T(0.25), T(1), std::numeric_limits<T>::min()}) {
    REQUIRE(s0.pmf(p, T(0.5)) == p);
    REQUIRE(s1.pmf(T(0.5), p) == p);
  }
}

TEMPLATE_TEST_CASE("mixture_split: empty components decide the effective eps", "[distribution][mixture]",
                   float, double) {
  using T = TestType;
  const T eps = T(0.3);
  CHECK(vplkit::mixture_split<T>(eps, false, false).effective_eps() == eps);
  CHECK(vplkit::mixture_split<T>(eps, true, false).effective_eps() == T(1));
  CHECK(vplkit::mixture_split<T>(eps, false, true).effective_eps() == T(0));
  CHECK(vplkit::mixture_split<T>(eps, true, true).effective_eps() == T(0));
  CHECK(vplkit::mixture_split<T>().effective_eps() == T(0));
  CHECK(vplkit::mixture_split<T>().learned_scale() == T(1));
  // Below the smallest normal T, eps counts as 0 (the normal-range contract).
  CHECK(vplkit::mixture_split<T>(std::numeric_limits<T>::denorm_min(), false, false).effective_eps() == T(0));
  // The scales are the reciprocals, computed in double and rounded once.
  const vplkit::mixture_split<T> s(eps, false, false);
  CHECK(s.fallback_scale() == T(1.0 / double(eps)));
  CHECK(s.learned_scale() == T(1.0 / double(T(1) - eps)));
}

TEMPLATE_TEST_CASE("mixture_split: the remapped u stays in 0 <= u < 1 and is monotone per component",
                   "[distribution][mixture]", float, double) {
  using T = TestType;
  for (T eps : {T(1e-7), T(0.1), T(1) / T(3), T(0.5), T(0.9), std::nextafter(T(1), T(0))}) {
    INFO("eps = " << eps);
    const vplkit::mixture_split<T> s(eps, false, false);
    std::vector<T> us = probe_us<T>(eps, 2u, 20000);
    // Every float u in a window around eps and below 1, in increasing order.
    for (T u = std::max(T(0), eps - T(64) * std::numeric_limits<T>::epsilon()), k = 0; k < 256;
         u = std::nextafter(u, T(2)), ++k)
      us.push_back(u);
    for (T u = std::nextafter(T(1), T(0)), k = 0; k < 64; u = std::nextafter(u, T(0)), ++k) us.push_back(u);
    std::sort(us.begin(), us.end(), [](T a, T b) {  // NaN last; clamp order is the order of u
      return vplkit::discrete_clamp_u(a) < vplkit::discrete_clamp_u(b);
    });
    T last[2] = {T(-1), T(-1)};
    T prev_u = T(-1);
    for (T u : us) {
      const auto c = s.choose(u);
      const T cu = vplkit::discrete_clamp_u(u);
      REQUIRE(c.u >= T(0));
      REQUIRE(c.u < T(1));
      REQUIRE(c.component == (cu < eps ? vplkit::mixture_fallback : vplkit::mixture_learned));
      if (cu >= prev_u) REQUIRE(c.u >= last[c.component]);
      last[c.component] = c.u;
      prev_u = cu;
    }
    // The first u of the learned side maps to 0.
    REQUIRE(s.choose(eps).component == vplkit::mixture_learned);
    REQUIRE(s.choose(eps).u == T(0));
  }
}

TEMPLATE_TEST_CASE("mixture_split: NaN and out-of-range eps are rejected with a clear error",
                   "[distribution][mixture][hardcase]", float, double) {
  using T = TestType;
  for (T bad : {std::numeric_limits<T>::quiet_NaN(), T(-0.01), T(1.01), std::numeric_limits<T>::infinity()}) {
    REQUIRE_THROWS_AS(vplkit::mixture_split<T>(bad, false, false), vplkit::invalid_input);
    REQUIRE_THROWS_WITH(vplkit::mixture_split<T>(bad, true, true),
                        Catch::Matchers::Contains("mixture_split") && Catch::Matchers::Contains("eps") &&
                            Catch::Matchers::Contains("outside [0, 1]"));
  }
  REQUIRE_THROWS_WITH(vplkit::defensive_mixture<T>(vplkit::discrete_cdf<T>(), vplkit::discrete_cdf<T>(),
                                                   std::numeric_limits<T>::quiet_NaN()),
                      Catch::Matchers::Contains("defensive_mixture") && Catch::Matchers::Contains("nan"));
}

TEST_CASE("defensive_mixture<discrete_cdf>: sample is its split's choice sampled by the chosen CDF",
          "[distribution][mixture]") {
  const std::size_t n = 700;
  const vplkit::discrete_cdf<float> learned(learned_weights(n, 3u)), fallback(valid_weights(n));
  for (float eps : {0.0f, 0.05f, 0.5f, 1.0f}) {
    const vplkit::defensive_mixture<float> m(learned, fallback, eps);
    for (float u : probe_us<float>(eps, 4u, 20000)) {
      const auto c = m.split().choose(u);
      const auto& d = c.component == vplkit::mixture_fallback ? fallback : learned;
      const auto s = m.sample(u);
      REQUIRE(s.index == d.sample(c.u).index);
      REQUIRE(s.pmf == m.split().pmf(learned.pmf(s.index), fallback.pmf(s.index)));
    }
  }
}

TEST_CASE("defensive_mixture over alias_table and flat_face_roulette: pmf is the pmf of the sampled "
          "index, the split is the CDF mixture's",
          "[distribution][mixture]") {
  const int R = 16;  // faces of R^2 texels
  const std::size_t n = 2 * std::size_t(R) * std::size_t(R), face = n / 2;
  const std::vector<float> lw = learned_weights(n, 5u), vw = valid_weights(n);
  std::vector<float> front_empty = lw;
  for (std::size_t i = 0; i < face; ++i) front_empty[i] = 0.0f;
  const std::vector<float> zeros(n, 0.0f);
  struct weights_pair {
    const char* name;
    const std::vector<float>* learned;
    const std::vector<float>* fallback;
  };
  for (const weights_pair& wp : {weights_pair{"holes + valid", &lw, &vw}, weights_pair{"front face empty", &front_empty, &vw},
                                 weights_pair{"learned empty", &zeros, &vw}, weights_pair{"fallback empty", &lw, &zeros}}) {
    for (float eps : {0.0f, 0.1f, 0.75f, 1.0f}) {
      INFO(wp.name << ", eps = " << eps);
      const vplkit::defensive_mixture<float> joint(vplkit::discrete_cdf<float>(*wp.learned),
                                                   vplkit::discrete_cdf<float>(*wp.fallback), eps);
      const vplkit::defensive_mixture<float, vplkit::alias_table<float>> alias(
          vplkit::alias_table<float>(*wp.learned), vplkit::alias_table<float>(*wp.fallback), eps);
      const vplkit::face_roulette<float> rl(vplkit::discrete_cdf<float>(wp.learned->data(), face),
                                            vplkit::discrete_cdf<float>(wp.learned->data() + face, face));
      const vplkit::face_roulette<float> rf(vplkit::discrete_cdf<float>(wp.fallback->data(), face),
                                            vplkit::discrete_cdf<float>(wp.fallback->data() + face, face));
      const vplkit::defensive_mixture<float, vplkit::flat_face_roulette<float>> flat(
          vplkit::flat_face_roulette<float>(rl, R), vplkit::flat_face_roulette<float>(rf, R), eps);
      for (const auto* split : {&alias.split(), &flat.split()}) {
        REQUIRE(split->effective_eps() == joint.effective_eps());
        REQUIRE(split->fallback_scale() == joint.fallback_scale());
        REQUIRE(split->learned_scale() == joint.learned_scale());
      }
      REQUIRE(alias.size() == n);
      REQUIRE(flat.size() == n);
      REQUIRE(alias.empty() == joint.empty());
      REQUIRE(flat.empty() == joint.empty());
      for (float u : probe_us<float>(joint.effective_eps(), 6u, 20000)) {
        const auto a = alias.sample(u), f = flat.sample(u);
        REQUIRE(a.pmf == alias.pmf(a.index));
        REQUIRE(f.pmf == flat.pmf(f.index));
        REQUIRE(a.pmf > 0.0f);
        REQUIRE(f.pmf > 0.0f);
        // The component the split picked produced the index.
        const auto c = joint.split().choose(u);
        REQUIRE(a.index == (c.component == vplkit::mixture_fallback ? alias.fallback() : alias.learned()).sample(c.u).index);
        REQUIRE(f.index == (c.component == vplkit::mixture_fallback ? flat.fallback() : flat.learned()).sample(c.u).index);
      }
      // The same pmf as the joint mixture up to the components' rounding of w_i / sum w.
      double sum_a = 0.0, sum_f = 0.0;
      for (std::size_t i = 0; i < n; ++i) {
        REQUIRE((alias.pmf(i) > 0.0f) == (joint.pmf(i) > 0.0f));
        REQUIRE((flat.pmf(i) > 0.0f) == (joint.pmf(i) > 0.0f));
        REQUIRE(alias.pmf(i) == Approx(joint.pmf(i)).epsilon(1e-5).margin(1e-7));
        REQUIRE(flat.pmf(i) == Approx(joint.pmf(i)).epsilon(1e-5).margin(1e-7));
        sum_a += alias.pmf(i);
        sum_f += flat.pmf(i);
      }
      REQUIRE(sum_a == Approx(1.0).epsilon(1e-5));
      REQUIRE(sum_f == Approx(1.0).epsilon(1e-5));
    }
  }
}

TEST_CASE("defensive_mixture over alias_table: components of different sizes are rejected, an empty one "
          "is not",
          "[distribution][mixture][hardcase]") {
  const vplkit::alias_table<float> a(std::vector<float>{1, 2}), b(std::vector<float>{1, 1, 1}), none;
  REQUIRE_THROWS_WITH((vplkit::defensive_mixture<float, vplkit::alias_table<float>>(a, b, 0.1f)),
                      Catch::Matchers::Contains("2 entries") && Catch::Matchers::Contains("3"));
  REQUIRE_THROWS_WITH((vplkit::defensive_mixture<float, vplkit::alias_table<float>>(b, a, 0.1f)),
                      Catch::Matchers::Contains("3 entries") && Catch::Matchers::Contains("2"));
  const vplkit::defensive_mixture<float, vplkit::alias_table<float>> m(a, none, 0.1f);
  CHECK(m.size() == 2);
  CHECK(m.effective_eps() == 0.0f);
  const vplkit::defensive_mixture<float, vplkit::alias_table<float>> e(none, none, 0.1f);
  CHECK(e.empty());
  CHECK(e.sample(0.5f).pmf == 0.0f);
  CHECK(e.pmf(0) == 0.0f);
}
