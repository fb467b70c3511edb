// SPDX-License-Identifier: MIT
// docs/math.md section 10, CDF and face-roulette hard cases: one TEST_CASE per case, each run on
// discrete_cdf and alias_table where it applies. The 2^24+ cases take about a second each
// (RelWithDebInfo, one core), so they stay here rather than in a *_slow.cpp file.
#include <vplkit/distribution/alias_table.hpp>
#include <vplkit/distribution/discrete_cdf.hpp>
#include <vplkit/distribution/face_roulette.hpp>

#include <distribution_checks.hpp>
#include <fp_mode.hpp>
#include <special_values.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <string>
#include <vector>

namespace {

using vplkit_test::finite_nonneg;
using vplkit_test::realised_alias_pmf;
using vplkit_test::require_cdf_invariants;

// The u every sampler must survive: 0, the smallest positive, a tiny one, the middle, the
// largest below 1, exactly 1, and the out-of-range ones that get clamped.
template <class T>
std::vector<T> edge_us() {
  return vplkit_test::special_values_and<T>(
      {T(1e-30), std::nextafter(T(1), T(0)), std::nextafter(T(1), T(2))});
}

// Every stored CDF value, its neighbours and the edge u's: the sampled index always has a
// positive pmf equal to pmf(index), and guided == binary search.
template <class T>
void require_cdf_sampling_consistent(const vplkit::discrete_cdf<T>& d) {
  std::vector<T> us = edge_us<T>();
  for (T c : d.cdf()) {
    us.push_back(c);
    us.push_back(std::nextafter(c, T(0)));
    us.push_back(std::nextafter(c, T(2)));
  }
  for (T u : us) {
    const auto s = d.sample(u);
    REQUIRE(s.index < d.size());
    REQUIRE(s.pmf > T(0));
    REQUIRE(s.pmf == d.pmf(s.index));
    REQUIRE(d.sample_binary_search(u).index == s.index);
  }
}

// A returned index has a positive weight and a positive pmf, the one pmf(index) reports.
template <class T>
void require_alias_sample_valid(const vplkit::alias_table<T>& a, const std::vector<T>& w,
                                const vplkit::discrete_sample<T>& s) {
  REQUIRE(w[s.index] >= std::numeric_limits<T>::min());
  REQUIRE(s.pmf >= std::numeric_limits<T>::min());
  REQUIRE(s.pmf == a.pmf(s.index));
}

template <class T>
void require_alias_never_returns_zero(const vplkit::alias_table<T>& a, const std::vector<T>& w) {
  const std::vector<T> us = edge_us<T>();
  for (T u1 : us) {
    require_alias_sample_valid(a, w, a.sample(u1));
    for (T u2 : us) require_alias_sample_valid(a, w, a.sample(u1, u2));
  }
  for (std::size_t j = 0; j < a.size(); ++j) {
    const auto& b = a.bins()[j];
    REQUIRE(finite_nonneg(b.threshold));
    REQUIRE(finite_nonneg(b.pmf));
    if (!(w[j] >= std::numeric_limits<T>::min()) || b.pmf == T(0)) REQUIRE(b.threshold == T(0));
    REQUIRE((b.threshold == T(0) || b.threshold >= std::numeric_limits<T>::min()));
    REQUIRE((b.pmf == T(0) || b.pmf >= std::numeric_limits<T>::min()));
    if (b.threshold < T(1)) REQUIRE(a.bins()[b.alias].pmf > T(0));
    // Every bucket's edge and its neighbours, with fractions 0 and just below 1.
    const T e = T(j) / T(a.size());
    for (T u : {e, std::nextafter(e, T(0)), std::nextafter(e, T(2))}) {
      require_alias_sample_valid(a, w, a.sample(u));
      require_alias_sample_valid(a, w, a.sample(u, T(0)));
      require_alias_sample_valid(a, w, a.sample(u, std::nextafter(T(1), T(0))));
    }
  }
}

// 10^k for k = lo..hi, each followed by a zero; forward, reversed and shuffled.
template <class T>
std::vector<std::vector<T>> spanning_inputs(int lo, int hi) {
  std::vector<T> w;
  for (int k = lo; k <= hi; ++k) {
    w.push_back(T(std::pow(10.0L, k)));
    w.push_back(T(0));
  }
  std::vector<T> rev(w.rbegin(), w.rend());
  std::vector<T> shuf = w;
  std::shuffle(shuf.begin(), shuf.end(), std::mt19937(1));
  return {w, rev, shuf};
}

template <class T>
void check_spanning(int lo, int hi) {
  for (const auto& w : spanning_inputs<T>(lo, hi)) {
    long double total_ld = 0.0L;
    for (T x : w) total_ld += x;
    const double total = double(total_ld);
    REQUIRE(std::isfinite(total));

    const vplkit::discrete_cdf<T> d(w);
    REQUIRE(double(d.total()) == Approx(total).epsilon(1e-6));
    require_cdf_invariants(d, w);
    require_cdf_sampling_consistent(d);
    // The CDF is stored in T: each pmf is within a couple of ulps of 1 of w / total, and a
    // weight too small for that resolution gets pmf 0 (and is then never sampled).
    const double abs_tol = 4.0 * double(std::numeric_limits<T>::epsilon());
    for (std::size_t i = 0; i < w.size(); ++i) {
      REQUIRE(std::abs(double(d.pmf(i)) - double(w[i]) / total) <= abs_tol);
    }

    const vplkit::alias_table<T> a(w);
    require_alias_never_returns_zero(a, w);
    const std::vector<double> p = realised_alias_pmf(a);
    for (std::size_t i = 0; i < w.size(); ++i) {
      const double exact = double(w[i]) / total;
      // pmf is w / total rounded once (the total itself within an ulp): relative accuracy
      // wherever that is a normal T.
      if (exact >= double(std::numeric_limits<T>::min())) {
        REQUIRE(std::abs(double(a.pmf(i)) - exact) <=
                2.0 * double(std::numeric_limits<T>::epsilon()) * exact);
      } else {
        REQUIRE(double(a.pmf(i)) <= 2.0 * double(std::numeric_limits<T>::min()));
      }
      // Vose's updates round once per donation of the large buckets: ~n double ulps.
      REQUIRE(std::abs(p[i] - exact) <= abs_tol + double(w.size()) * 0x1p-52);
    }
  }
}

template <class T>
void check_single_nonzero(std::size_t n, std::size_t k) {
  std::vector<T> w(n, T(0));
  w[k] = T(0.75);
  const vplkit::discrete_cdf<T> d(w);
  REQUIRE(d.pmf(k) == T(1));
  REQUIRE(d.total() == T(0.75));
  const vplkit::alias_table<T> a(w);
  REQUIRE(a.pmf(k) == T(1));
  for (T u : edge_us<T>()) {
    const auto s = d.sample(u);
    REQUIRE(s.index == k);
    REQUIRE(s.pmf == T(1));
    REQUIRE(d.sample_binary_search(u).index == k);
    const auto t = a.sample(u);
    REQUIRE(t.index == k);
    REQUIRE(t.pmf == T(1));
    for (T u2 : edge_us<T>()) REQUIRE(a.sample(u, u2).index == k);
  }
  // Every bucket of the alias table is all alias: threshold 0 except the one full bucket.
  std::size_t bad = 0;
  for (std::size_t j = 0; j < n; ++j) {
    const auto& b = a.bins()[j];
    bad += j == k ? b.threshold != T(1) : (b.threshold != T(0) || b.alias != k);
  }
  REQUIRE(bad == 0);
  // Every CDF value below k is 0 and every one above is 1: the whole of [0, 1) maps to k.
  for (std::size_t i = 0; i <= n; ++i) bad += d.cdf()[i] != (i <= k ? T(0) : T(1));
  REQUIRE(bad == 0);
}

}  // namespace

