// SPDX-License-Identifier: MIT
#pragma once
// Error of an image against a reference, on linear HDR values (docs/speed_vs_error.md):
//   RMSE   = sqrt( mean over pixels p and channels c of (x_pc - r_pc)^2 )
//   relMSE = mean over pixels p and channels c of (x_pc - r_pc)^2 / (r_pc^2 + eps), eps = 1e-2
// Sums in double: 3 * W * H float terms would otherwise lose the small ones.
#include "io/image.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>
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

// The noise of a Monte Carlo reference r (converged gathering, exact: cosine gathering at a finite
// number of directions), from a second render r2 of it with the same directions and an independent
// seed. Against a noisy reference every error above carries the reference's own variance:
//   E[(x - r)^2] = E[(x - t)^2] + Var(r)   (t the true value, x independent of r),
// so at high sample counts every method's error meets a floor that is the reference's, not its
// own. v_pc = (r_pc - r2_pc)^2 / 2 estimates Var(r_pc) without bias; m_pc = (r_pc + r2_pc) / 2.
// The noise, as the floor it makes:
//   mse    = mean_{p,c} v_pc
//   relmse = mean_{p,c} v_pc / (m_pc^2 + eps)
// with their standard errors (the spread of the terms over the square root of their count).
struct reference_noise {
  double mse = 0.0, mse_se = 0.0;
  double relmse = 0.0, relmse_se = 0.0;
};

namespace detail {

inline void check_same_size(const vplrender::image_rgb& a, const vplrender::image_rgb& b, const char* what) {
  if (a.width != b.width || a.height != b.height || a.rgb.size() != b.rgb.size() || a.rgb.empty())
    throw std::runtime_error(std::string(what) + ": images differ in size");
}

}  // namespace detail

inline reference_noise estimate_noise(const vplrender::image_rgb& r, const vplrender::image_rgb& r2,
                                      double eps = relmse_epsilon) {
  detail::check_same_size(r, r2, "estimate_noise");
  double s = 0.0, s2 = 0.0, q = 0.0, q2 = 0.0;
  for (std::size_t i = 0; i < r.rgb.size(); ++i) {
    const double a = static_cast<double>(r.rgb[i]), b = static_cast<double>(r2.rgb[i]);
    const double m = 0.5 * (a + b), v = 0.5 * (a - b) * (a - b), w = v / (m * m + eps);
    s += v, s2 += v * v, q += w, q2 += w * w;
  }
  const double n = static_cast<double>(r.rgb.size());
  const auto se = [n](double sum, double sum2) {
    const double mean = sum / n;
    return n > 1.0 ? std::sqrt(std::max(0.0, sum2 / n - mean * mean) / (n - 1.0)) : 0.0;
  };
  return {s / n, se(s, s2), q / n, se(q, q2)};
}

// The error of x against the truth, from the reference r and its second render r2 (the "net"
// error):
//   net MSE    = mean_{p,c} ((x_pc - r_pc)^2 - v_pc)                  (unbiased for E[(x - t)^2])
//   net relMSE = mean_{p,c} ((x_pc - r_pc)^2 - v_pc) / (m_pc^2 + eps)
// and RMSE = sqrt(net MSE), 0 where it is not positive (a run closer to the truth than the noise
// can tell; the relMSE stays signed). The relMSE divides by m, which holds half r's noise and is
// symmetric in r and r2, so the numerator's r^2 and r2^2 noise terms cancel in expectation; what
// is left is a bias of about 3 sigma^2 / t^2 relative (sigma / t: r's relative noise per pixel,
// a few % for a converged reference), half that of dividing by r.
inline image_error compare_net(const vplrender::image_rgb& x, const vplrender::image_rgb& r,
                               const vplrender::image_rgb& r2, double eps = relmse_epsilon) {
  detail::check_same_size(x, r, "compare_net");
  detail::check_same_size(r, r2, "compare_net");
  double se = 0.0, rel = 0.0;
  for (std::size_t i = 0; i < x.rgb.size(); ++i) {
    const double a = static_cast<double>(r.rgb[i]), b = static_cast<double>(r2.rgb[i]);
    const double d = static_cast<double>(x.rgb[i]) - a;
    const double m = 0.5 * (a + b), e = d * d - 0.5 * (a - b) * (a - b);
    se += e;
    rel += e / (m * m + eps);
  }
  const double n = static_cast<double>(x.rgb.size());
  const double mse = se / n;
  return {mse > 0.0 ? std::sqrt(mse) : 0.0, rel / n};
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
