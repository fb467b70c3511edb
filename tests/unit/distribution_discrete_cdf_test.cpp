// SPDX-License-Identifier: MIT
#include <vplkit/distribution/alias_table.hpp>
#include <vplkit/distribution/discrete_cdf.hpp>

#include <distribution_checks.hpp>
#include <weight_generators.hpp>

#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace {

using vplkit_test::exponential_weights;
using vplkit_test::require_cdf_invariants;
using vplkit_test::u01;

// A span-like type that is neither a std container nor a pointer.
template <class T>
struct view {
  const T* p;
  std::size_t n;
  const T* data() const { return p; }
  std::size_t size() const { return n; }
};

}  // namespace

TEMPLATE_TEST_CASE("discrete_cdf: pmf, total and CDF of small inputs", "[distribution]", float,
                   double) {
  using T = TestType;
  const std::vector<T> w = {1, 2, 3, 4};
  const vplkit::discrete_cdf<T> d(w);
  vplkit_test::require_pmf(d, T(10), {0.1, 0.2, 0.3, 0.4}, 1e-6);  // CDF differences: not exact
  REQUIRE(d.pmf(std::size_t(-1)) == T(0));
  REQUIRE(d.cdf()[0] == T(0));
  REQUIRE(d.cdf()[1] == T(0.1));
  REQUIRE(d.cdf()[3] == T(0.6));
  REQUIRE(d.cdf()[4] == T(1));
  require_cdf_invariants(d, w);
}

TEMPLATE_TEST_CASE("discrete_cdf: sample returns the largest i with cdf(i) <= u", "[distribution]",
                   float, double) {
  using T = TestType;
  const std::vector<T> w = {1, 0, 3};  // cdf = {0, 0.25, 0.25, 1}
  const vplkit::discrete_cdf<T> d(w);
  REQUIRE(d.cdf()[1] == T(0.25));
  REQUIRE(d.cdf()[2] == T(0.25));
  REQUIRE(d.sample(T(0)).index == 0);
  REQUIRE(d.sample(std::nextafter(T(0.25), T(0))).index == 0);
  REQUIRE(d.sample(T(0.25)).index == 2);  // never the zero-width bin 1
  REQUIRE(d.sample(T(0.5)).index == 2);
  REQUIRE(d.sample(T(1)).index == 2);
  REQUIRE(d.sample(T(0.1)).pmf == T(0.25));
  REQUIRE(d.sample(T(0.9)).pmf == T(0.75));
  for (T u : {T(0), T(0.2), T(0.25), T(0.3), T(0.99), T(1)}) {
    REQUIRE(d.sample_binary_search(u).index == d.sample(u).index);
    REQUIRE(d.sample_binary_search(u).pmf == d.sample(u).pmf);
  }
}

TEMPLATE_TEST_CASE("discrete_cdf: every constructor gives the same distribution",
                   "[distribution]", float, double) {
  using T = TestType;
  const T raw[5] = {0.5, 0, 2, 7, 1};
  const std::vector<T> vec(raw, raw + 5);
  const std::array<T, 5> arr = {raw[0], raw[1], raw[2], raw[3], raw[4]};
  const vplkit::discrete_cdf<T> a(raw, 5), b(vec), c(arr), d(raw), e(view<T>{raw, 5});
  for (const auto* x : {&b, &c, &d, &e}) {
    REQUIRE(x->cdf() == a.cdf());
    REQUIRE(x->guide() == a.guide());
    REQUIRE(x->total() == a.total());
  }
  // Copies and moves are plain value semantics.
  vplkit::discrete_cdf<T> f = a;
  const vplkit::discrete_cdf<T> g = std::move(f);
  REQUIRE(g.cdf() == a.cdf());
}

