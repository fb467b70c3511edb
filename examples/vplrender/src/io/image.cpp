// SPDX-License-Identifier: MIT
#include "io/image.hpp"

#include "io/errors.hpp"

#include <cmath>

namespace vplrender {

std::optional<non_finite_report> find_non_finite(const image_rgb& img) {
  non_finite_report r;
  for (std::size_t i = 0; i < img.rgb.size(); ++i) {
    if (std::isfinite(img.rgb[i])) continue;
    if (r.count++ == 0) {
      const std::size_t pixel = i / 3;
      r.x = static_cast<int>(pixel % static_cast<std::size_t>(img.width));
      r.y = static_cast<int>(pixel / static_cast<std::size_t>(img.width));
      r.channel = static_cast<int>(i % 3);
      r.value = img.rgb[i];
    }
  }
  if (r.count == 0) return std::nullopt;
  return r;
}

void require_finite(const image_rgb& img, const std::string& what) {
  if (img.width <= 0 || img.height <= 0 ||
      img.rgb.size() != static_cast<std::size_t>(img.width) * static_cast<std::size_t>(img.height) * 3u)
    throw output_error(what + ": image size " + std::to_string(img.width) + "x" + std::to_string(img.height) +
                       " does not match its " + std::to_string(img.rgb.size()) + " values");
  if (auto r = find_non_finite(img)) {
    static const char* names[] = {"R", "G", "B"};
    throw output_error(what + ": refusing to write an image with " + std::to_string(r->count) +
                       " non-finite value(s); first " + (std::isnan(r->value) ? "NaN" : "Inf") + " at pixel (" +
                       std::to_string(r->x) + ", " + std::to_string(r->y) + ") channel " + names[r->channel]);
  }
}

}  // namespace vplrender
