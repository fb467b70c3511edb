// SPDX-License-Identifier: MIT
// vplkit GLSL pack: direct light at a gather point from the DPRSM's point light, shadowed by the
// DPRSM itself; mirrors include/vplkit/vpl/direct_light.hpp (T = float) statement for statement.
// ACCESSORS used: those of vpl/dprsm_view.glsl.
#ifndef VPLKIT_VPL_DIRECT_LIGHT_GLSL
#define VPLKIT_VPL_DIRECT_LIGHT_GLSL

#include "vplkit/core/gather_point.glsl"
#include "vplkit/vpl/dprsm_lookup.glsl"
#include "vplkit/vpl/dprsm_view.glsl"
#include "vplkit/vpl/vpl.glsl"

// Depth tolerance of the shadow test (the C++ comment gives the reasoning).
float vplkit_direct_light_depth_tolerance(float d, float cos_a, int resolution) {
  float tan_a = min(20.0, sqrt(max(0.0, 1.0 - cos_a * cos_a)) / cos_a);
  return d * (4.0 / float(resolution)) * (0.5 + tan_a) + 1e-4 * d;
}

// L_o(x) where the DPRSM sees x lit, else 0; cos(alpha) the shading normal's, facing and
// tolerance the geometric surface's.
vec3 vplkit_direct_light(vplkit_gather_point gp, vplkit_dprsm_view view) {
  if (!vplkit_gather_point_valid(gp)) return vec3(0.0);
  vec3 to_light = view.light.position - gp.position;
  float d = length(to_light);
  if (!(d > 0.0)) return vec3(0.0);
  float cos_a = dot(normalize(gp.normal), to_light / d);
  if (!(cos_a > 0.0)) return vec3(0.0);
  float tolerance = vplkit_direct_light_depth_tolerance(d, cos_a, view.resolution);
  vplkit_dprsm_lookup_result r = vplkit_dprsm_lookup(view, gp.position, tolerance);
  if (!r.lit) return vec3(0.0);
  return vplkit_reflected_radiance(view.light.position, view.light.intensity, gp.position,
                                   vplkit_gather_point_shading_normal(gp), gp.albedo);
}

#endif  // VPLKIT_VPL_DIRECT_LIGHT_GLSL