TEMPLATE_TEST_CASE("discrete_cdf: default-constructed and zero-size distributions are empty",
                   "[distribution]", float, double) {
  using T = TestType;
  const vplkit::discrete_cdf<T> a;
  const vplkit::discrete_cdf<T> b(static_cast<const T*>(nullptr), 0);
  for (const auto* d : {&a, &b}) {
    REQUIRE(d->empty());
    REQUIRE(d->size() == 0);
    REQUIRE(d->total() == T(0));
    REQUIRE(d->pmf(0) == T(0));
    REQUIRE(d->sample(T(0.5)).index == 0);
    REQUIRE(d->sample(T(0.5)).pmf == T(0));
    REQUIRE(d->sample_binary_search(T(0.5)).pmf == T(0));
    REQUIRE(d->cdf() == std::vector<T>{T(0)});
    REQUIRE(d->guide().size() == d->guide_size() + 1);
  }
}

TEMPLATE_TEST_CASE("discrete_cdf: invalid weights are rejected naming the first bad index",
                   "[distribution]", float, double) {
  using T = TestType;
  const T nan = std::numeric_limits<T>::quiet_NaN();
  const T inf = std::numeric_limits<T>::infinity();
  using Catch::Matchers::Contains;
  {
    const std::vector<T> w = {1, 2, -1, nan};
    REQUIRE_THROWS_WITH(vplkit::discrete_cdf<T>(w), Contains("weight[2]") && Contains("-1") &&
                                                         Contains("negative"));
  }
  {
    const std::vector<T> w = {1, nan, -1};
    REQUIRE_THROWS_WITH(vplkit::discrete_cdf<T>(w), Contains("weight[1]") && Contains("NaN"));
  }
  {
    const std::vector<T> w = {1, 2, 3, -inf};
    REQUIRE_THROWS_WITH(vplkit::discrete_cdf<T>(w), Contains("weight[3]") && Contains("infinite"));
  }
  REQUIRE_THROWS_AS(vplkit::discrete_cdf<T>(static_cast<const T*>(nullptr), 3),
                    vplkit::invalid_input);
  // -0 is a zero weight, not a negative one.
  const std::vector<T> w = {T(-0.0), 1};
  const vplkit::discrete_cdf<T> d(w);
  REQUIRE(d.pmf(0) == T(0));
  REQUIRE(d.sample(T(0)).index == 1);
}

TEMPLATE_TEST_CASE("discrete_cdf: sanitized zeroes and counts bad weights", "[distribution]",
                   float, double) {
  using T = TestType;
  const T nan = std::numeric_limits<T>::quiet_NaN();
  const T inf = std::numeric_limits<T>::infinity();
  const std::vector<T> w = {1, nan, 2, -3, inf, 1};
  const auto s = vplkit::discrete_cdf<T>::sanitized(w);
  REQUIRE(s.zeroed == 3);
  const vplkit::discrete_cdf<T> ref(std::vector<T>{1, 0, 2, 0, 0, 1});
  REQUIRE(s.distribution.cdf() == ref.cdf());
  REQUIRE(s.distribution.total() == T(4));
  const auto clean = vplkit::discrete_cdf<T>::sanitized(ref.cdf().data(), 3);
  REQUIRE(clean.zeroed == 0);
}

TEST_CASE("discrete_cdf<float>: a total beyond FLT_MAX is accepted (total() is +Inf, sum() "
          "finite), and a double sum that overflows is rejected", "[distribution]") {
  const std::vector<float> w(4, std::ldexp(1.0f, 127));  // 4 * 2^127 > FLT_MAX
  const vplkit::discrete_cdf<float> f(w);
  REQUIRE(std::isinf(f.total()));
  REQUIRE(f.sum() == std::ldexp(1.0, 129));
  REQUIRE_FALSE(f.empty());
  for (std::size_t i = 0; i < 4; ++i) REQUIRE(f.pmf(i) == 0.25f);
  REQUIRE(f.cdf() == std::vector<float>{0.0f, 0.25f, 0.5f, 0.75f, 1.0f});
  const std::vector<double> wd(4, std::ldexp(1.0, 127));
  const vplkit::discrete_cdf<double> d(wd);
  REQUIRE(d.pmf(2) == 0.25);
  const std::vector<double> huge(4, 1e308);
  REQUIRE_THROWS_WITH(vplkit::discrete_cdf<double>(huge),
                      Catch::Matchers::Contains("sum to more than the largest finite double"));
  // Overflow inside one summation lane (the first two of 16 weights share a lane).
  std::vector<double> lane(16, 0.0);
  lane[0] = lane[1] = 1.7e308;
  REQUIRE_THROWS_AS(vplkit::discrete_cdf<double>(lane), vplkit::invalid_input);
  REQUIRE_THROWS_AS(vplkit::alias_table<double>(lane), vplkit::invalid_input);
}

