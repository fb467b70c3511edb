// SPDX-License-Identifier: MIT
#pragma once
// A linear HDR RGB image as the renderer produces it: row 0 is the TOP row (as in the files we
// write; a GL read-back, bottom row first, must be flipped before it lands here).
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace vplrender {

struct image_rgb {
  int width = 0;
  int height = 0;
  std::vector<float> rgb;  // width * height * 3, row-major

  image_rgb() = default;
  // A non-positive size gives an empty buffer (which require_finite refuses), not a huge allocation.
  image_rgb(int w, int h)
      : width(w), height(h),
        rgb(w > 0 && h > 0 ? static_cast<std::size_t>(w) * static_cast<std::size_t>(h) * 3u : 0u, 0.0f) {}
  float* at(int x, int y) { return rgb.data() + (static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)) * 3u; }
  const float* at(int x, int y) const { return rgb.data() + (static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)) * 3u; }
};

struct non_finite_report {
  std::size_t count = 0;  // non-finite values (not pixels)
  int x = 0, y = 0, channel = 0;  // the first one, in row-major order
  float value = 0.0f;
};

std::optional<non_finite_report> find_non_finite(const image_rgb& img);

// Throws output_error("what: N non-finite values, first NaN at pixel (x, y) channel G") if the
// image holds a NaN or Inf, or if its size does not match its buffer. The renderer never writes
// such an image.
void require_finite(const image_rgb& img, const std::string& what);

}  // namespace vplrender
