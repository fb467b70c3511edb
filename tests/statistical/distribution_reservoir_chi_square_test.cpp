// SPDX-License-Identifier: MIT
// The streaming weighted reservoir (distribution/weighted_reservoir.hpp) against its closed form:
// after a stream of weights w_1..w_n the kept item is i with probability w_i / sum w (Pearson
// chi-square, fixed seeds, critical value at alpha ~ 1e-4 as in distribution_chi_square_test), with
// zero, negative, NaN and infinite weights in the stream (never kept, and they change no
// probability); keep k: two reservoirs fed the same stream keep independent items, each pair (i, j)
// with probability p_i p_j.
#include <vplkit/distribution/weighted_reservoir.hpp>
#include <vplkit/sampling/rng.hpp>

#include <vplkit_test_support.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace {

using vplkit::counter_rng;
using vplkit::make_counter_rng;
using vplkit::rng_next_unit;

// A stream with every kind of weight: ordinary ones spanning 4 decades, zeros, and the unusable.
template <class T>
std::vector<T> stream_weights() {
  const T nan = std::numeric_limits<T>::quiet_NaN(), inf = std::numeric_limits<T>::infinity();
  std::vector<T> w;
  for (int i = 0; i < 40; ++i) w.push_back(T(std::pow(10.0, -2.0 + 4.0 * double((i * 7) % 40) / 39.0)));
  w[3] = T(0);
  w[11] = T(-1);
  w[17] = nan;
  w[23] = inf;
  w[31] = -inf;
  w[0] = T(0);  // the stream starts with an item that can never be kept
  return w;
}

template <class T>
std::vector<double> closed_form(const std::vector<T>& w) {
  long double total = 0.0L;
  for (T x : w)
    if (vplkit::reservoir_weight_usable(x)) total += x;
  std::vector<double> p(w.size(), 0.0);
  for (std::size_t i = 0; i < w.size(); ++i)
    if (vplkit::reservoir_weight_usable(w[i])) p[i] = double(w[i] / total);
  return p;
}

void require_fit(const std::vector<std::uint64_t>& counts, const std::vector<double>& p, std::uint64_t n) {
  for (std::size_t i = 0; i < p.size(); ++i)
    if (p[i] == 0.0) REQUIRE(counts[i] == 0);
  int dof = 0;
  const double stat = vplkit_test::chi_square(counts, p, n, &dof);
  INFO("chi2 = " << stat << " with " << dof << " dof, critical " << vplkit_test::chi_square_critical(dof));
  REQUIRE(dof > 10);
  REQUIRE(stat < vplkit_test::chi_square_critical(dof));
}

}  // namespace

TEMPLATE_TEST_CASE("weighted reservoir: keeps item i with probability w_i / sum w", "[distribution][reservoir]",
                   float, double) {
  using T = TestType;
  const std::vector<T> w = stream_weights<T>();
  const std::vector<double> p = closed_form(w);
  const std::uint64_t n = 400000;
  std::vector<std::uint64_t> counts(w.size(), 0);
  for (std::uint64_t k = 0; k < n; ++k) {
    counter_rng rng = make_counter_rng(0x5e11u, std::uint32_t(k));
    vplkit::weighted_reservoir<T> r;
    for (std::size_t i = 0; i < w.size(); ++i) vplkit::reservoir_update(r, std::uint32_t(i), w[i], rng_next_unit<T>(rng));
    REQUIRE_FALSE(vplkit::reservoir_empty_of(r));
    REQUIRE(r.weight == w[r.index]);
    ++counts[r.index];
  }
  require_fit(counts, p, n);
}

TEMPLATE_TEST_CASE("weighted reservoir: keep k keeps independent items", "[distribution][reservoir]", float, double) {
  using T = TestType;
  // 12 items: 144 pair cells, each expected > 5 at the sample size below.
  std::vector<T> w;
  for (int i = 0; i < 12; ++i) w.push_back(T(1 + (i * 5) % 12));
  const std::vector<double> p = closed_form(w);
  std::vector<double> pair(w.size() * w.size());
  for (std::size_t i = 0; i < w.size(); ++i)
    for (std::size_t j = 0; j < w.size(); ++j) pair[i * w.size() + j] = p[i] * p[j];
  const std::uint64_t n = 400000;
  std::vector<std::uint64_t> counts(pair.size(), 0), first(w.size(), 0), second(w.size(), 0);
  for (std::uint64_t k = 0; k < n; ++k) {
    counter_rng rng = make_counter_rng(0x5e12u, std::uint32_t(k));
    vplkit::weighted_reservoir<T> a, b;
    for (std::size_t i = 0; i < w.size(); ++i) {  // one item to both, each with its own u
      vplkit::reservoir_update(a, std::uint32_t(i), w[i], rng_next_unit<T>(rng));
      vplkit::reservoir_update(b, std::uint32_t(i), w[i], rng_next_unit<T>(rng));
    }
    REQUIRE(a.weight_sum == b.weight_sum);
    ++counts[a.index * w.size() + b.index];
    ++first[a.index];
    ++second[b.index];
  }
  require_fit(first, p, n);
  require_fit(second, p, n);
  require_fit(counts, pair, n);
}
