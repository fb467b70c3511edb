// SPDX-License-Identifier: MIT
#pragma once
// Pearson correlation of two equally long sequences, for the tests that check samples or weights
// are (un)correlated (not part of the library).
#include <cmath>
#include <cstddef>
#include <vector>

namespace vplkit_test {

inline double pearson_correlation(const std::vector<double>& a, const std::vector<double>& b) {
  const double n = double(a.size());
  double ma = 0, mb = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    ma += a[i];
    mb += b[i];
  }
  ma /= n;
  mb /= n;
  double sab = 0, saa = 0, sbb = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    sab += (a[i] - ma) * (b[i] - mb);
    saa += (a[i] - ma) * (a[i] - ma);
    sbb += (b[i] - mb) * (b[i] - mb);
  }
  return sab / std::sqrt(saa * sbb);
}

}  // namespace vplkit_test
