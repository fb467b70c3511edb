// SPDX-License-Identifier: MIT
// vplkit::share_tree<float>: the probability of every draw is the pmf it reports (exact
// enumeration of the paths, and chi-square of the draws), pmf(sample) == pmf(index) bit for bit,
// zero weights never drawn, every positive weight drawable (the share clamps), the exact integer
// share against a double reference, and the hard cases (n = 0, 1, all zero, NaN / Inf / negative,
// denormals, the same arrays under MXCSR FTZ|DAZ, float overflow).
#include <fp_mode.hpp>

#include <vplkit/core/error.hpp>
#include <vplkit/distribution/share_tree.hpp>
#include <vplkit/sampling/rng.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

namespace {

using vplkit::share_tree;

// The exact probability of leaf i under independent uniform 24-bit numbers, in double.
double path_probability(const share_tree<float>& t, std::size_t i) {
  double p = 1.0;
  for (std::size_t k = t.leaf_count() + i; k > 1; k /= 2) {
    const double share = double(t.shares()[k / 2]) / 16777216.0;
    p *= (k % 2 == 0) ? share : 1.0 - share;
  }
  return p;
}

// The level numbers that lead to leaf i: 0 at a left turn, q at a right turn (the smallest).
std::vector<std::uint32_t> path_numbers(const share_tree<float>& t, std::size_t i) {
  std::vector<std::uint32_t> path;
  for (std::size_t m = t.leaf_count() + i; m > 1; m /= 2) path.push_back((m % 2 == 0) ? 0u : t.shares()[m / 2]);
  std::reverse(path.begin(), path.end());
  return path;
}

std::uint32_t bits_of(float f) {
  std::uint32_t b;
  std::memcpy(&b, &f, 4);
  return b;
}

}  // namespace

TEST_CASE("share_tree_share is ceil(left / fl(left + right) 2^24), clamped", "[share_tree]") {
  std::mt19937 g(3);
  std::uniform_real_distribution<double> e(-40.0, 40.0);
  // q is the smallest integer with q s >= l 2^24, clamped to [1, 2^24 - 1]. In long double (64-bit
  // significand) q s (25 x 24 bits) and l 2^24 are exact, so both comparisons below are exact.
  for (int t = 0; t < 200000; ++t) {
    const float l = float(std::exp2(e(g))), r = float(std::exp2(e(g) * (t % 2 == 0 ? 1.0 : 0.01)));
    const long double s = (long double)(l + r), l24 = (long double)l * 16777216.0L;
    const std::uint32_t q = vplkit::share_tree_share(l, r);
    INFO("l = " << l << ", r = " << r << ", q = " << q);
    REQUIRE(q >= 1u);
    REQUIRE(q <= 16777215u);
    if (q < 16777215u) REQUIRE((long double)q * s >= l24);
    if (q > 1u) REQUIRE((long double)(q - 1u) * s < l24);
  }
  CHECK(vplkit::share_tree_share(0.0f, 1.0f) == 0u);
  CHECK(vplkit::share_tree_share(1.0f, 0.0f) == 16777216u);
  CHECK(vplkit::share_tree_share(1.0f, 1.0f) == 8388608u);        // exactly 1/2: no rounding up
  CHECK(vplkit::share_tree_share(1.0f, 2.0f) == 5592406u);        // ceil(2^24 / 3)
  CHECK(vplkit::share_tree_share(1e-38f, 3e38f) == 1u);           // tiny beside huge: kept drawable
  CHECK(vplkit::share_tree_share(3e38f, 1e-38f) == 16777215u);    // and its mirror
  CHECK(vplkit::share_tree_share(1.0f, 1e-30f) == 16777215u);     // fl(1 + 1e-30) = 1: clamped
}

