// SPDX-License-Identifier: MIT
// defensive_mixture::sample_binary_search: the same index and pmf as the guided sample() for
// every u (the renderer's --cdf-search binary relies on it for bit-identical images).
#include <vplkit/distribution/defensive_mixture.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

namespace {

template <class T>
bool same_bits(T a, T b) {
  return std::memcmp(&a, &b, sizeof(T)) == 0;
}

template <class T>
void check_same(const vplkit::defensive_mixture<T>& m, T u) {
  const auto g = m.sample(u);
  const auto b = m.sample_binary_search(u);
  INFO("u = " << u << ", eps = " << m.eps());
  REQUIRE(b.index == g.index);
  REQUIRE(same_bits(T(b.pmf), T(g.pmf)));
}

}  // namespace

TEMPLATE_TEST_CASE("defensive_mixture: sample_binary_search equals sample for every u", "[distribution]", float,
                   double) {
  using T = TestType;
  std::mt19937 rng(91);
  std::exponential_distribution<double> ex(1.0);
  const std::size_t n = 5000;
  std::vector<T> learned(n), valid(n);
  for (std::size_t i = 0; i < n; ++i) {
    valid[i] = (i % 7 == 3) ? T(0) : T(1);
    // Holes, runs of tiny weights packed below one guide bucket, and ordinary weights.
    learned[i] = (valid[i] > T(0) && i % 4 != 0) ? T(ex(rng)) * (i > 2000 && i < 2600 ? T(1e-6) : T(1)) : T(0);
  }
  const vplkit::discrete_cdf<T> l(learned), f(valid), none;
  const vplkit::discrete_cdf<T> zeros(std::vector<T>(n, T(0)));
  const std::vector<vplkit::defensive_mixture<T>> mixtures = {
      {l, f, T(0)}, {l, f, T(0.05)}, {l, f, T(0.5)}, {l, f, T(1)}, {zeros, f, T(0.1)}, {l, none, T(0.1)}};
  for (const auto& m : mixtures) {
    for (int k = 0; k < 20000; ++k) check_same(m, T(rng() >> 8) * T(0x1p-24));
    // Every CDF edge of the learned component, mapped back through the mixing (and its neighbours).
    for (std::size_t i = 0; i < n; i += 13) {
      const T c = m.learned().cdf()[i];
      const T u = m.effective_eps() + c * (T(1) - m.effective_eps());
      for (T v : {u, std::nextafter(u, T(0)), std::nextafter(u, T(1))}) check_same(m, v);
    }
    const T e = m.effective_eps();
    for (T v : {T(0), e, std::nextafter(e, T(0)), std::nextafter(e, T(1)), std::nextafter(T(1), T(0)), T(1), T(-1),
                std::numeric_limits<T>::quiet_NaN()})
      check_same(m, v);
  }
  const vplkit::defensive_mixture<T> empty(zeros, none, T(0.3));
  CHECK(empty.sample_binary_search(T(0.5)).index == 0);
  CHECK(empty.sample_binary_search(T(0.5)).pmf == T(0));
}