TEMPLATE_TEST_CASE("discrete_cdf: CDF invariants and pmf accuracy on random weights",
                   "[distribution]", float, double) {
  using T = TestType;
  for (std::size_t n : {1u, 2u, 3u, 17u, 1000u, 4097u, 100000u}) {
    const std::vector<T> w = exponential_weights<T>(n, unsigned(n), 0.3);
    const vplkit::discrete_cdf<T> d(w);
    if (d.empty()) continue;
    require_cdf_invariants(d, w);
    double total = 0.0;
    for (T x : w) total += double(x);
    REQUIRE(double(d.total()) == Approx(total).epsilon(1e-6));
    // pmf is a difference of stored CDF values: absolute error ~ one ulp of the CDF near 1.
    const double abs_tol = std::is_same<T, float>::value ? 2e-7 : 1e-15;
    double sum = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      REQUIRE(std::abs(double(d.pmf(i)) - double(w[i]) / total) <= abs_tol);
      sum += double(d.pmf(i));
    }
    // Telescopes to cdf[n] - cdf[0] = 1, up to the rounding of each float subtraction.
    REQUIRE(sum == Approx(1.0).epsilon(std::is_same<T, float>::value ? 1e-6 : 1e-12));
  }
}

TEMPLATE_TEST_CASE("discrete_cdf: guide entry j is the largest i with cdf(i) <= j / m",
                   "[distribution]", float, double) {
  using T = TestType;
  for (std::size_t n : {1u, 5u, 64u, 1000u, 65536u}) {
    std::vector<T> w = exponential_weights<T>(n, 7u + unsigned(n), 0.5);
    w[0] = T(1);
    // A spike that packs many CDF steps into one guide bucket.
    if (n > 10) {
      for (std::size_t i = 0; i < n / 2; ++i) w[i] = T(1e-6) * w[i];
    }
    const vplkit::discrete_cdf<T> d(w);
    const std::size_t m = d.guide_size();
    REQUIRE(m == vplkit::discrete_guide_size(n));
    REQUIRE(d.guide().size() == m + 1);
    const auto& c = d.cdf();
    std::size_t i = 0;
    for (std::size_t j = 0; j <= m; ++j) {
      const double x = double(j) / double(m);
      while (i + 1 < n && double(c[i + 1]) <= x) ++i;
      REQUIRE(d.guide()[j] == i);
    }
  }
}

TEST_CASE("discrete_guide_size is the smallest power of two >= n", "[distribution]") {
  REQUIRE(vplkit::discrete_guide_size(0) == 1);
  REQUIRE(vplkit::discrete_guide_size(1) == 1);
  REQUIRE(vplkit::discrete_guide_size(2) == 2);
  REQUIRE(vplkit::discrete_guide_size(3) == 4);
  REQUIRE(vplkit::discrete_guide_size(1024) == 1024);
  REQUIRE(vplkit::discrete_guide_size(1025) == 2048);
  REQUIRE(vplkit::discrete_guide_size(std::size_t(1) << 24) == std::size_t(1) << 24);
}

TEMPLATE_TEST_CASE("discrete_clamp_u maps every T into 0 <= u < 1", "[distribution]", float, double) {
  using T = TestType;
  const T below1 = std::nextafter(T(1), T(0));
  REQUIRE(vplkit::discrete_u_max<T>() == below1);
  REQUIRE(vplkit::discrete_clamp_u(T(0.25)) == T(0.25));
  REQUIRE(vplkit::discrete_clamp_u(T(0)) == T(0));
  REQUIRE(vplkit::discrete_clamp_u(T(-0.0)) == T(0));
  REQUIRE(vplkit::discrete_clamp_u(T(-1)) == T(0));
  REQUIRE(vplkit::discrete_clamp_u(std::numeric_limits<T>::quiet_NaN()) == T(0));
  REQUIRE(vplkit::discrete_clamp_u(-std::numeric_limits<T>::infinity()) == T(0));
  REQUIRE(vplkit::discrete_clamp_u(T(1)) == below1);
  REQUIRE(vplkit::discrete_clamp_u(std::numeric_limits<T>::infinity()) == below1);
  REQUIRE(vplkit::discrete_clamp_u(below1) == below1);
}