TEST_CASE("share_tree: pmf is the exact probability of its draws, on every path", "[share_tree]") {
  for (const std::vector<float>& w :
       {std::vector<float>{0.0f, 1e-30f, 3.0f, 0.5f, 0.0f, 2e-7f, 1.0f}, std::vector<float>{2e-38f, 3e37f},
        std::vector<float>{3e37f, 2e-38f}, std::vector<float>{1.0f, 1.0f, 1.0f}, std::vector<float>{5.0f}}) {
    const share_tree<float> t(w);
    double total = 0.0;
    for (std::size_t i = 0; i < t.leaf_count(); ++i) {
      const double p = path_probability(t, i);
      total += p;
      const bool positive = i < w.size() && w[i] > 0.0f;
      INFO("n = " << w.size() << ", i = " << i);
      CHECK((p > 0.0) == positive);
      CHECK((t.pmf(i) > 0.0f) == positive);
      if (positive) {
        const std::vector<std::uint32_t> path = path_numbers(t, i);
        std::size_t level = 0;
        const auto s = t.sample([&] { return path[level++]; });
        CHECK(level == t.depth());
        CHECK(s.index == i);
        CHECK(bits_of(s.pmf) == bits_of(t.pmf(i)));
        CHECK(std::abs(double(s.pmf) - p) <= double(t.depth() + 1) * 0x1p-24 * p);
        // One below q at a right turn goes left instead: the path's edges are where they should be.
      }
    }
    CHECK(std::abs(total - 1.0) < 1e-12);
  }
}

TEST_CASE("share_tree: chi-square of 10^6 draws against pmf", "[share_tree][statistical]") {
  const std::size_t n = 1000;  // not a power of two: 24 padding leaves
  std::mt19937 g(11);
  std::lognormal_distribution<float> ln(0.0f, 1.5f);
  std::vector<float> w(n);
  for (std::size_t i = 0; i < n; ++i) w[i] = i % 7 == 3 ? 0.0f : ln(g);
  const share_tree<float> t(w);
  std::vector<double> count(n, 0.0);
  vplkit::counter_rng rng = vplkit::make_counter_rng(5u, 9u);
  const int draws = 1000000;
  for (int d = 0; d < draws; ++d) {
    const auto s = t.sample([&] { return vplkit::rng_next_u32(rng) >> 8u; });
    REQUIRE(s.index < n);
    REQUIRE(w[s.index] > 0.0f);                              // zero weights never drawn
    REQUIRE(bits_of(s.pmf) == bits_of(t.pmf(s.index)));      // pmf(sample) == pmf(index)
    count[s.index] += 1.0;
  }
  CHECK(rng.counter == std::uint32_t(draws) * t.depth());   // depth() numbers per draw, always
  double chi2 = 0.0;
  int dof = -1;
  for (std::size_t i = 0; i < n; ++i) {
    const double e = draws * double(t.pmf(i));
    if (e == 0.0) {
      CHECK(count[i] == 0.0);
      continue;
    }
    chi2 += (count[i] - e) * (count[i] - e) / e;
    ++dof;
    // and the pmf is the weight's share up to the quantisation: each factor f is within 2^-24
    // of the exact ratio (plus the float rounding of the sums), i.e. 2^-24 / f relative.
    double bound = 0.0;
    for (std::size_t k = t.leaf_count() + i; k > 1; k /= 2) {
      const double share = double(t.shares()[k / 2]) / 16777216.0;
      bound += 2.0 * 0x1p-24 / ((k % 2 == 0) ? share : 1.0 - share) + 0x1p-23;
    }
    CHECK(std::abs(double(t.pmf(i)) - double(w[i]) / double(t.total())) <= bound * double(t.pmf(i)));
  }
  // dof ~ 856: mean dof, sd sqrt(2 dof) ~ 41; 6 sd.
  INFO("chi2 = " << chi2 << ", dof = " << dof);
  CHECK(chi2 < dof + 6.0 * std::sqrt(2.0 * dof));
}

TEST_CASE("share_tree: a tiny weight beside huge ones is drawable", "[share_tree]") {
  std::vector<float> w(16, 1e37f);
  w[5] = 1.5e-38f;
  const share_tree<float> t(w);
  CHECK(t.pmf(5) > 0.0f);
  CHECK(t.pmf(5) >= std::numeric_limits<float>::min());
  const std::vector<std::uint32_t> path = path_numbers(t, 5);
  std::size_t level = 0;
  CHECK(t.sample([&] { return path[level++]; }).index == 5u);
}