TEST_CASE("CDF hard case: 2^24 equal float weights give an exactly uniform pmf",
          "[distribution][hardcase]") {
  const std::size_t n = std::size_t(1) << 24;
  const std::vector<float> w(n, 0.7f);
  // Why this is hard: a float running sum stalls once it reaches 2^24 times the weight's ulp
  // scale; here it drifts far from the true sum, so a float-accumulated CDF would be wrong.
  float naive = 0.0f;
  for (float x : w) naive += x;
  REQUIRE(std::abs(double(naive) - 0.7 * double(n)) > 0.01 * 0.7 * double(n));

  const vplkit::discrete_cdf<float> d(w);
  REQUIRE(double(d.total()) == Approx(0.7 * double(n)).epsilon(1e-7));
  const float p = 0x1p-24f;
  std::size_t bad = 0;
  for (std::size_t i = 0; i < n; ++i) {
    bad += d.cdf()[i] != float(i) * p;  // cdf[i] = i / 2^24 exactly
    bad += d.pmf(i) != p;
  }
  REQUIRE(bad == 0);
  REQUIRE(d.cdf()[n] == 1.0f);
  // Every u on the 2^-24 grid (the RNG convention) maps to its own index, guided and binary.
  for (std::size_t k = 0; k < n; ++k) {
    const float u = float(k) * p;
    const auto s = d.sample(u);
    bad += s.index != k || s.pmf != p;
    bad += d.sample_binary_search(u).index != k;
  }
  REQUIRE(bad == 0);
  REQUIRE(d.sample(1.0f).index == n - 1);

  const vplkit::alias_table<float> a(w);
  for (std::size_t i = 0; i < n; ++i) {
    bad += a.pmf(i) != p;
    bad += a.bins()[i].threshold != 1.0f;  // every bucket is exactly full
  }
  REQUIRE(bad == 0);
  for (std::size_t k = 0; k < n; k += 7) bad += a.sample(float(k) * p, 0.5f).index != k;
  REQUIRE(bad == 0);
}

