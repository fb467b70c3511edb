// SPDX-License-Identifier: MIT
#pragma once
// The LDR preview: Reinhard's global operator on luminance, then the sRGB curve, 8 bits.
//   c = exposure * max(rgb, 0);  L = Rec.709 luminance of c;  c' = c / (1 + L)
// i.e. L maps to L / (1 + L) and hue is kept; channels that a saturated colour pushes past 1 are
// clipped. No log-average "key": a fixed exposure keeps previews of different methods comparable.
#include "io/image.hpp"
#include "io/output_set.hpp"

#include <cstdint>
#include <string>
#include <vector>

namespace vplrender {

// width * height * 3 bytes, row 0 at the top. The image must be finite (require_finite).
std::vector<std::uint8_t> tonemap_reinhard(const image_rgb& img, float exposure = 1.0f);

// Tone-maps and writes a PNG atomically. Throws output_error on a non-finite image, a bad exposure
// or a failed write.
void write_png_preview(const std::string& path, const image_rgb& img, float exposure = 1.0f);
// The same into `set`: on disk under `path` once the set is published.
void write_png_preview(output_set& set, const std::string& path, const image_rgb& img, float exposure = 1.0f);
// The PNG file's bytes (stb_image_write's encoder, in memory). Throws output_error naming `path`.
std::vector<std::uint8_t> encode_png(const std::string& path, const std::vector<std::uint8_t>& rgb8, int width, int height);

}  // namespace vplrender