TEMPLATE_TEST_CASE("discrete_cdf_search finds the largest i in lo..hi with cdf(i) <= u",
                   "[distribution]", float, double) {
  using T = TestType;
  const std::vector<T> c = {0, T(0.25), T(0.25), T(0.5), T(0.75), T(0.75), T(0.75), T(1)};
  for (std::size_t lo = 0; lo < 7; ++lo) {
    for (std::size_t hi = lo; hi < 7; ++hi) {
      for (T u : {T(0), T(0.1), T(0.25), T(0.3), T(0.5), T(0.6), T(0.75), T(0.9)}) {
        if (!(c[lo] <= u)) continue;
        std::size_t expect = lo;
        for (std::size_t i = lo; i <= hi; ++i) {
          if (c[i] <= u) expect = i;
        }
        REQUIRE(vplkit::discrete_cdf_search(c.data(), lo, hi, u) == expect);
      }
    }
  }
}

TEMPLATE_TEST_CASE("discrete_cdf: pmf(sample(u).index) == sample(u).pmf", "[distribution]",
                   float, double) {
  using T = TestType;
  const std::vector<T> w = exponential_weights<T>(5000, 3u, 0.4);
  const vplkit::discrete_cdf<T> d(w);
  std::mt19937 rng(11);
  for (int k = 0; k < 200000; ++k) {
    const auto s = d.sample(u01<T>(rng));
    REQUIRE(s.pmf > T(0));
    REQUIRE(w[s.index] > T(0));
    REQUIRE(d.pmf(s.index) == s.pmf);
  }
}

// The guided search must return exactly what a plain binary search returns: random u, every
// stored CDF value, and its neighbours one ulp up and down (where a floor(u * m) or a comparison
// done slightly differently would go wrong first).
TEMPLATE_TEST_CASE("discrete_cdf: guided search == binary search on millions of u",
                   "[distribution]", float, double) {
  using T = TestType;
  std::vector<std::vector<T>> inputs;
  inputs.push_back(exponential_weights<T>(1, 1u));
  inputs.push_back(exponential_weights<T>(3, 2u));
  inputs.push_back(exponential_weights<T>(1000, 3u, 0.5));
  inputs.push_back(exponential_weights<T>(4097, 4u, 0.1));
  inputs.push_back(exponential_weights<T>(300000, 5u, 0.3));
  {  // spiky: most mass in a few weights, many tiny ones crowding single guide buckets
    std::vector<T> w = exponential_weights<T>(70000, 6u, 0.2);
    for (std::size_t i = 0; i < w.size(); ++i) w[i] = (i % 997 == 0) ? T(1e6) * w[i] : w[i];
    inputs.push_back(w);
  }
  std::mt19937 rng(2024);
  std::size_t checked = 0;
  for (const auto& w : inputs) {
    const vplkit::discrete_cdf<T> d(w);
    REQUIRE_FALSE(d.empty());
    auto check = [&](T u) {
      const auto g = d.sample(u);
      const auto b = d.sample_binary_search(u);
      if (g.index != b.index) FAIL("guided " << g.index << " != binary " << b.index << " at u = " << u);
      ++checked;
    };
    for (T c : d.cdf()) {
      check(c);
      check(std::nextafter(c, T(0)));
      check(std::nextafter(c, T(2)));
    }
    for (int k = 0; k < 1000000; ++k) check(u01<T>(rng));
    // Full-precision u (not on the 2^-24 grid) for double.
    std::uniform_real_distribution<T> full(T(0), T(1));
    for (int k = 0; k < 200000; ++k) check(full(rng));
  }
  REQUIRE(checked > 6000000);
}

