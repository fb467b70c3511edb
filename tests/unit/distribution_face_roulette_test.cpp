// SPDX-License-Identifier: MIT
#include <vplkit/distribution/face_roulette.hpp>

#include <weight_generators.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace {

using vplkit_test::exponential_weights;
using vplkit_test::u01;

template <class T>
std::vector<T> concat(const std::vector<T>& a, const std::vector<T>& b) {
  std::vector<T> c(a);
  c.insert(c.end(), b.begin(), b.end());
  return c;
}

}  // namespace

TEMPLATE_TEST_CASE("face_roulette: b_F = v_F / (v_F + v_B)", "[distribution]", float, double) {
  using T = TestType;
  const vplkit::face_roulette<T> r(vplkit::discrete_cdf<T>(std::vector<T>{1, 2}),
                                   vplkit::discrete_cdf<T>(std::vector<T>{3, 0, 2}));
  REQUIRE(r.front_probability() == T(0.375));
  REQUIRE(r.back_probability() == T(0.625));
  REQUIRE(r.face_probability(0) == T(0.375));
  REQUIRE(r.face_probability(1) == T(0.625));
  REQUIRE(r.face_probability(2) == T(0));
  REQUIRE_FALSE(r.empty());
  REQUIRE(r.pmf(0, 1) == Approx(0.25).epsilon(1e-6));  // 0.375 * 2/3 in T
  REQUIRE(r.pmf(1, 0) == T(0.375));
  REQUIRE(r.pmf(1, 1) == T(0));
  REQUIRE(r.pmf(1, 3) == T(0));
  REQUIRE(r.pmf(2, 0) == T(0));
  REQUIRE(r.pmf(-1, 0) == T(0));
  REQUIRE(&r.face(0) == &r.front());
  REQUIRE(&r.face(1) == &r.back());
}

// docs/math.md section 3: the roulette and one CDF over both faces' weights give the same pmf.
TEMPLATE_TEST_CASE("face_roulette: same pmf as one CDF over the concatenated weights",
                   "[distribution]", float, double) {
  using T = TestType;
  const double rel = std::is_same<T, float>::value ? 1e-6 : 1e-13;
  for (unsigned seed : {1u, 2u, 3u}) {
    const std::size_t n = 4096;
    const std::vector<T> wf = exponential_weights<T>(n, seed, 0.3);
    const std::vector<T> wb = exponential_weights<T>(n, seed + 100u, 0.6);
    const vplkit::face_roulette<T> r{vplkit::discrete_cdf<T>(wf), vplkit::discrete_cdf<T>(wb)};
    const vplkit::discrete_cdf<T> all(concat(wf, wb));
    double total = 0.0;
    for (T x : concat(wf, wb)) total += double(x);
    for (std::size_t i = 0; i < 2 * n; ++i) {
      const int face = i < n ? 0 : 1;
      const std::size_t idx = i < n ? i : i - n;
      const double p = double(r.pmf(face, idx));
      const double q = double(all.pmf(i));
      const double exact = double(i < n ? wf[idx] : wb[idx]) / total;
      // Both are float-rounded estimates of w / total: compare each with the exact value, with
      // an absolute slack of a few ulps of the CDF (the stored CDFs are differenced).
      const double abs_tol = std::is_same<T, float>::value ? 2e-7 : 1e-15;
      REQUIRE(std::abs(p - exact) <= rel * exact + abs_tol);
      REQUIRE(std::abs(p - q) <= 2.0 * (rel * exact + abs_tol));
      if (exact == 0.0) REQUIRE(p == 0.0);
    }
  }
}

// Same u -> same (face, index) as the concatenated CDF, except where the rescale of u rounds
// across a bin edge; and pmf(sample) == sample.pmf.
TEMPLATE_TEST_CASE("face_roulette: samples agree with the concatenated CDF", "[distribution]",
                   float, double) {
  using T = TestType;
  const std::size_t n = 1000;
  const std::vector<T> wf = exponential_weights<T>(n, 10u, 0.2);
  const std::vector<T> wb = exponential_weights<T>(n, 11u, 0.2);
  const vplkit::face_roulette<T> r{vplkit::discrete_cdf<T>(wf), vplkit::discrete_cdf<T>(wb)};
  const vplkit::discrete_cdf<T> all(concat(wf, wb));
  std::mt19937 rng(12);
  const int N = 1000000;
  int agree = 0;
  for (int k = 0; k < N; ++k) {
    const T u = u01<T>(rng);
    const auto s = r.sample(u);
    REQUIRE(s.pmf == r.pmf(s.face, s.index));
    REQUIRE(s.pmf > T(0));
    REQUIRE((s.face == 0 ? wf[s.index] : wb[s.index]) > T(0));
    const std::size_t flat = s.face == 0 ? s.index : n + s.index;
    agree += flat == all.sample(u).index ? 1 : 0;
  }
  // Disagreements need u within a few ulps of a bin edge: 2000 edges * ~2^-22 each.
  REQUIRE(N - agree <= 20);
}

