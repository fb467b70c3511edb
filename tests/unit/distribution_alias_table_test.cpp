// SPDX-License-Identifier: MIT
#include <vplkit/distribution/alias_table.hpp>

#include <distribution_checks.hpp>
#include <special_values.hpp>
#include <weight_generators.hpp>

#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace {

using vplkit_test::exponential_weights;
using vplkit_test::realised_alias_pmf;
using vplkit_test::u01;

}  // namespace

TEMPLATE_TEST_CASE("alias_table: pmf is w / total, total and size", "[distribution]", float,
                   double) {
  using T = TestType;
  const std::vector<T> w = {1, 2, 3, 4};
  const vplkit::alias_table<T> a(w);
  vplkit_test::require_pmf(a, T(10), {0.1, 0.2, 0.3, 0.4}, 0.0);  // exact
}

TEMPLATE_TEST_CASE("alias_table: Vose's construction realises the pmf", "[distribution]", float,
                   double) {
  using T = TestType;
  const double tol = std::is_same<T, float>::value ? 1e-7 : 1e-15;
  for (std::size_t n : {1u, 2u, 7u, 100u, 4096u, 100000u}) {
    const std::vector<T> w = exponential_weights<T>(n, unsigned(n) + 1u, 0.3);
    const vplkit::alias_table<T> a(w);
    if (a.empty()) continue;
    const std::vector<double> p = realised_alias_pmf(a);
    long double total_ld = 0.0L;
    for (T x : w) total_ld += x;
    const double total = double(total_ld);
    for (std::size_t i = 0; i < n; ++i) {
      // Thresholds are T: each carries a T rounding of up to half an ulp of 1, per bucket.
      REQUIRE(std::abs(p[i] - double(w[i]) / total) <= tol * (1.0 + double(n) * p[i]));
      REQUIRE(std::abs(double(a.pmf(i)) - double(w[i]) / total) <=
                  4.0 * double(std::numeric_limits<T>::epsilon()) * double(w[i]) / total);
      const auto& b = a.bins()[i];
      REQUIRE(b.threshold >= T(0));
      REQUIRE(b.threshold <= T(1));
      REQUIRE(b.alias < n);
      if (w[i] == T(0)) {
        REQUIRE(b.threshold == T(0));
        REQUIRE(w[b.alias] > T(0));
      }
      if (b.threshold < T(1)) REQUIRE(w[b.alias] > T(0));
    }
  }
}

TEMPLATE_TEST_CASE("alias_table: zero weights are never returned", "[distribution]", float,
                   double) {
  using T = TestType;
  const std::vector<T> w = {0, 1, 0, 0, 5, 0, 2, 0};
  const vplkit::alias_table<T> a(w);
  const std::size_t n = w.size();
  // Bucket edges, their neighbours and the extreme fractions: the places a threshold test of
  // the wrong strictness would leak.
  std::vector<T> us = {T(0), std::numeric_limits<T>::denorm_min(), T(1e-30), T(0.5),
                       std::nextafter(T(1), T(0)), T(1), std::numeric_limits<T>::infinity(),
                       -T(1), std::numeric_limits<T>::quiet_NaN()};
  vplkit_test::append_bucket_edges(us, n);
  for (T u1 : us) {
    REQUIRE(w[a.sample(u1).index] > T(0));
    for (T u2 : us) REQUIRE(w[a.sample(u1, u2).index] > T(0));
  }
  std::mt19937 rng(5);
  for (int k = 0; k < 100000; ++k) {
    REQUIRE(w[a.sample(u01<T>(rng)).index] > T(0));
    REQUIRE(w[a.sample(u01<T>(rng), u01<T>(rng)).index] > T(0));
  }
}

TEMPLATE_TEST_CASE("alias_table: pmf(sample.index) == sample.pmf", "[distribution]", float,
                   double) {
  using T = TestType;
  const std::vector<T> w = exponential_weights<T>(3000, 77u, 0.3);
  const vplkit::alias_table<T> a(w);
  std::mt19937 rng(8);
  for (int k = 0; k < 100000; ++k) {
    const auto s = a.sample(u01<T>(rng));
    REQUIRE(a.pmf(s.index) == s.pmf);
    REQUIRE(s.pmf > T(0));
    const auto s2 = a.sample(u01<T>(rng), u01<T>(rng));
    REQUIRE(a.pmf(s2.index) == s2.pmf);
  }
}

TEMPLATE_TEST_CASE("alias_table: sample(u) splits u into bucket and fraction", "[distribution]",
                   float, double) {
  using T = TestType;
  // Four buckets; weights {3, 1, 0, 4}: q = {1.5, 0.5, 0, 2}.
  const std::vector<T> w = {3, 1, 0, 4};
  const vplkit::alias_table<T> a(w);
  for (int j = 0; j < 4; ++j) {
    for (T f : {T(0), T(0.25), T(0.5), T(0.75), T(0.999)}) {
      const T u = (T(j) + f) / T(4);
      REQUIRE(a.sample(u).index == a.sample(T(j) / T(4), f).index);
    }
  }
}

