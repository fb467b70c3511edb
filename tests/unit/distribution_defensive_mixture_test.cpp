// SPDX-License-Identifier: MIT
#include <vplkit/distribution/defensive_mixture.hpp>

#include <weight_generators.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace {

using vplkit_test::u01;

// A learned CDF with holes (zeros) and a 0/1 fallback over "valid" entries.
template <class T>
void make_inputs(std::vector<T>* learned, std::vector<T>* valid, std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::exponential_distribution<double> ex(1.0);
  learned->resize(n);
  valid->resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    (*valid)[i] = (i % 5 == 4) ? T(0) : T(1);  // every fifth entry invalid (outside the disk)
    (*learned)[i] = ((*valid)[i] > T(0) && i % 3 != 0) ? T(ex(rng)) : T(0);  // holes
  }
}

// The mixture with weight eps on the valid-texel fallback of make_inputs(n, seed).
template <class T>
vplkit::defensive_mixture<T> make_mixture(std::size_t n, unsigned seed, T eps) {
  std::vector<T> lw, vw;
  make_inputs<T>(&lw, &vw, n, seed);
  return vplkit::defensive_mixture<T>(vplkit::discrete_cdf<T>(lw), vplkit::discrete_cdf<T>(vw), eps);
}

}  // namespace

TEMPLATE_TEST_CASE("defensive_mixture: eps is validated", "[distribution]", float, double) {
  using T = TestType;
  const vplkit::discrete_cdf<T> a(std::vector<T>{1, 2}), b(std::vector<T>{1, 1});
  REQUIRE_THROWS_AS(vplkit::defensive_mixture<T>(a, b, T(-0.01)), vplkit::invalid_input);
  REQUIRE_THROWS_AS(vplkit::defensive_mixture<T>(a, b, T(1.01)), vplkit::invalid_input);
  REQUIRE_THROWS_AS(vplkit::defensive_mixture<T>(a, b, std::numeric_limits<T>::quiet_NaN()),
                    vplkit::invalid_input);
  REQUIRE_NOTHROW(vplkit::defensive_mixture<T>(a, b, T(0)));
  REQUIRE_NOTHROW(vplkit::defensive_mixture<T>(a, b, T(1)));
  const vplkit::discrete_cdf<T> c(std::vector<T>{1, 1, 1});
  REQUIRE_THROWS_WITH(vplkit::defensive_mixture<T>(a, c, T(0.1)),
                      Catch::Matchers::Contains("2") && Catch::Matchers::Contains("3"));
  REQUIRE_NOTHROW(vplkit::defensive_mixture<T>(a, vplkit::discrete_cdf<T>(), T(0.1)));
}

TEMPLATE_TEST_CASE("defensive_mixture: pmf is (1 - eps) learned + eps fallback", "[distribution]",
                   float, double) {
  using T = TestType;
  std::vector<T> lw, vw;
  make_inputs<T>(&lw, &vw, 200, 1u);
  const vplkit::discrete_cdf<T> learned(lw), fallback(vw);
  const T eps = T(0.1);
  const vplkit::defensive_mixture<T> m(learned, fallback, eps);
  REQUIRE(m.size() == 200);
  REQUIRE(m.eps() == eps);
  REQUIRE(m.effective_eps() == eps);
  double sum = 0.0;
  for (std::size_t i = 0; i < 200; ++i) {
    REQUIRE(m.pmf(i) == (T(1) - eps) * learned.pmf(i) + eps * fallback.pmf(i));
    if (vw[i] > T(0)) REQUIRE(m.pmf(i) > T(0));  // the holes of the learned CDF are covered
    if (vw[i] == T(0)) REQUIRE(m.pmf(i) == T(0));
    sum += double(m.pmf(i));
  }
  REQUIRE(sum == Approx(1.0).epsilon(1e-5));
  REQUIRE(m.pmf(200) == T(0));
}

TEMPLATE_TEST_CASE("defensive_mixture: sample returns the mixture pmf, never a zero one",
                   "[distribution]", float, double) {
  using T = TestType;
  std::vector<T> lw, vw;
  make_inputs<T>(&lw, &vw, 500, 2u);
  const vplkit::defensive_mixture<T> m(vplkit::discrete_cdf<T>(lw), vplkit::discrete_cdf<T>(vw),
                                       T(0.25));
  std::mt19937 rng(3);
  for (int k = 0; k < 100000; ++k) {
    const auto s = m.sample(u01<T>(rng));
    REQUIRE(s.pmf == m.pmf(s.index));
    REQUIRE(s.pmf > T(0));
    REQUIRE(vw[s.index] > T(0));
  }
  for (T u : {T(0), T(0.25), std::nextafter(T(0.25), T(0)), std::nextafter(T(1), T(0)), T(1),
              std::numeric_limits<T>::quiet_NaN(), T(-3), std::numeric_limits<T>::infinity()}) {
    const auto s = m.sample(u);
    REQUIRE(s.pmf == m.pmf(s.index));
    REQUIRE(s.pmf > T(0));
  }
}