TEMPLATE_TEST_CASE("face_roulette: u at and around b_F, 0 and 1", "[distribution]", float,
                   double) {
  using T = TestType;
  const vplkit::face_roulette<T> r(vplkit::discrete_cdf<T>(std::vector<T>{0, 1, 0}),
                                   vplkit::discrete_cdf<T>(std::vector<T>{0, 0, 3, 0}));
  const T b = r.front_probability();
  REQUIRE(b == T(0.25));
  const T below1 = std::nextafter(T(1), T(0));
  for (T u : {T(0), std::nextafter(b, T(0)), T(-1), std::numeric_limits<T>::quiet_NaN()}) {
    const auto s = r.sample(u);
    REQUIRE(s.face == 0);
    REQUIRE(s.index == 1);
    REQUIRE(s.pmf == T(0.25));
  }
  for (T u : {b, std::nextafter(b, T(1)), T(0.5), below1, T(1),
              std::numeric_limits<T>::infinity()}) {
    const auto s = r.sample(u);
    REQUIRE(s.face == 1);
    REQUIRE(s.index == 2);
    REQUIRE(s.pmf == T(0.75));
  }
}

TEMPLATE_TEST_CASE("face_roulette: a tiny face share never produces NaN or Inf, one below FLT_MIN counts as 0",
                   "[distribution]", float, double) {
  using T = TestType;
  const T lo = std::numeric_limits<T>::min();
  // b_F = 2^-4 min() / (2^-4 min() + 1): a share just above the smallest normal T; its reciprocal
  // is finite.
  const T small = std::ldexp(lo, 100);
  const T big = std::ldexp(T(1), 96);
  const vplkit::face_roulette<T> r{vplkit::discrete_cdf<T>(std::vector<T>{small, 0}),
                                   vplkit::discrete_cdf<T>(std::vector<T>{0, big})};
  REQUIRE(r.front_probability() >= lo);
  REQUIRE(std::isfinite(r.front_scale()));
  for (T u : {T(0), std::numeric_limits<T>::denorm_min(), lo, std::nextafter(r.front_probability(), T(1)),
              T(0.5), T(1)}) {
    const auto s = r.sample(u);
    REQUIRE(std::isfinite(s.pmf));
    REQUIRE(s.pmf > T(0));
    REQUIRE(s.pmf == r.pmf(s.face, s.index));
  }
  REQUIRE(r.sample(T(0)).face == 0);
  REQUIRE(r.sample(T(0)).index == 0);
  REQUIRE(r.sample(T(0.5)).face == 1);
  // A share below the smallest normal T counts as 0 (the normal-range contract): the front face
  // is never picked and reports pmf 0, on every device.
  const vplkit::face_roulette<T> z{vplkit::discrete_cdf<T>(std::vector<T>{small, 0}),
                                   vplkit::discrete_cdf<T>(std::vector<T>{0, std::ldexp(T(1), 120)})};
  REQUIRE(z.front_probability() == T(0));
  REQUIRE(z.back_probability() == T(1));
  for (T u : {T(0), lo, T(0.5), T(1)}) REQUIRE(z.sample(u).face == 1);
  REQUIRE(z.pmf(0, 0) == T(0));
  // A denormal weight is a zero weight: an empty face.
  const vplkit::face_roulette<T> d{vplkit::discrete_cdf<T>(std::vector<T>{std::numeric_limits<T>::denorm_min(), 0}),
                                   vplkit::discrete_cdf<T>(std::vector<T>{0, 1})};
  REQUIRE(d.front().empty());
  REQUIRE(d.front_probability() == T(0));
  REQUIRE(d.sample(T(0)).face == 1);
}