TEMPLATE_TEST_CASE("alias_table: constructors, default, validation and sanitized",
                   "[distribution]", float, double) {
  using T = TestType;
  const T raw[4] = {1, 0, 2, 5};
  const std::array<T, 4> arr = {1, 0, 2, 5};
  const vplkit::alias_table<T> a(raw, 4), b(arr), c(raw), d(std::vector<T>(raw, raw + 4));
  for (const auto* x : {&b, &c, &d}) {
    for (std::size_t i = 0; i < 4; ++i) {
      REQUIRE(x->bins()[i].threshold == a.bins()[i].threshold);
      REQUIRE(x->bins()[i].alias == a.bins()[i].alias);
      REQUIRE(x->pmf(i) == a.pmf(i));
    }
  }
  const vplkit::alias_table<T> e;
  REQUIRE(e.empty());
  REQUIRE(e.size() == 0);
  REQUIRE(e.sample(T(0.3)).pmf == T(0));
  REQUIRE(e.sample(T(0.3), T(0.3)).pmf == T(0));
  REQUIRE(e.pmf(0) == T(0));

  using Catch::Matchers::Contains;
  const T nan = std::numeric_limits<T>::quiet_NaN();
  const T inf = std::numeric_limits<T>::infinity();
  REQUIRE_THROWS_WITH(vplkit::alias_table<T>(std::vector<T>{1, 1, 1, -2}),
                      Contains("alias_table") && Contains("weight[3]") && Contains("negative"));
  REQUIRE_THROWS_WITH(vplkit::alias_table<T>(std::vector<T>{nan}), Contains("weight[0]"));
  REQUIRE_THROWS_WITH(vplkit::alias_table<T>(std::vector<T>{0, inf}), Contains("weight[1]"));
  const auto s = vplkit::alias_table<T>::sanitized(std::vector<T>{nan, 1, -1, inf, 3});
  REQUIRE(s.zeroed == 3);
  REQUIRE(s.distribution.pmf(1) == T(0.25));
  REQUIRE(s.distribution.pmf(4) == T(0.75));
  REQUIRE(s.distribution.pmf(0) == T(0));
}

TEMPLATE_TEST_CASE("alias_table: assign rebuilds in place, rejected weights change nothing",
                   "[distribution]", float, double) {
  using T = TestType;
  const std::vector<T> a = exponential_weights<T>(2000, 31u, 0.2);
  const std::vector<T> b = exponential_weights<T>(1500, 32u, 0.2);
  vplkit::alias_table<T> t(a);
  t.assign(b);
  const vplkit::alias_table<T> fresh(b);
  REQUIRE(t.size() == fresh.size());
  REQUIRE(t.total() == fresh.total());
  for (std::size_t i = 0; i < b.size(); ++i) {
    REQUIRE(t.bins()[i].threshold == fresh.bins()[i].threshold);
    REQUIRE(t.bins()[i].alias == fresh.bins()[i].alias);
    REQUIRE(t.bins()[i].pmf == fresh.bins()[i].pmf);
  }
  std::vector<T> bad = a;
  bad[5] = std::numeric_limits<T>::infinity();
  REQUIRE_THROWS_WITH(t.assign(bad), Catch::Matchers::Contains("weight[5]"));
  REQUIRE(t.size() == fresh.size());
  REQUIRE(t.total() == fresh.total());
  t.assign(std::vector<T>(4, T(0)));
  REQUIRE(t.empty());
  REQUIRE(t.sample(T(0.5)).pmf == T(0));
}

TEST_CASE("alias_table<float>: a weight whose w / total rounds to 0 is never returned",
          "[distribution]") {
  // n w / total = 2^-149 survives as a threshold while w / total = 2^-150 rounds to pmf 0: the
  // table must not keep that bucket (it used to: sample(0.5) gave {1, 0}).
  const float w[] = {2.0f, 1.4e-45f};
  const vplkit::alias_table<float> a(w, 2);
  REQUIRE(a.pmf(1) == 0.0f);
  REQUIRE(a.bins()[1].threshold == 0.0f);
  REQUIRE(a.bins()[1].alias == 0u);
  for (float u : {0.0f, 0.25f, 0.5f, 0.75f, std::nextafter(1.0f, 0.0f)}) {
    const auto s = a.sample(u);
    REQUIRE(s.index == 0);
    REQUIRE(s.pmf == 1.0f);
    REQUIRE(a.sample(u, 0.0f).index == 0);
  }
  // The same weights sum past FLT_MAX: accepted, total() is +Inf, sum() the double sum.
  const float big[] = {3e38f, 3e38f};
  const vplkit::alias_table<float> b(big, 2);
  REQUIRE(std::isinf(b.total()));
  REQUIRE(b.sum() == 2.0 * double(3e38f));
  REQUIRE(b.pmf(0) == 0.5f);
  REQUIRE(b.sample(0.25f).pmf == 0.5f);
}
