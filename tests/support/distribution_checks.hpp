// SPDX-License-Identifier: MIT
#pragma once
// Checks the distribution tests share (not part of the library; needs Catch2): the invariants
// every discrete_cdf must keep, and the pmf an alias_table really samples.
#include <vplkit/distribution/alias_table.hpp>
#include <vplkit/distribution/discrete_cdf.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

namespace vplkit_test {

template <class T>
bool finite_nonneg(T x) {
  return std::isfinite(x) && x >= T(0);
}

// A distribution of pmf.size() entries (discrete_cdf, alias_table): its size and total, not
// empty, pmf(i) == T(pmf[i]) (rel = 0) or within `rel` relative, and 0 one past the end.
template <class D, class T>
void require_pmf(const D& d, T total, const std::vector<double>& pmf, double rel) {
  REQUIRE(d.size() == pmf.size());
  REQUIRE(d.total() == total);
  REQUIRE_FALSE(d.empty());
  for (std::size_t i = 0; i < pmf.size(); ++i) {
    if (rel == 0.0) {
      REQUIRE(d.pmf(i) == T(pmf[i]));
    } else {
      REQUIRE(d.pmf(i) == Approx(pmf[i]).epsilon(rel));
    }
  }
  REQUIRE(d.pmf(pmf.size()) == T(0));
}

// n + 1 finite values from exactly 0 to exactly 1, never decreasing, flat over a zero weight, and
// every pmf finite and non-negative.
template <class T>
void require_cdf_invariants(const vplkit::discrete_cdf<T>& d, const std::vector<T>& w) {
  const auto& c = d.cdf();
  REQUIRE(c.size() == w.size() + 1);
  REQUIRE(c.front() == T(0));
  REQUIRE(c.back() == T(1));
  for (std::size_t i = 0; i < w.size(); ++i) {
    REQUIRE(finite_nonneg(c[i]));
    REQUIRE(c[i] <= c[i + 1]);
    // A weight below the smallest normal T counts as 0 (the normal-range contract, weights.hpp).
    if (!(w[i] >= std::numeric_limits<T>::min())) REQUIRE(c[i] == c[i + 1]);
    // Stored values are 0 or at least discrete_cdf_min_value, every pmf 0 or normal.
    REQUIRE((c[i] == T(0) || c[i] >= vplkit::discrete_cdf_min_value<T>()));
    const T p = d.pmf(i);
    REQUIRE(finite_nonneg(p));
    REQUIRE((p == T(0) || p >= std::numeric_limits<T>::min()));
  }
}

// The probability the table really gives each index: bucket j (probability 1/n) keeps itself
// with probability threshold[j] and hands the rest to alias[j].
template <class T>
std::vector<double> realised_alias_pmf(const vplkit::alias_table<T>& a) {
  const std::size_t n = a.size();
  std::vector<double> p(n, 0.0);
  for (std::size_t j = 0; j < n; ++j) {
    const auto& b = a.bins()[j];
    p[j] += double(b.threshold) / double(n);
    p[b.alias] += (1.0 - double(b.threshold)) / double(n);
  }
  return p;
}

}  // namespace vplkit_test
