// SPDX-License-Identifier: MIT
#include "io/png_preview.hpp"

#include "io/atomic_file.hpp"
#include "io/color.hpp"
#include "io/errors.hpp"

#include <stb_image_write.h>

#include <algorithm>
#include <cmath>

namespace vplrender {

std::vector<std::uint8_t> tonemap_reinhard(const image_rgb& img, float exposure) {
  std::vector<std::uint8_t> out(img.rgb.size());
  // Double, so exposure * FLT_MAX cannot overflow into Inf * 0 = NaN; non-finite input reads as 0
  // (write_png_preview refuses it before we get here).
  const double e = std::isfinite(exposure) && exposure > 0.0f ? exposure : 1.0;
  for (std::size_t i = 0; i + 2 < img.rgb.size(); i += 3) {
    double c[3];
    for (int k = 0; k < 3; ++k) {
      const float v = img.rgb[i + static_cast<std::size_t>(k)];
      c[k] = std::isfinite(v) ? e * std::max(static_cast<double>(v), 0.0) : 0.0;
    }
    const double l = 0.2126 * c[0] + 0.7152 * c[1] + 0.0722 * c[2];
    const double s = 1.0 / (1.0 + l);
    for (int k = 0; k < 3; ++k) {
      const float v = linear_to_srgb(static_cast<float>(std::clamp(c[k] * s, 0.0, 1.0)));
      out[i + static_cast<std::size_t>(k)] = static_cast<std::uint8_t>(std::lround(v * 255.0f));
    }
  }
  return out;
}

std::vector<std::uint8_t> encode_png(const std::string& path, const std::vector<std::uint8_t>& rgb8, int width,
                                     int height) {
  std::vector<std::uint8_t> png;
  // In memory, then written by write_file_bytes: stbi_write_png ignores fwrite's errors (a full
  // disk left a truncated file behind a success).
  const auto append = [](void* context, void* data, int size) {
    auto* out = static_cast<std::vector<std::uint8_t>*>(context);
    const auto* bytes = static_cast<const std::uint8_t*>(data);
    out->insert(out->end(), bytes, bytes + size);
  };
  if (!stbi_write_png_to_func(append, &png, width, height, 3, rgb8.data(), width * 3) || png.empty())
    throw output_error(path + ": cannot encode PNG");
  return png;
}

void write_png_preview(const std::string& path, const image_rgb& img, float exposure) {
  output_set set;
  write_png_preview(set, path, img, exposure);
  set.publish();
}

void write_png_preview(output_set& set, const std::string& path, const image_rgb& img, float exposure) {
  if (!(std::isfinite(exposure) && exposure > 0.0f))
    throw output_error(path + ": exposure " + std::to_string(exposure) + " must be finite and > 0");
  require_finite(img, path);
  const std::vector<std::uint8_t> ldr = tonemap_reinhard(img, exposure);
  const std::vector<std::uint8_t> png = encode_png(path, ldr, img.width, img.height);
  set.write(path, [&](const std::string& temp) { write_file_bytes(temp, path, png.data(), png.size()); });
}

}  // namespace vplrender
