// SPDX-License-Identifier: MIT
#include "render/lighting_facts.hpp"

#include <vplkit/vpl/direct_light.hpp>

namespace vplrender {

std::size_t count_directly_lit_pixels(const gbuffer_data& g, const dprsm_data& d) {
  const vplkit::gbuffer_view<float> gv = g.view();
  const vplkit::dprsm_view<float> dv = d.view();
  std::size_t lit = 0;
  const int n = gv.width * gv.height;
  for (int p = 0; p < n; ++p) {
    const vec3 c = vplkit::direct_light(gv.at(p), dv);
    if (c.x > 0.0f || c.y > 0.0f || c.z > 0.0f) ++lit;
  }
  return lit;
}

bool image_is_black(const image_rgb& img) {
  for (float v : img.rgb)
    if (v != 0.0f) return false;
  return true;
}

}  // namespace vplrender
