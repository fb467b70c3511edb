// SPDX-License-Identifier: MIT
#pragma once
// Direct light at a gather point from the DPRSM's point light, shadowed by the DPRSM itself: the
// DPRSM records what the light sees, so it doubles as the light's shadow map (docs/api/vpl.md,
// "Direct light"). GLSL: vpl/direct_light.glsl, statement for statement.
#include <vplkit/core/gather_point.hpp>
#include <vplkit/core/vector.hpp>
#include <vplkit/vpl/dprsm_lookup.hpp>
#include <vplkit/vpl/dprsm_view.hpp>
#include <vplkit/vpl/vpl.hpp>

#include <algorithm>
#include <cmath>

namespace vplkit {

// Depth tolerance of the shadow test for a point at distance d from the light whose normal makes
// cos_a > 0 with the direction to the light. A texel's footprint is at most 4 d / R wide (the
// paraboloid's angular texel size is 2/R at the rim, 4/R at the pole); on a surface tilted by
// alpha the depth along the light ray varies by footprint * tan(alpha) across it, tan capped at
// 20; 1e-4 d more covers the depth's own rounding.
template <class T>
inline T direct_light_depth_tolerance(T d, T cos_a, int resolution) {
  const T tan_a = std::min(T(20), std::sqrt(std::max(T(0), T(1) - cos_a * cos_a)) / cos_a);
  return d * (T(4) / T(resolution)) * (T(0.5) + tan_a) + T(1e-4) * d;
}

// L_o(x) = rho_x I_s cos(alpha) / (pi d^2) (reflected_radiance) where the DPRSM sees x lit
// (dprsm_lookup within direct_light_depth_tolerance), else 0: background pixels, points at the
// light or facing away from it, points in shadow. cos(alpha) is the shading normal's; whether x
// faces the light, and the shadow test's tolerance, are the geometric surface's.
template <class T>
inline vec3<T> direct_light(const gather_point<T>& gp, const dprsm_view<T>& view) {
  if (!gather_point_valid(gp)) return vec3<T>(T(0));
  const vec3<T> to_light = view.light.position - gp.position;
  const T d = glm::length(to_light);
  if (!(d > T(0))) return vec3<T>(T(0));
  const T cos_a = glm::dot(glm::normalize(gp.normal), to_light / d);
  if (!(cos_a > T(0))) return vec3<T>(T(0));
  const T tolerance = direct_light_depth_tolerance(d, cos_a, view.resolution);
  const dprsm_lookup_result r = dprsm_lookup(view, gp.position, tolerance);
  if (!r.lit) return vec3<T>(T(0));
  return reflected_radiance(view.light.position, view.light.intensity, gp.position,
                            gather_point_shading_normal(gp), gp.albedo);
}

}  // namespace vplkit
