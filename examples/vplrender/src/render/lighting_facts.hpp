// SPDX-License-Identifier: MIT
#pragma once
// What a frame shows of the light: G-buffer coverage, pixels the light reaches directly, a black
// image. The pipeline counts them; the application turns them into warnings (app/lighting_check).
#include "io/image.hpp"
#include "raster/render_data.hpp"

#include <cstddef>

namespace vplrender {

struct lighting_facts {
  std::size_t pixels = 0;               // width x height
  std::size_t visible_pixels = 0;       // the camera sees a surface there (valid G-buffer pixels)
  std::size_t directly_lit_pixels = 0;  // ... that the light reaches (vplkit::direct_light > 0)
  bool image_black = false;             // every value of the written image is 0
};

// Pixels whose surface the light reaches: vplkit::direct_light, the DPRSM as shadow map, as the
// --direct term computes it.
std::size_t count_directly_lit_pixels(const gbuffer_data& g, const dprsm_data& d);
bool image_is_black(const image_rgb& img);

}  // namespace vplrender
