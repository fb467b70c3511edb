// SPDX-License-Identifier: MIT
// vplkit GLSL pack: scalar weight of an RGB quantity (paper eq. 6; ITU-R BT.601 luma weights).
// Mirrors include/vplkit/vpl/luminance.hpp (T = float).
#ifndef VPLKIT_VPL_LUMINANCE_GLSL
#define VPLKIT_VPL_LUMINANCE_GLSL

float vplkit_luminance(vec3 rgb) {
  return 0.299 * rgb.x + 0.587 * rgb.y + 0.114 * rgb.z;
}

#endif  // VPLKIT_VPL_LUMINANCE_GLSL
