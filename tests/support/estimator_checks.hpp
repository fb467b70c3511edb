// SPDX-License-Identifier: MIT
#pragma once
// What the estimator hard-case tests share (not part of the library): the check every estimate
// must pass, and a distribution that draws one fixed index with a chosen pmf (denormal, NaN,
// infinite, out of range), which no real distribution would give.
#include <vplkit/core/vector.hpp>
#include <vplkit/distribution/discrete_sample.hpp>

#include <cmath>
#include <cstddef>

namespace vplkit_test {

// Every channel finite and not negative.
template <class T>
bool finite_nonneg(vplkit::vec3<T> v) {
  for (int c = 0; c < 3; ++c)
    if (!std::isfinite(v[c]) || v[c] < T(0)) return false;
  return true;
}

// A distribution that always returns one index with one pmf.
template <class T>
struct fixed_draw {
  std::size_t index;
  T p;
  vplkit::discrete_sample<T> sample(T) const { return {index, p}; }
  T pmf(std::size_t i) const { return i == index ? p : T(0); }
};

}  // namespace vplkit_test
