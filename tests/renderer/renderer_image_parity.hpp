// SPDX-License-Identifier: MIT
#pragma once
// Per-pixel agreement of two renders of one frame (the CPU and the GPU backend's), as
// renderer_gpu_parity_test's compare(): a pixel agrees when each channel is within rel relative
// (plus 1e-6 of the first image's mean: float noise around zero counts as equal); every value must be
// finite and non-negative.
#include "render/result.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>

namespace vplrender_test {

struct parity {
  double within = 0.0;  // fraction of the pixels that agree
  double worst = 0.0;   // worst relative difference of a channel, over every pixel
};

inline parity compare(const vplrender::image_rgb& c, const vplrender::image_rgb& g, double rel) {
  REQUIRE(c.rgb.size() == g.rgb.size());
  double mean = 0.0;
  for (float v : c.rgb) mean += v;
  mean /= std::max<std::size_t>(1, c.rgb.size());
  const double floor_abs = 1e-6 * mean;
  parity r;
  std::size_t ok = 0;
  const std::size_t pixels = c.rgb.size() / 3;
  for (std::size_t p = 0; p < pixels; ++p) {
    bool inside = true;
    for (std::size_t k = 0; k < 3; ++k) {
      const double a = c.rgb[3 * p + k], b = g.rgb[3 * p + k];
      REQUIRE(std::isfinite(a));
      REQUIRE(std::isfinite(b));
      REQUIRE(a >= 0.0);
      REQUIRE(b >= 0.0);
      const double d = std::abs(a - b), m = std::max(std::abs(a), std::abs(b));
      if (d > rel * m + floor_abs) inside = false;
      if (m > 0.0) r.worst = std::max(r.worst, d / m);
    }
    if (inside) ++ok;
  }
  r.within = static_cast<double>(ok) / static_cast<double>(std::max<std::size_t>(pixels, 1));
  return r;
}

}  // namespace vplrender_test
