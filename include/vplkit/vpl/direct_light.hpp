// SPDX-License-Identifier: MIT
#pragma once
// Direct light at a gather point from the DPRSM's point light, shadowed by the DPRSM itself: the
// DPRSM records what the light sees, so it doubles as the light's shadow map (docs/api/vpl.md,
// "Direct light"). GLSL: vpl/direct_light.glsl, statement for statement.
#include <vplkit/core/gather_point.hpp>
#include <vplkit/core/normal_range.hpp>
#include <vplkit/core/vector.hpp>
#include <vplkit/vpl/dprsm_lookup.hpp>
#include <vplkit/vpl/dprsm_view.hpp>
#include <vplkit/vpl/vpl.hpp>

namespace vplkit {

// L_o(x) = rho_x I_s cos(alpha) / (pi d^2) (reflected_radiance) where the DPRSM sees x lit
// (dprsm_lookup with tolerance 0: a G-buffer point lies on its triangle up to rounding, which the
// lit test's own slack covers), else 0: background pixels, points at the light or facing away
// from it, points in shadow. cos(alpha) is the shading normal's; whether x faces the light is the
// geometric surface's.
template <class T>
inline vec3<T> direct_light(const gather_point<T>& gp, const dprsm_view<T>& view) {
  if (!gather_point_valid(gp)) return vec3<T>(T(0));
  const vec3<T> to_light = view.light.position - gp.position;
  // Scale-first (scaled_length): glm::length's square is a denormal below 2^-63 (float), which a
  // GPU flushes to 0 (the point was lit here and unlit there), and Inf beyond 2^64. Beyond 2^126
  // nothing is lit (dprsm_lookup's plane test says behind there): a GPU may divide by such a d as
  // to_light * (1 / d), whose reciprocal it flushes to 0.
  const T d = scaled_length(to_light);
  if (!(d > T(0)) || !(d <= exp2i<T>(std::numeric_limits<T>::max_exponent - 2))) return vec3<T>(T(0));
  const T cos_a = glm::dot(glm::normalize(gp.normal), to_light / d);
  if (!(cos_a > T(0))) return vec3<T>(T(0));
  const dprsm_lookup_result r = dprsm_lookup(view, gp.position, T(0));
  if (!r.lit) return vec3<T>(T(0));
  return reflected_radiance(view.light.position, view.light.intensity, gp.position,
                            gather_point_shading_normal(gp), gp.albedo);
}

}  // namespace vplkit
