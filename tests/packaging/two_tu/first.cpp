// SPDX-License-Identifier: MIT
// Included in two translation units: a non-inline definition anywhere in the amalgamation would
// fail to link here.
#include <vplkit/vplkit.hpp>

double first_translation_unit() {
  const std::vector<float> weights = {1.0f, 0.0f, 3.0f};
  const vplkit::discrete_cdf<float> cdf(weights);
  return double(cdf.sample(0.9f).pmf);
}