TEST_CASE("CDF hard case: 2^24+ equal double weights stay uniform", "[distribution][hardcase]") {
  const std::size_t n = (std::size_t(1) << 24) + 12345;
  const std::vector<double> w(n, 0.1);  // 0.1 is inexact: every partial sum rounds
  const vplkit::discrete_cdf<double> d(w);
  const double p = 1.0 / double(n);
  double worst = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    worst = std::max(worst, std::abs(d.pmf(i) - p) / p);
    // Stratum centres map to their own index.
    if (i % 5 == 0 && d.sample((double(i) + 0.5) * p).index != i) FAIL("index " << i);
  }
  REQUIRE(worst <= 1e-8);  // pmf ~ 6e-8 from differences of values < 1: ~1e-16 / 6e-8
  REQUIRE(d.sample(std::nextafter(1.0, 0.0)).index == n - 1);

  const vplkit::alias_table<double> a(w);
  worst = 0.0;
  for (std::size_t i = 0; i < n; ++i) worst = std::max(worst, std::abs(a.pmf(i) - p) / p);
  REQUIRE(worst <= 1e-14);
  for (std::size_t i = 0; i < n; i += 11) {
    if (a.sample((double(i) + 0.5) * p, 0.5).index != i) FAIL("alias index " << i);
  }
}

TEST_CASE("CDF hard case: 2^25 equal float weights, beyond float CDF resolution",
          "[distribution][hardcase]") {
  // A float CDF cannot represent i / 2^25 near 1; what is guaranteed: every stored value is the
  // correctly rounded i / n (no stalled tail), zero-width bins are never sampled, and the
  // pmf of every bin is 0, 2^-25 or 2^-24 (round-to-nearest-even pairs neighbours).
  const std::size_t n = std::size_t(1) << 25;
  const std::vector<float> w(n, 1.0f);
  const vplkit::discrete_cdf<float> d(w);
  std::size_t bad = 0, zero_width = 0;
  for (std::size_t i = 0; i <= n; ++i) bad += d.cdf()[i] != float(double(i) / double(n));
  for (std::size_t i = 0; i < n; ++i) {
    const float q = d.pmf(i);
    zero_width += q == 0.0f;
    bad += !(q == 0.0f || q == 0x1p-25f || q == 0x1p-24f);
  }
  REQUIRE(bad == 0);
  REQUIRE(zero_width > 0);          // the documented float limit is real
  REQUIRE(zero_width <= n / 4 + 1);  // only the top half [0.5, 1) loses resolution
  for (std::size_t k = 0; k < (std::size_t(1) << 24); k += 3) {
    const auto s = d.sample(float(k) * 0x1p-24f);
    bad += s.pmf == 0.0f || s.pmf != d.pmf(s.index);
  }
  REQUIRE(bad == 0);
  // The same weights in double: exactly uniform.
  const vplkit::discrete_cdf<double> dd(std::vector<double>(n, 1.0));
  for (std::size_t i = 0; i < n; i += 101) bad += dd.pmf(i) != 0x1p-25;
  REQUIRE(bad == 0);
}

