// SPDX-License-Identifier: MIT
#pragma once
// Colour conversions used by textures (decode) and previews (encode). sRGB is the IEC 61966-2-1
// piecewise curve, not a 2.2 power, so a GL_SRGB8 texture and the CPU agree.
#include <cmath>

namespace vplrender {

inline float srgb_to_linear(float c) {
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}

inline float linear_to_srgb(float c) {
  return c <= 0.0031308f ? 12.92f * c : 1.055f * std::pow(c, 1.0f / 2.4f) - 0.055f;
}

// Rec. 709 / sRGB-primaries luminance of linear RGB. (The VPL weights of docs/math.md section 2 use
// the paper's 0.299/0.587/0.114; this one is only for tone mapping, where the primaries matter.)
inline float luminance_rec709(float r, float g, float b) { return 0.2126f * r + 0.7152f * g + 0.0722f * b; }

}  // namespace vplrender
