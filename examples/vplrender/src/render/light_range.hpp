// SPDX-License-Identifier: MIT
#pragma once
// A point light whose intensity is near float's limit overflows the renderer's float sums (VPL
// fluxes, GBG weights, the estimators' terms) on either backend. The library reports where
// (e.g. "median_fill: texel ... is infinite"); the user needs to hear which flag to change.
#include "io/image.hpp"

#include <vplkit/core/vector.hpp>

#include <string>

namespace vplrender {

// Above this (W/sr, any channel) an overflow is the light's doing: the largest scene terms are
// I rho / (pi d^2) over up to 2 * 4096^2 texels, so 1e20 leaves float about 1e18 of headroom for
// d and the sums, and no physical light in a float renderer comes near it.
constexpr float light_overflow_intensity = 1e20f;

bool light_may_overflow(vplkit::vec3<float> intensity);

// "--light: the intensity (r, g, b) W/sr overflows float in <what>; lower it" when the light may
// overflow, else `what` unchanged.
std::string with_light_hint(const std::string& what, vplkit::vec3<float> intensity);

// Throws input_error naming --light when `img` has a non-finite pixel and the light may overflow.
void check_image_against_light(const image_rgb& img, vplkit::vec3<float> intensity);

}  // namespace vplrender
