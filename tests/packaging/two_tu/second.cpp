// SPDX-License-Identifier: MIT
#include <vplkit/vplkit.hpp>

double second_translation_unit() {
  const std::vector<double> weights = {1.0, 0.0, 3.0};
  const vplkit::alias_table<double> table(weights);
  return table.pmf(2);
}