TEST_CASE("CDF hard case: weights spanning 1e-38..1e38", "[distribution][hardcase]") {
  SECTION("float, 1e-38..1e38") { check_spanning<float>(-38, 38); }
  SECTION("double, 1e-38..1e38") { check_spanning<double>(-38, 38); }
  SECTION("double, 1e-300..1e300") { check_spanning<double>(-300, 300); }
}

TEST_CASE("CDF hard case: one non-zero weight among 10^7, at either end",
          "[distribution][hardcase]") {
  const std::size_t n = 10000000;
  SECTION("float, first") { check_single_nonzero<float>(n, 0); }
  SECTION("float, last") { check_single_nonzero<float>(n, n - 1); }
  SECTION("float, middle") { check_single_nonzero<float>(n, n / 2 + 1); }
  SECTION("double, first") { check_single_nonzero<double>(n, 0); }
  SECTION("double, last") { check_single_nonzero<double>(n, n - 1); }
}

TEST_CASE("CDF hard case: u = 0, the largest float below 1, exactly 1",
          "[distribution][hardcase]") {
  // Zeros at both ends: u = 0 must give the first positive weight, u -> 1 the last one.
  const std::vector<float> w = {0, 0, 2, 0, 1, 5, 0, 0};
  const vplkit::discrete_cdf<float> d(w);
  const vplkit::alias_table<float> a(w);
  const float below1 = 0x1.fffffep-1f;
  REQUIRE(below1 == std::nextafter(1.0f, 0.0f));
  for (float u : {0.0f, -0.0f, -1.0f, std::numeric_limits<float>::quiet_NaN(),
                  -std::numeric_limits<float>::infinity()}) {
    REQUIRE(d.sample(u).index == 2);
    REQUIRE(d.sample(u).pmf == d.pmf(2));
    REQUIRE(d.sample_binary_search(u).index == 2);
  }
  for (float u : {below1, 1.0f, std::nextafter(1.0f, 2.0f), 2.0f,
                  std::numeric_limits<float>::infinity()}) {
    REQUIRE(d.sample(u).index == 5);
    REQUIRE(d.sample(u).pmf == d.pmf(5));
    REQUIRE(d.sample_binary_search(u).index == 5);
  }
  require_cdf_sampling_consistent(d);
  require_alias_never_returns_zero(a, w);
  // The same with double.
  const std::vector<double> wd(w.begin(), w.end());
  const vplkit::discrete_cdf<double> dd(wd);
  REQUIRE(dd.sample(0.0).index == 2);
  REQUIRE(dd.sample(std::nextafter(1.0, 0.0)).index == 5);
  REQUIRE(dd.sample(1.0).index == 5);
  require_cdf_sampling_consistent(dd);
  require_alias_never_returns_zero(vplkit::alias_table<double>(wd), wd);
  // With a single weight the whole of [0, 1] maps to it, u = 1 included.
  const vplkit::discrete_cdf<float> one(std::vector<float>{3.0f});
  for (float u : edge_us<float>()) REQUIRE(one.sample(u).pmf == 1.0f);
}

