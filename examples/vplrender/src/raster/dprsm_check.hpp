// SPDX-License-Identifier: MIT
#pragma once
// The DPRSM by ray casting on the CPU (vplkit::render_dprsm with the renderer's double-precision
// ray caster), and the comparison used to measure the rasterised DPRSM's error.
#include "raster/render_data.hpp"
#include "scene/scene.hpp"

#include <cstddef>

namespace vplrender {

// One ray per valid texel centre; normal = interpolated shading normal turned towards the light,
// albedo = the material's (texture lookup included). O(texels x triangles): for tests and checks.
dprsm_data raycast_dprsm(const scene& s, const vplkit::point_light<float>& light, int R);

struct dprsm_difference {
  std::size_t valid_texels = 0;     // texels inside the unit disk
  std::size_t coverage_diff = 0;    // one map saw a surface there, the other did not
  std::size_t position_diff = 0;    // both saw one, positions differ by more than the tolerance
  double fraction() const {          // (coverage_diff + position_diff) / valid_texels
    return valid_texels ? double(coverage_diff + position_diff) / double(valid_texels) : 0.0;
  }
};

// tolerance: world distance (e.g. 1e-3 of the scene diagonal).
dprsm_difference compare_dprsm(const dprsm_data& a, const dprsm_data& b, double tolerance);

}  // namespace vplrender