TEST_CASE("share_tree: hard cases", "[share_tree][hardcases]") {
  const float nan = std::numeric_limits<float>::quiet_NaN(), inf = std::numeric_limits<float>::infinity();
  SECTION("empty: n = 0 and all zero (denormals and -0 included)") {
    for (const share_tree<float>& t : {share_tree<float>(), share_tree<float>(std::vector<float>{}),
                                       share_tree<float>(std::vector<float>{0.0f, -0.0f, 1e-40f, -1e-45f, 0.0f})}) {
      CHECK(t.empty());
      vplkit::counter_rng r{1u, 0u};
      const auto s = t.sample([&] { return vplkit::rng_next_u32(r) >> 8u; });
      CHECK(s.index == 0u);
      CHECK(s.pmf == 0.0f);
      CHECK(r.counter == t.depth());
      CHECK(t.pmf(0) == 0.0f);
    }
  }
  SECTION("n = 1") {
    const share_tree<float> t(std::vector<float>{2.5f});
    CHECK(t.depth() == 0u);
    vplkit::counter_rng r{1u, 0u};
    const auto s = t.sample([&] { return vplkit::rng_next_u32(r) >> 8u; });
    CHECK(s.index == 0u);
    CHECK(s.pmf == 1.0f);
    CHECK(r.counter == 0u);
  }
  SECTION("NaN, Inf, negative throw naming the index; sanitized() zeroes them") {
    for (float bad : {nan, inf, -inf, -1.0f}) {
      std::vector<float> w{1.0f, 2.0f, bad, 3.0f};
      CHECK_THROWS_AS(share_tree<float>(w), vplkit::invalid_input);
      CHECK_THROWS_WITH(share_tree<float>(w), Catch::Contains("weight[2]"));
      const auto s = share_tree<float>::sanitized(w);
      CHECK(s.zeroed == 1u);
      CHECK(s.distribution.pmf(2) == 0.0f);
      CHECK(s.distribution.pmf(3) > 0.0f);
    }
  }
  SECTION("a float sum past FLT_MAX throws") {
    CHECK_THROWS_AS(share_tree<float>(std::vector<float>{3e38f, 3e38f}), vplkit::invalid_input);
  }
  SECTION("an exception leaves the object unchanged") {
    share_tree<float> t(std::vector<float>{1.0f, 3.0f});
    const std::vector<float> w{nan};
    CHECK_THROWS(t.assign(w.data(), w.size()));
    CHECK(t.size() == 2u);
    CHECK(t.pmf(1) == 0.75f);
  }
  SECTION("denormal weights count as 0; the arrays are the same bits under FTZ|DAZ") {
    std::mt19937 g(2);
    std::uniform_real_distribution<float> u(0.0f, 1.0f);
    std::vector<float> w(3000);
    for (std::size_t i = 0; i < w.size(); ++i) w[i] = u(g) * (i % 5 == 0 ? 1e-38f : i % 5 == 1 ? 1e-30f : 1.0f);
    w[7] = std::numeric_limits<float>::denorm_min();
    w[8] = -1e-40f;
    const share_tree<float> ieee(w);
    CHECK(ieee.pmf(7) == 0.0f);
    CHECK(ieee.pmf(8) == 0.0f);
    for (std::size_t i = 0; i < w.size(); ++i) {
      if (w[i] < std::numeric_limits<float>::min()) REQUIRE(ieee.pmf(i) == 0.0f);
      else REQUIRE(ieee.pmf(i) >= std::numeric_limits<float>::min());
    }
#if VPLKIT_TEST_HAS_MXCSR
    vplkit_test::fp_mode_scope ftz(true);
    REQUIRE(vplkit_test::ftz_daz_active());
    const share_tree<float> flushed(w);
    CHECK(flushed.sums() == ieee.sums());
    CHECK(flushed.shares() == ieee.shares());
    for (std::size_t i = 0; i < w.size(); ++i) REQUIRE(bits_of(flushed.pmf(i)) == bits_of(ieee.pmf(i)));
#endif
  }
}