TEST_CASE("CDF hard case: denormal weights count as zero", "[distribution][hardcase]") {
  // The normal-range contract (weights.hpp, docs/math.md, "GPU arithmetic model"): a GPU may read a denormal
  // weight as 0, so every backend does; the indices are the same with and without FTZ|DAZ.
  SECTION("float: only denormals -> empty") {
    std::vector<float> w;
    for (int k = 0; k < 100; ++k) w.push_back(float(k) * std::numeric_limits<float>::denorm_min());
    for (bool ftz : {false, true}) {
      const vplkit_test::fp_mode_scope mode(ftz);
      const vplkit::discrete_cdf<float> d(w);
      REQUIRE(d.empty());
      REQUIRE(d.total() == 0.0f);
      REQUIRE(d.cdf().back() == 0.0f);
      for (float u : edge_us<float>()) REQUIRE(d.sample(u).pmf == 0.0f);
      const vplkit::alias_table<float> a(w);
      REQUIRE(a.empty());
      for (int k = 0; k < 100; ++k) REQUIRE(a.pmf(k) == 0.0f);
    }
  }
  SECTION("float: denormals among normal weights are never returned") {
    const float dm = std::numeric_limits<float>::denorm_min();
    const float below_min = std::nextafter(std::numeric_limits<float>::min(), 0.0f);
    const std::vector<float> w = {1.0f, dm, 1.0f, 0.0f, below_min, -dm, 2.0f};
    for (bool ftz : {false, true}) {
      const vplkit_test::fp_mode_scope mode(ftz);
      const vplkit::discrete_cdf<float> d(w);
      require_cdf_invariants(d, w);
      require_cdf_sampling_consistent(d);
      for (std::size_t i : {1u, 3u, 4u, 5u}) REQUIRE(d.pmf(i) == 0.0f);
      REQUIRE(d.pmf(0) == 0.25f);
      REQUIRE(d.pmf(6) == 0.5f);
      const vplkit::alias_table<float> a(w);
      require_alias_never_returns_zero(a, w);
      for (std::size_t i : {1u, 3u, 4u, 5u}) REQUIRE(a.pmf(i) == 0.0f);
      for (const auto& bin : a.bins()) REQUIRE(vplkit::flush_denormal(bin.threshold) == bin.threshold);
    }
  }
  SECTION("double: only denormals -> empty") {
    const double dm = std::numeric_limits<double>::denorm_min();
    const std::vector<double> w(1000, dm);
    const vplkit::discrete_cdf<double> d(w);
    REQUIRE(d.empty());
    REQUIRE(d.cdf().back() == 0.0);
    REQUIRE(vplkit::alias_table<double>(w).empty());
  }
}

TEST_CASE("CDF hard case: a positive weight whose probability underflows float",
          "[distribution][hardcase]") {
  // w / total below 2^-126 is flushed to a zero pmf (weights.hpp): its alias threshold n w / total
  // could otherwise survive as a denormal and hand out the index with pmf 0 (1 / pmf = Inf), or
  // read as 0 on a GPU. 2^-150 of the total, and 1e-40 of it (a denormal pmf).
  for (const std::vector<float>& w :
       {std::vector<float>{2.0f, 0x1p-149f * 2.0f}, std::vector<float>{0x1p-100f, 0x1p+50f},
        std::vector<float>{1.0f, 0x1p-126f, 1.0f, 0.0f}, std::vector<float>{1e30f, 1e-10f}}) {
    const std::size_t tiny = w[0] < w[1] ? 0 : 1;
    for (bool ftz : {false, true}) {
      const vplkit_test::fp_mode_scope mode(ftz);
      const vplkit::alias_table<float> a(w);
      REQUIRE(a.pmf(tiny) == 0.0f);
      REQUIRE(a.bins()[tiny].threshold == 0.0f);
      const auto half = a.sample(0.5f);
      REQUIRE(half.index != tiny);
      REQUIRE(half.pmf > 0.0f);
      require_alias_never_returns_zero(a, w);
      // Every u on the RNG's 2^-24 grid, one-u and two-u (u2 = 0 keeps every bucket it can).
      std::size_t bad = 0;
      for (std::uint32_t k = 0; k < (1u << 24); k += ftz ? 13 : 1) {
        const float u = float(k) * 0x1p-24f;
        const auto s1 = a.sample(u), s2 = a.sample(u, 0.0f);
        bad += std::size_t(s1.index == tiny || !(s1.pmf > 0.0f) || s1.pmf != a.pmf(s1.index));
        bad += std::size_t(s2.index == tiny || !(s2.pmf > 0.0f) || s2.pmf != a.pmf(s2.index));
      }
      REQUIRE(bad == 0);
      // discrete_cdf drops the same weight the same way: a bin of width 0, never returned.
      const vplkit::discrete_cdf<float> d(w);
      REQUIRE(d.pmf(tiny) == 0.0f);
      require_cdf_sampling_consistent(d);
      for (std::uint32_t k = 0; k < (1u << 24); k += 7) {
        const auto s = d.sample(float(k) * 0x1p-24f);
        bad += std::size_t(s.index == tiny || !(s.pmf > 0.0f));
      }
      REQUIRE(bad == 0);
    }
  }
}

