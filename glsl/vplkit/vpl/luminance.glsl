// SPDX-License-Identifier: MIT
// vplkit GLSL pack: scalar weight of an RGB quantity (paper eq. 6; ITU-R BT.601 luma weights).
// Mirrors include/vplkit/vpl/luminance.hpp (T = float): a result below the smallest normal float
// is 0.
#ifndef VPLKIT_VPL_LUMINANCE_GLSL
#define VPLKIT_VPL_LUMINANCE_GLSL

#include "vplkit/core/normal_range.glsl"

float vplkit_luminance(vec3 rgb) {
  return vplkit_flush_denormal(0.299 * rgb.x + 0.587 * rgb.y + 0.114 * rgb.z);
}

#endif  // VPLKIT_VPL_LUMINANCE_GLSL