// Inverse transform is monotone in u: stratified u (one per stratum) put within +-1 of
// N * pmf(i) samples in every bin. The alias table has no such property.
TEMPLATE_TEST_CASE("discrete_cdf: stratified u stay stratified", "[distribution]", float,
                   double) {
  using T = TestType;
  const std::vector<T> w = exponential_weights<T>(100, 9u, 0.2);
  const vplkit::discrete_cdf<T> d(w);
  const std::size_t N = 1 << 16;
  std::vector<std::size_t> counts(w.size(), 0);
  for (std::size_t k = 0; k < N; ++k) ++counts[d.sample((T(k) + T(0.5)) / T(N)).index];
  for (std::size_t i = 0; i < w.size(); ++i) {
    REQUIRE(std::abs(double(counts[i]) - double(N) * double(d.pmf(i))) <= 1.0 + 1e-3);
  }
}

TEST_CASE("discrete_cdf<double>: pmf matches w / total to double precision", "[distribution]") {
  const std::vector<double> w = exponential_weights<double>(100000, 42u, 0.1);
  const vplkit::discrete_cdf<double> d(w);
  long double total = 0.0L;
  for (double x : w) total += x;
  for (std::size_t i = 0; i < w.size(); ++i) {
    REQUIRE(std::abs(double(d.pmf(i)) - double(w[i] / total)) <= 1e-15);
  }
}

TEMPLATE_TEST_CASE("discrete_cdf: assign rebuilds in place, rejected weights change nothing",
                   "[distribution]", float, double) {
  using T = TestType;
  const std::vector<T> a = exponential_weights<T>(5000, 21u, 0.2);
  const std::vector<T> b = exponential_weights<T>(3000, 22u, 0.2);
  vplkit::discrete_cdf<T> d(a);
  const T* storage = d.cdf().data();
  d.assign(b);
  const vplkit::discrete_cdf<T> fresh(b);
  REQUIRE(d.cdf() == fresh.cdf());
  REQUIRE(d.guide() == fresh.guide());
  REQUIRE(d.size() == 3000);
  REQUIRE(d.total() == fresh.total());
  REQUIRE(d.cdf().data() == storage);  // shrinking reuses the storage
  std::vector<T> bad = a;
  bad[17] = T(-1);
  REQUIRE_THROWS_WITH(d.assign(bad), Catch::Matchers::Contains("weight[17]"));
  REQUIRE(d.cdf() == fresh.cdf());
  REQUIRE(d.size() == 3000);
  d.assign(std::vector<T>(10, T(0)));
  REQUIRE(d.empty());
  REQUIRE(d.cdf() == std::vector<T>(11, T(0)));
  d.assign(a.data(), a.size());
  REQUIRE(d.cdf() == vplkit::discrete_cdf<T>(a).cdf());
}

// The lanes of the summation must not show: any n, including n < number of lanes and n not a
// multiple of it, gives the same CDF as an independent long double reference (to rounding).
TEMPLATE_TEST_CASE("discrete_cdf: every n from 1 to 70 against a long double reference",
                   "[distribution]", float, double) {
  using T = TestType;
  for (std::size_t n = 1; n <= 70; ++n) {
    const std::vector<T> w = exponential_weights<T>(n, 1000u + unsigned(n), 0.25);
    long double total = 0.0L;
    for (T x : w) total += x;
    if (total == 0.0L) continue;
    const vplkit::discrete_cdf<T> d(w);
    require_cdf_invariants(d, w);
    long double prefix = 0.0L;
    for (std::size_t i = 0; i < n; ++i) {
      prefix += w[i];
      const double ref = double(prefix / total);
      // float: the correctly rounded value (half an ulp of [0.5, 1) is eps / 4; allow eps / 2).
      // double: a few ulps (compensated lane sums, then one division).
      const double tol = std::is_same<T, float>::value ? 0.5 * 0x1p-23 : 4.0 * 0x1p-52;
      REQUIRE(std::abs(double(d.cdf()[i + 1]) - ref) <= tol);
    }
  }
}