TEST_CASE("CDF hard case: stored CDF values are 0 or at least 2^-103, every pmf 0 or normal",
          "[distribution][hardcase]") {
  // Weights spread over 76 decades: prefix sums far below 2^-103 of the total are stored as 0, so
  // every difference of two stored values is 0 or normal, and the guide and the indices do not
  // depend on the denormal mode (the case that picked index 100 instead of 3 on a GPU).
  std::vector<float> w;
  std::mt19937 gen(7);
  std::uniform_real_distribution<float> exponent(-38.0f, 38.0f);
  for (int i = 0; i < 5000; ++i) w.push_back(std::pow(10.0f, exponent(gen)));
  w[3] = 1e-38f;
  w[100] = 3e-31f;
  const vplkit::discrete_cdf<float> ieee(w);
  for (std::size_t i = 0; i <= w.size(); ++i) {
    const float c = ieee.cdf()[i];
    REQUIRE((c == 0.0f || c >= vplkit::discrete_cdf_min_value<float>()));
  }
  for (std::size_t i = 0; i < w.size(); ++i) {
    const float p = ieee.pmf(i);
    REQUIRE((p == 0.0f || p >= std::numeric_limits<float>::min()));
  }
  const vplkit_test::fp_mode_scope mode(true);
  const vplkit::discrete_cdf<float> ftz(w);
  REQUIRE(ftz.cdf() == ieee.cdf());
  REQUIRE(ftz.guide() == ieee.guide());
  for (float u : edge_us<float>()) {
    REQUIRE(ftz.sample(u).index == ieee.sample(u).index);
    REQUIRE(ftz.sample(u).pmf == ieee.sample(u).pmf);
  }
  for (std::uint32_t k = 0; k < (1u << 24); k += 101) {
    const float u = float(k) * 0x1p-24f;
    REQUIRE(ftz.sample(u).index == ieee.sample(u).index);
  }
}

TEST_CASE("CDF hard case: finite float weights whose sum passes FLT_MAX",
          "[distribution][hardcase]") {
  // The sums run in double, so every pmf is defined; total() (the sum rounded to float) is +Inf
  // and sum() keeps the double value.
  const std::vector<float> w = {3e38f, 0.0f, 3e38f, 1.0f, std::numeric_limits<float>::max()};
  const double sum = 6e38 + 1.0 + double(std::numeric_limits<float>::max());
  const vplkit::discrete_cdf<float> d(w);
  REQUIRE(std::isinf(d.total()));
  REQUIRE(d.sum() == Approx(double(3e38f) * 2.0 + double(std::numeric_limits<float>::max())));
  REQUIRE_FALSE(d.empty());
  require_cdf_invariants(d, w);
  require_cdf_sampling_consistent(d);
  REQUIRE(double(d.pmf(0)) == Approx(double(3e38f) / sum).epsilon(1e-6));
  REQUIRE(double(d.pmf(4)) == Approx(double(std::numeric_limits<float>::max()) / sum).epsilon(1e-6));
  const vplkit::alias_table<float> a(w);
  REQUIRE(std::isinf(a.total()));
  REQUIRE(a.sum() == d.sum());
  REQUIRE(a.pmf(3) == 0.0f);  // 1 / 9.4e38 = 1.1e-39: below the smallest normal float
  require_alias_never_returns_zero(a, w);
  const std::vector<double> p = realised_alias_pmf(a);
  for (std::size_t i = 0; i < w.size(); ++i) REQUIRE(p[i] == Approx(double(w[i]) / sum).margin(1e-7));
  // The exact case of the report: two weights of 3e38.
  const vplkit::alias_table<float> two(std::vector<float>{3e38f, 3e38f});
  REQUIRE(two.pmf(0) == 0.5f);
  REQUIRE(two.pmf(1) == 0.5f);
  REQUIRE(two.sample(0.75f).pmf == 0.5f);
  // The roulette keeps the ratio of the double sums (its float totals are both +Inf here).
  const vplkit::discrete_cdf<float> big(std::vector<float>{3e38f, 3e38f, 3e38f});
  const vplkit::face_roulette<float> r(d, big);
  REQUIRE(double(r.front_probability()) == Approx(d.sum() / (d.sum() + big.sum())).epsilon(1e-6));
  REQUIRE(double(r.back_probability()) == Approx(big.sum() / (d.sum() + big.sum())).epsilon(1e-6));
  for (float u : edge_us<float>()) {
    const auto f = r.sample(u);
    REQUIRE(std::isfinite(f.pmf));
    REQUIRE(f.pmf > 0.0f);
    REQUIRE(f.pmf == r.pmf(f.face, f.index));
  }
  const vplkit::discrete_cdf<float> small(std::vector<float>{1.0f, 2.0f});
  REQUIRE(vplkit::face_roulette<float>(d, small).front_probability() == 1.0f);
  // 3 / 9.4e38 = 3.2e-39 is below the smallest normal float: the small face's share counts as 0.
  REQUIRE(vplkit::face_roulette<float>(small, d).front_probability() == 0.0f);
}

