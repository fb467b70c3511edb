// SPDX-License-Identifier: MIT
#pragma once
// Helpers shared by the test programs (not part of the library).
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <vector>

namespace vplkit_test {

// Pearson chi-square statistic of observed counts against expected probabilities. Bins with
// expected count < 5 are pooled into one bin, as the test requires.
inline double chi_square(const std::vector<std::uint64_t>& counts, const std::vector<double>& probs,
                         std::uint64_t n, int* dof_out) {
  double stat = 0.0, pooled_obs = 0.0, pooled_exp = 0.0;
  int bins = 0;
  for (std::size_t i = 0; i < counts.size(); ++i) {
    const double e = probs[i] * double(n);
    if (e < 5.0) {
      pooled_obs += double(counts[i]);
      pooled_exp += e;
      continue;
    }
    stat += (double(counts[i]) - e) * (double(counts[i]) - e) / e;
    ++bins;
  }
  if (pooled_exp >= 5.0) {
    stat += (pooled_obs - pooled_exp) * (pooled_obs - pooled_exp) / pooled_exp;
    ++bins;
  }
  *dof_out = bins - 1;
  return stat;
}

// Upper critical value of chi-square with `dof` degrees of freedom at significance ~1e-4
// (Wilson-Hilferty approximation, z = 3.719). Fixed seeds make the tests deterministic; the
// small alpha keeps a correct sampler from failing after an innocent seed change.
inline double chi_square_critical(int dof) {
  const double k = double(dof), z = 3.719;
  const double a = 2.0 / (9.0 * k);
  const double c = 1.0 - a + z * std::sqrt(a);
  return k * c * c * c;
}

}  // namespace vplkit_test
