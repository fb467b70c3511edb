// SPDX-License-Identifier: MIT
// vplkit GLSL pack: direct light at a gather point from the DPRSM's point light, shadowed by the
// DPRSM itself; mirrors include/vplkit/vpl/direct_light.hpp (T = float) statement for statement.
// ACCESSORS used: those of vpl/dprsm_view.glsl.
#ifndef VPLKIT_VPL_DIRECT_LIGHT_GLSL
#define VPLKIT_VPL_DIRECT_LIGHT_GLSL

#include "vplkit/core/gather_point.glsl"
#include "vplkit/core/normal_range.glsl"
#include "vplkit/vpl/dprsm_lookup.glsl"
#include "vplkit/vpl/dprsm_view.glsl"
#include "vplkit/vpl/vpl.glsl"

// L_o(x) where the DPRSM sees x lit (tolerance 0), else 0; cos(alpha) the shading normal's, facing
// the geometric surface's.
vec3 vplkit_direct_light(vplkit_gather_point gp, vplkit_dprsm_view view) {
  if (!vplkit_gather_point_valid(gp)) return vec3(0.0);
  vec3 to_light = view.light.position - gp.position;
  // Scale-first, and nothing lit beyond 2^126 (a reciprocal of d would flush), as the C++.
  float d = vplkit_scaled_length(to_light);
  if (!(d > 0.0) || !(d <= 8.5070591730234616e37)) return vec3(0.0);
  float cos_a = dot(normalize(gp.normal), to_light / d);
  if (!(cos_a > 0.0)) return vec3(0.0);
  vplkit_dprsm_lookup_result r = vplkit_dprsm_lookup(view, gp.position, 0.0);
  if (!r.lit) return vec3(0.0);
  return vplkit_reflected_radiance(view.light.position, view.light.intensity, gp.position,
                                   vplkit_gather_point_shading_normal(gp), gp.albedo);
}

#endif  // VPLKIT_VPL_DIRECT_LIGHT_GLSL