TEST_CASE("CDF hard case: NaN, Inf and negative weights", "[distribution][hardcase]") {
  using Catch::Matchers::Contains;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  struct bad_case {
    std::size_t index;
    float value;
    const char* word;
  };
  for (const bad_case& c : {bad_case{0, nan, "NaN"}, bad_case{5, inf, "infinite"},
                            bad_case{9, -inf, "infinite"}, bad_case{3, -2.5f, "negative"},
                            bad_case{7, -std::numeric_limits<float>::min(), "negative"}}) {
    std::vector<float> w(10, 1.0f);
    w[c.index] = c.value;
    if (c.index + 1 < w.size()) w[c.index + 1] = -1.0f;  // a later bad weight is not reported
    const std::string where = "weight[" + std::to_string(c.index) + "]";
    REQUIRE_THROWS_WITH(vplkit::discrete_cdf<float>(w),
                        Contains("discrete_cdf") && Contains(where) && Contains(c.word));
    REQUIRE_THROWS_WITH(vplkit::alias_table<float>(w),
                        Contains("alias_table") && Contains(where) && Contains(c.word));
    const std::vector<double> wd(w.begin(), w.end());
    REQUIRE_THROWS_WITH(vplkit::discrete_cdf<double>(wd), Contains(where) && Contains(c.word));
    REQUIRE_THROWS_WITH(vplkit::alias_table<double>(wd), Contains(where) && Contains(c.word));
  }
  // A negative denormal is a zero weight, not a negative one (denormals-are-zero reads it as -0).
  {
    const std::vector<float> w = {1.0f, -std::numeric_limits<float>::denorm_min(), 2.0f};
    REQUIRE(vplkit::discrete_cdf<float>(w).pmf(1) == 0.0f);
    REQUIRE(vplkit::alias_table<float>(w).pmf(1) == 0.0f);
    REQUIRE(vplkit::discrete_cdf<float>::sanitized(w).zeroed == 0);
  }
  // The value itself is in the message.
  REQUIRE_THROWS_WITH(vplkit::discrete_cdf<float>(std::vector<float>{1.0f, -2.5f}),
                      Contains("-2.5"));
  // sanitized() zeroes and counts them instead.
  const std::vector<float> w = {nan, 1.0f, -1.0f, inf, 2.0f, -inf, 0.0f, -0.0f};
  const auto s = vplkit::discrete_cdf<float>::sanitized(w);
  REQUIRE(s.zeroed == 4);
  REQUIRE(s.distribution.pmf(1) == Approx(1.0 / 3.0));
  REQUIRE(s.distribution.pmf(4) == Approx(2.0 / 3.0));
  for (std::size_t i : {0u, 2u, 3u, 5u, 6u, 7u}) REQUIRE(s.distribution.pmf(i) == 0.0f);
  require_cdf_sampling_consistent(s.distribution);
  const auto t = vplkit::alias_table<float>::sanitized(w.data(), w.size());
  REQUIRE(t.zeroed == 4);
  require_alias_never_returns_zero(t.distribution, std::vector<float>{0, 1, 0, 0, 2, 0, 0, 0});
  const std::vector<double> wd(w.begin(), w.end());
  REQUIRE(vplkit::discrete_cdf<double>::sanitized(wd).zeroed == 4);
  REQUIRE(vplkit::alias_table<double>::sanitized(wd).zeroed == 4);
}

