// SPDX-License-Identifier: MIT
#pragma once
// What a discrete sampler returns: the chosen index and the probability of choosing it. The pmf is
// the value the estimator divides by, so every sampler returns exactly what its pmf(index) would
// return for that index (same formula, same rounding). pmf == 0 means "no sample" (an empty
// distribution); callers must test it before dividing.
#include <cstddef>

namespace vplkit {

template <class T>
struct discrete_sample {
  std::size_t index;
  T pmf;
};

}  // namespace vplkit