TEMPLATE_TEST_CASE("defensive_mixture: eps = 0 reproduces the learned CDF exactly, eps = 1 the "
                   "fallback",
                   "[distribution]", float, double) {
  using T = TestType;
  std::vector<T> lw, vw;
  make_inputs<T>(&lw, &vw, 300, 4u);
  const vplkit::discrete_cdf<T> learned(lw), fallback(vw);
  const vplkit::defensive_mixture<T> m0(learned, fallback, T(0)), m1(learned, fallback, T(1));
  std::mt19937 rng(5);
  std::vector<T> us = {T(0), std::nextafter(T(1), T(0)), T(1)};
  for (T c : learned.cdf()) us.push_back(c);
  for (int k = 0; k < 100000; ++k) us.push_back(u01<T>(rng));
  for (T u : us) {
    const auto a = m0.sample(u), b = learned.sample(u);
    REQUIRE(a.index == b.index);
    REQUIRE(a.pmf == b.pmf);
    const auto c = m1.sample(u), d = fallback.sample(u);
    REQUIRE(c.index == d.index);
    REQUIRE(c.pmf == d.pmf);
  }
  for (std::size_t i = 0; i < 300; ++i) {
    REQUIRE(m0.pmf(i) == learned.pmf(i));
    REQUIRE(m1.pmf(i) == fallback.pmf(i));
  }
}

TEMPLATE_TEST_CASE("defensive_mixture: an empty component hands all mass to the other",
                   "[distribution]", float, double) {
  using T = TestType;
  const std::vector<T> zeros(4, T(0));
  const vplkit::discrete_cdf<T> empty(zeros), fallback(std::vector<T>{1, 1, 0, 1}),
      learned(std::vector<T>{0, 3, 1, 0});
  const vplkit::defensive_mixture<T> a(empty, fallback, T(0.2));
  REQUIRE(a.effective_eps() == T(1));
  const vplkit::defensive_mixture<T> b(learned, empty, T(0.2));
  REQUIRE(b.effective_eps() == T(0));
  const vplkit::defensive_mixture<T> c(empty, empty, T(0.2));
  const vplkit::defensive_mixture<T> d(vplkit::discrete_cdf<T>(), fallback, T(0.5));
  REQUIRE(c.empty());
  REQUIRE(c.sample(T(0.5)).pmf == T(0));
  REQUIRE(c.sample(T(0.5)).index == 0);
  REQUIRE(vplkit::defensive_mixture<T>().sample(T(0.5)).pmf == T(0));
  for (std::size_t i = 0; i < 4; ++i) {
    REQUIRE(a.pmf(i) == fallback.pmf(i));
    REQUIRE(d.pmf(i) == fallback.pmf(i));
    REQUIRE(b.pmf(i) == learned.pmf(i));
    REQUIRE(c.pmf(i) == T(0));
  }
  for (int k = 0; k <= 64; ++k) {
    const T u = T(k) / T(64);
    REQUIRE(a.sample(u).index == fallback.sample(u).index);
    REQUIRE(d.sample(u).index == fallback.sample(u).index);
    REQUIRE(b.sample(u).index == learned.sample(u).index);
    REQUIRE(a.sample(u).pmf > T(0));
    REQUIRE(b.sample(u).pmf > T(0));
  }
}

TEMPLATE_TEST_CASE("defensive_mixture: the fraction of the unit interval mapping to i is pmf(i)",
                   "[distribution]", float, double) {
  using T = TestType;
  const vplkit::defensive_mixture<T> m = make_mixture<T>(50, 6u, T(0.3));
  // Stratified sweep: each stratum-centred u counts 1 / N; monotone in u within each
  // component, so every index is off by at most one stratum per component boundary.
  const std::size_t N = 1 << 20;
  std::vector<double> count(50, 0.0);
  for (std::size_t k = 0; k < N; ++k) count[m.sample((T(k) + T(0.5)) / T(N)).index] += 1.0;
  for (std::size_t i = 0; i < 50; ++i) {
    REQUIRE(std::abs(count[i] / double(N) - double(m.pmf(i))) <= 4.0 / double(N));
  }
}

TEMPLATE_TEST_CASE("defensive_mixture: tiny and denormal eps never produce NaN or Inf",
                   "[distribution]", float, double) {
  using T = TestType;
  const vplkit::discrete_cdf<T> learned(std::vector<T>{0, 1, 2, 0}), fallback(std::vector<T>{1, 1, 1, 1});
  for (T eps : {std::numeric_limits<T>::denorm_min(), std::numeric_limits<T>::min(), T(1e-30),
                std::nextafter(T(1), T(0))}) {
    const vplkit::defensive_mixture<T> m(learned, fallback, eps);
    REQUIRE(std::isfinite(m.fallback_scale()));
    REQUIRE(std::isfinite(m.learned_scale()));
    for (T u : {T(0), std::numeric_limits<T>::denorm_min(), eps, std::nextafter(eps, T(0)),
                T(0.5), std::nextafter(T(1), T(0)), T(1)}) {
      const auto s = m.sample(u);
      REQUIRE(s.index < 4);
      REQUIRE(s.pmf > T(0));
      REQUIRE(std::isfinite(s.pmf));
      REQUIRE(s.pmf == m.pmf(s.index));
    }
  }
}

// A fallback pmf and an eps whose product falls below FLT_MIN: u = 0 returns that index, and its
// pmf is floored to FLT_MIN (never 0, never a denormal that a GPU reads as 0).
TEST_CASE("defensive_mixture: a product that underflows FLT_MIN is floored", "[distribution]") {
  const vplkit::discrete_cdf<float> learned(std::vector<float>{0.0f, 1.0f});
  const vplkit::discrete_cdf<float> fallback(std::vector<float>{0x1p-99f, 1.0f});
  REQUIRE(fallback.pmf(0) == 0x1p-99f);
  const vplkit::defensive_mixture<float> m(learned, fallback, 0x1p-30f);  // eps pmf = 2^-129
  const auto s = m.sample(0.0f);
  REQUIRE(s.index == 0);
  REQUIRE(s.pmf == std::numeric_limits<float>::min());
  REQUIRE(m.pmf(0) == s.pmf);
  REQUIRE(m.pmf(1) == Approx(1.0f));
}
