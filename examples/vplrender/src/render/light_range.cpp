// SPDX-License-Identifier: MIT
#include "render/light_range.hpp"

#include "io/errors.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace vplrender {

bool light_may_overflow(vplkit::vec3<float> intensity) {
  return !(std::max({intensity.x, intensity.y, intensity.z}) < light_overflow_intensity);
}

std::string with_light_hint(const std::string& what, vplkit::vec3<float> intensity) {
  if (!light_may_overflow(intensity)) return what;
  std::ostringstream s;
  s << "--light: the intensity (" << intensity.x << ", " << intensity.y << ", " << intensity.z
    << ") W/sr overflows float in the renderer (" << what << "); lower it below "
    << light_overflow_intensity << " W/sr";
  return s.str();
}

void check_image_against_light(const image_rgb& img, vplkit::vec3<float> intensity) {
  const auto bad = std::find_if(img.rgb.begin(), img.rgb.end(), [](float v) { return !std::isfinite(v); });
  if (bad == img.rgb.end() || !light_may_overflow(intensity)) return;
  const std::size_t pixel = static_cast<std::size_t>(bad - img.rgb.begin()) / 3u;
  const int w = std::max(img.width, 1);
  throw input_error(with_light_hint("pixel (x=" + std::to_string(pixel % std::size_t(w)) + ", y=" +
                                        std::to_string(pixel / std::size_t(w)) + ") is not finite",
                                    intensity));
}

}  // namespace vplrender
