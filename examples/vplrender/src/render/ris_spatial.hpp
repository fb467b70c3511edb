// SPDX-License-Identifier: MIT
#pragma once
// The spatial reuse's settings of --method ris, shared by both backends (render/cpu/ris_render.hpp,
// render/gpu/gpu_backend.cpp), so that they pick the same neighbours.
#include <vplkit/estimators/ris_spatial_reuse.hpp>

#include <algorithm>

namespace vplrender {

// The neighbourhood of the spatial reuse: a square of 1/16 of the image's shorter side on each
// side of the pixel (at least 2 pixels), so that it covers the same part of the view at every
// image size; the rejection thresholds are the library's defaults.
inline vplkit::ris_spatial_settings<float> ris_spatial_settings_for(int width, int height, int neighbours) {
  vplkit::ris_spatial_settings<float> s;
  s.neighbours = neighbours;
  s.radius = std::max(2, std::min(width, height) / 16);
  return s;
}

}  // namespace vplrender
