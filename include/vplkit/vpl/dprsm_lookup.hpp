// SPDX-License-Identifier: MIT
#pragma once
// Is a surface point lit by the light, and through which DPRSM texel? The shadow-map test of the
// gathering estimator and of the GBG builder (docs/math.md section 4): y is lit when the light,
// looking through the texel y projects into, saw a surface at y's distance (within a depth
// tolerance).
#include <vplkit/core/vector.hpp>
#include <vplkit/vpl/dprsm_view.hpp>

#include <cmath>

namespace vplkit {

struct dprsm_lookup_result {
  int texel = -1;    // flat texel index y projects into (-1 when y coincides with the light)
  bool lit = false;  // texel valid, saw a surface, and that surface is at y's depth
};

// tolerance: world-space depth tolerance (a voxel or two when y comes from voxel ray marching).
// Depth is compared along the light ray (|y - c| against |y_t - c|), as a shadow map does; the
// lateral offset within one texel's footprint is not a reason to reject.
template <class T>
inline dprsm_lookup_result dprsm_lookup(const dprsm_view<T>& view, vec3<T> y, T tolerance) {
  dprsm_lookup_result r;
  const vec3<T> to_y = y - view.light.position;
  const T d_y = glm::length(to_y);
  if (!(d_y > T(0))) return r;
  r.texel = view.texel_of_direction(to_y);
  if (!view.texel_valid(r.texel)) return r;
  const vec3<T> rho = view.albedo[r.texel];
  if (!(rho.x > T(0) || rho.y > T(0) || rho.z > T(0))) return r;
  const T d_t = glm::length(view.position[r.texel] - view.light.position);
  r.lit = std::abs(d_y - d_t) <= tolerance;
  return r;
}

}  // namespace vplkit
