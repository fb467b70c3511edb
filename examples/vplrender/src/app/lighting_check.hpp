// SPDX-License-Identifier: MIT
#pragma once
// After a render: warnings for an image that shows nothing lit, each saying what to try. The facts
// come from the frame (G-buffer coverage, pixels the light reaches directly) and the image.
#include "app/options.hpp"
#include "app/scene_setup.hpp"
#include "io/image.hpp"
#include "raster/render_data.hpp"

#include <cstddef>
#include <string>
#include <vector>

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

// One warning per problem (none for a healthy frame). The hints follow how the camera and the
// light were chosen (prepared_scene's rules): an OBJ's automatic camera, an automatic light, flags.
std::vector<std::string> lighting_warnings(const prepared_scene& p, const options& o, const lighting_facts& f);

}  // namespace vplrender