TEST_CASE("CDF hard case: all-zero weights give an empty distribution",
          "[distribution][hardcase]") {
  for (std::size_t n : {0u, 1u, 7u, 100000u}) {
    const std::vector<float> w(n, 0.0f);
    const vplkit::discrete_cdf<float> d(w);
    REQUIRE(d.empty());
    REQUIRE(d.size() == n);
    REQUIRE(d.total() == 0.0f);
    REQUIRE(d.cdf().size() == n + 1);
    REQUIRE(d.cdf().back() == 0.0f);  // the GPU-side "empty" marker
    const vplkit::alias_table<float> a(w);
    REQUIRE(a.empty());
    REQUIRE(a.size() == n);
    for (std::size_t i = 0; i < n; i += 997) {
      REQUIRE(d.pmf(i) == 0.0f);
      REQUIRE(a.pmf(i) == 0.0f);
    }
    for (float u : edge_us<float>()) {
      REQUIRE(d.sample(u).index == 0);
      REQUIRE(d.sample(u).pmf == 0.0f);
      REQUIRE(d.sample_binary_search(u).pmf == 0.0f);
      REQUIRE(a.sample(u).index == 0);
      REQUIRE(a.sample(u).pmf == 0.0f);
      REQUIRE(a.sample(u, u).pmf == 0.0f);
    }
    const auto s = vplkit::discrete_cdf<float>::sanitized(std::vector<float>(n, -1.0f));
    REQUIRE(s.distribution.empty());
    REQUIRE(s.zeroed == n);
  }
  const vplkit::discrete_cdf<double> dd(std::vector<double>(5, 0.0));
  REQUIRE(dd.empty());
  REQUIRE(dd.sample(0.5).pmf == 0.0);
  REQUIRE(vplkit::alias_table<double>(std::vector<double>(5, 0.0)).sample(0.5).pmf == 0.0);
}

TEST_CASE("face roulette hard case: v_F + v_B = 0", "[distribution][hardcase]") {
  const vplkit::discrete_cdf<float> zero(std::vector<float>(16, 0.0f));
  for (const auto& r : {vplkit::face_roulette<float>(zero, zero), vplkit::face_roulette<float>(),
                        vplkit::face_roulette<float>(zero, vplkit::discrete_cdf<float>())}) {
    REQUIRE(r.empty());
    REQUIRE(r.front_probability() == 0.0f);
    REQUIRE(r.back_probability() == 0.0f);
    for (float u : edge_us<float>()) {
      const auto s = r.sample(u);
      REQUIRE(s.pmf == 0.0f);
      REQUIRE(s.index == 0);
      REQUIRE(s.face == 0);
    }
    for (std::size_t i = 0; i < 16; ++i) {
      REQUIRE(r.pmf(0, i) == 0.0f);
      REQUIRE(r.pmf(1, i) == 0.0f);
    }
  }
}

TEST_CASE("face roulette hard case: one face empty", "[distribution][hardcase]") {
  const std::vector<float> w = {0.0f, 1.0f, 0.0f, 3.0f, 0.0f};
  const vplkit::discrete_cdf<float> full(w), zero(std::vector<float>(5, 0.0f));
  const vplkit::face_roulette<float> front_only(full, zero), back_only(zero, full),
      back_default(vplkit::discrete_cdf<float>(), full);
  REQUIRE(front_only.front_probability() == 1.0f);
  REQUIRE(front_only.back_probability() == 0.0f);
  REQUIRE(back_only.front_probability() == 0.0f);
  REQUIRE(back_only.back_probability() == 1.0f);
  std::vector<float> us = edge_us<float>();
  for (int k = 0; k <= 1000; ++k) us.push_back(float(k) / 1000.0f);
  for (float u : us) {
    const auto f = front_only.sample(u);
    REQUIRE(f.face == 0);
    REQUIRE(f.index == full.sample(u).index);  // u passes through unchanged
    REQUIRE(f.pmf == full.sample(u).pmf);
    for (const auto* r : {&back_only, &back_default}) {
      const auto b = r->sample(u);
      REQUIRE(b.face == 1);
      REQUIRE(b.index == full.sample(u).index);
      REQUIRE(b.pmf == full.sample(u).pmf);
    }
  }
  for (std::size_t i = 0; i < 5; ++i) {
    REQUIRE(front_only.pmf(0, i) == full.pmf(i));
    REQUIRE(front_only.pmf(1, i) == 0.0f);
    REQUIRE(back_only.pmf(1, i) == full.pmf(i));
    REQUIRE(back_only.pmf(0, i) == 0.0f);
  }
  // A face whose share is below float resolution is never chosen and reports pmf 0.
  const vplkit::face_roulette<float> tiny(full, vplkit::discrete_cdf<float>(std::vector<float>{1e-30f}));
  REQUIRE(tiny.back_probability() == 0.0f);
  for (float u : us) REQUIRE(tiny.sample(u).face == 0);
  REQUIRE(tiny.pmf(1, 0) == 0.0f);
}
