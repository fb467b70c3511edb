// SPDX-License-Identifier: MIT
// vplkit GLSL pack: is a surface point lit by the light, and through which DPRSM texel? Mirrors
// include/vplkit/vpl/dprsm_lookup.hpp (T = float): the shadow-map test of the gathering estimator
// and of the GBG builder (docs/math.md section 4). y is lit when the light, looking through the
// texel y projects into, saw a surface at y's distance (within a depth tolerance).
//
// ACCESSORS used (declared in dprsm_view.glsl, defined by the including shader):
//   vec3 vplkit_load_dprsm_position(int texel);
//   vec3 vplkit_load_dprsm_albedo(int texel);
#ifndef VPLKIT_VPL_DPRSM_LOOKUP_GLSL
#define VPLKIT_VPL_DPRSM_LOOKUP_GLSL

#include "vplkit/vpl/dprsm_view.glsl"

struct vplkit_dprsm_lookup_result {
  int texel;  // flat texel index y projects into (-1 when y coincides with the light)
  bool lit;   // texel valid, saw a surface, and that surface is at y's depth
};

// tolerance: world-space depth tolerance. Depth is compared along the light ray (|y - c| against
// |y_t - c|), as a shadow map does.
vplkit_dprsm_lookup_result vplkit_dprsm_lookup(vplkit_dprsm_view view, vec3 y, float tolerance) {
  vplkit_dprsm_lookup_result r = vplkit_dprsm_lookup_result(-1, false);
  vec3 to_y = y - view.light.position;
  float d_y = length(to_y);
  if (!(d_y > 0.0)) return r;
  r.texel = vplkit_dprsm_view_texel_of_direction(view, to_y);
  if (!vplkit_dprsm_view_texel_valid(view, r.texel)) return r;
  vec3 rho = vplkit_load_dprsm_albedo(r.texel);
  if (!(rho.x > 0.0 || rho.y > 0.0 || rho.z > 0.0)) return r;
  float d_t = length(vplkit_load_dprsm_position(r.texel) - view.light.position);
  r.lit = abs(d_y - d_t) <= tolerance;
  return r;
}

#endif  // VPLKIT_VPL_DPRSM_LOOKUP_GLSL
