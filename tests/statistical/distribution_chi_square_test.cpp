// SPDX-License-Identifier: MIT
// Pearson chi-square goodness of fit of every discrete sampler against the distribution it
// claims (w / total computed here in long double, not the sampler's own pmf). Fixed seeds; the
// critical value is at alpha ~ 1e-4 (vplkit_test_support.hpp).
#include <vplkit/distribution/alias_table.hpp>
#include <vplkit/distribution/defensive_mixture.hpp>
#include <vplkit/distribution/discrete_cdf.hpp>
#include <vplkit/distribution/face_roulette.hpp>

#include <vplkit_test_support.hpp>
#include <weight_generators.hpp>

#include <array>
#include <cstdint>
#include <random>
#include <vector>

namespace {

using vplkit_test::exponential_weights;
using vplkit_test::u01;

constexpr std::uint64_t kSamples = 2000000;

template <class T>
std::vector<double> normalised(const std::vector<T>& w) {
  long double total = 0.0L;
  for (T x : w) total += x;
  std::vector<double> p(w.size());
  for (std::size_t i = 0; i < w.size(); ++i) p[i] = double(w[i] / total);
  return p;
}

// Goodness of fit, plus: no sample ever lands on a zero-probability entry.
void require_fit(const std::vector<std::uint64_t>& counts, const std::vector<double>& p) {
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p[i] == 0.0) REQUIRE(counts[i] == 0);
  }
  int dof = 0;
  const double stat = vplkit_test::chi_square(counts, p, kSamples, &dof);
  INFO("chi2 = " << stat << " with " << dof << " dof, critical " << vplkit_test::chi_square_critical(dof));
  REQUIRE(dof > 10);
  REQUIRE(stat < vplkit_test::chi_square_critical(dof));
}

// Per-index counts of kSamples draws by two samplers fed the same (u1, u2) pairs of one stream.
template <class T, class SampleA, class SampleB>
std::array<std::vector<std::uint64_t>, 2> paired_counts(std::size_t n, unsigned seed, SampleA a, SampleB b) {
  std::mt19937 rng(seed);
  std::array<std::vector<std::uint64_t>, 2> counts = {std::vector<std::uint64_t>(n, 0),
                                                      std::vector<std::uint64_t>(n, 0)};
  for (std::uint64_t k = 0; k < kSamples; ++k) {
    const T u1 = u01<T>(rng), u2 = u01<T>(rng);
    ++counts[0][a(u1, u2)];
    ++counts[1][b(u1, u2)];
  }
  return counts;
}

}  // namespace

TEMPLATE_TEST_CASE("chi-square: discrete_cdf", "[distribution][statistical]", float, double) {
  using T = TestType;
  const std::vector<T> w = exponential_weights<T>(300, 1u, 0.3);
  const vplkit::discrete_cdf<T> d(w);
  const auto [guided, binary] = paired_counts<T>(
      w.size(), 101u, [&](T u, T) { return d.sample(u).index; }, [&](T u, T) { return d.sample_binary_search(u).index; });
  require_fit(guided, normalised(w));
  REQUIRE(binary == guided);
}

TEMPLATE_TEST_CASE("chi-square: alias_table with two u and with one u", "[distribution][statistical]",
                   float, double) {
  using T = TestType;
  const std::vector<T> w = exponential_weights<T>(300, 2u, 0.3);
  const vplkit::alias_table<T> a(w);
  // n = 300: one u leaves 15+ bits for the fraction.
  const auto [two, one] = paired_counts<T>(
      w.size(), 202u, [&](T u1, T u2) { return a.sample(u1, u2).index; }, [&](T u1, T) { return a.sample(u1).index; });
  require_fit(two, normalised(w));
  require_fit(one, normalised(w));
}

TEMPLATE_TEST_CASE("chi-square: defensive_mixture", "[distribution][statistical]", float, double) {
  using T = TestType;
  const std::size_t n = 300;
  std::vector<T> learned = exponential_weights<T>(n, 3u, 0.5), valid(n);
  for (std::size_t i = 0; i < n; ++i) valid[i] = (i % 7 == 3) ? T(0) : T(1);
  for (std::size_t i = 0; i < n; ++i) learned[i] = valid[i] > T(0) ? learned[i] : T(0);
  const T eps = T(0.2);
  const vplkit::defensive_mixture<T> m(vplkit::discrete_cdf<T>(learned),
                                       vplkit::discrete_cdf<T>(valid), eps);
  const std::vector<double> pl = normalised(learned), pv = normalised(valid);
  std::vector<double> p(n);
  for (std::size_t i = 0; i < n; ++i) p[i] = (1.0 - double(eps)) * pl[i] + double(eps) * pv[i];
  std::mt19937 rng(303);
  std::vector<std::uint64_t> counts(n, 0);
  for (std::uint64_t k = 0; k < kSamples; ++k) ++counts[m.sample(u01<T>(rng)).index];
  require_fit(counts, p);
}

TEMPLATE_TEST_CASE("chi-square: face_roulette against one CDF over both faces",
                   "[distribution][statistical]", float, double) {
  using T = TestType;
  const std::size_t n = 200;
  const std::vector<T> wf = exponential_weights<T>(n, 4u, 0.3);
  std::vector<T> wb = exponential_weights<T>(n, 5u, 0.3);
  for (auto& x : wb) x *= T(0.4);  // unequal faces: b_F ~ 0.7
  const vplkit::face_roulette<T> r{vplkit::discrete_cdf<T>(wf), vplkit::discrete_cdf<T>(wb)};
  std::vector<T> both(wf);
  both.insert(both.end(), wb.begin(), wb.end());
  const vplkit::discrete_cdf<T> concatenated(both);
  std::mt19937 rng(404);
  std::vector<std::uint64_t> counts(2 * n, 0), counts_concat(2 * n, 0);
  for (std::uint64_t k = 0; k < kSamples; ++k) {
    const T u = u01<T>(rng);
    const auto s = r.sample(u);
    ++counts[s.face == 0 ? s.index : n + s.index];
    ++counts_concat[concatenated.sample(u01<T>(rng)).index];
  }
  require_fit(counts, normalised(both));
  require_fit(counts_concat, normalised(both));
}
