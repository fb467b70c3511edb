// SPDX-License-Identifier: MIT
#pragma once
// Error of an image against a reference, on linear HDR values (docs/speed_vs_error.md):
//   RMSE   = sqrt( mean over pixels p and channels c of (x_pc - r_pc)^2 )
//   relMSE = mean over pixels p and channels c of (x_pc - r_pc)^2 / (r_pc^2 + eps), eps = 1e-2
// Sums in double: 3 * W * H float terms would otherwise lose the small ones.
#include "io/image.hpp"

#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <vector>

namespace speed_vs_error {

constexpr double relmse_epsilon = 1e-2;

struct image_error {
  double rmse = 0.0;
  double relmse = 0.0;
};

inline image_error compare(const vplrender::image_rgb& x, const vplrender::image_rgb& r, double eps = relmse_epsilon) {
  if (x.width != r.width || x.height != r.height || x.rgb.size() != r.rgb.size() || x.rgb.empty())
    throw std::runtime_error("compare: images differ in size");
  double se = 0.0, rel = 0.0;
  for (std::size_t i = 0; i < x.rgb.size(); ++i) {
    const double d = static_cast<double>(x.rgb[i]) - static_cast<double>(r.rgb[i]);
    const double rv = static_cast<double>(r.rgb[i]);
    se += d * d;
    rel += d * d / (rv * rv + eps);
  }
  const double n = static_cast<double>(x.rgb.size());
  return {std::sqrt(se / n), rel / n};
}

// Bias/variance split over S >= 2 runs x_s with different seeds, m = their mean image:
//   variance = mean_{p,c} sum_s (x_s,pc - m_pc)^2 / (S - 1)   (one run's variance, unbiased)
//   bias2    = mean_{p,c} (m_pc - r_pc)^2 - variance / S      (unbiased, so it may dip below 0)
// E[MSE(x_s, r)] = bias2 + variance.
struct bias_variance {
  double variance = 0.0;
  double bias2 = 0.0;
};

inline bias_variance split(const std::vector<vplrender::image_rgb>& runs, const vplrender::image_rgb& r) {
  if (runs.size() < 2) throw std::runtime_error("split: needs 2 or more runs");
  for (const vplrender::image_rgb& x : runs)
    if (x.width != r.width || x.height != r.height || x.rgb.size() != r.rgb.size() || x.rgb.empty())
      throw std::runtime_error("split: images differ in size");
  const double S = static_cast<double>(runs.size());
  double var = 0.0, mse_mean = 0.0;
  for (std::size_t i = 0; i < r.rgb.size(); ++i) {
    double m = 0.0;
    for (const vplrender::image_rgb& x : runs) m += static_cast<double>(x.rgb[i]);
    m /= S;
    double ss = 0.0;
    for (const vplrender::image_rgb& x : runs) {
      const double d = static_cast<double>(x.rgb[i]) - m;
      ss += d * d;
    }
    var += ss / (S - 1.0);
    const double e = m - static_cast<double>(r.rgb[i]);
    mse_mean += e * e;
  }
  const double n = static_cast<double>(r.rgb.size());
  var /= n;
  return {var, mse_mean / n - var / S};
}

}  // namespace speed_vs_error
