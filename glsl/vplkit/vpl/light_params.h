// SPDX-License-Identifier: MIT
// The point light of a DPRSM as kernel parameters (std140, 80 bytes): part of the parameter blocks
// of the builder kernels. C++: vplkit::gpu::light_params, filled by make_light_params(light);
// GLSL: vplkit_light_params, turned back into a vplkit_point_light by
// vplkit_light_params_point_light (core/params.h explains the two-language form).
#ifndef VPLKIT_VPL_LIGHT_PARAMS_H
#define VPLKIT_VPL_LIGHT_PARAMS_H

#include "vplkit/core/params.h"

#ifdef __cplusplus
#include <vplkit/vpl/dprsm_view.hpp>
namespace vplkit::gpu {
struct light_params {
#else
#include "vplkit/vpl/dprsm_view.glsl"
struct vplkit_light_params {
#endif
  vec4 position;   // xyz: c, also the light frame's position; w unused
  vec4 intensity;  // xyz: I_s
  vec4 axis_x;     // xyz: the DPRSM's light frame
  vec4 axis_y;
  vec4 axis_z;
};
#ifdef __cplusplus
static_assert(sizeof(light_params) == 80);

inline light_params make_light_params(const point_light<float>& light) {
  return {vec4(light.position, 0.0f), vec4(light.intensity, 0.0f), vec4(light.frame.axis_x, 0.0f),
          vec4(light.frame.axis_y, 0.0f), vec4(light.frame.axis_z, 0.0f)};
}
}  // namespace vplkit::gpu
#else
vplkit_point_light vplkit_light_params_point_light(vplkit_light_params p) {
  return vplkit_point_light(p.position.xyz, p.intensity.xyz,
                            vplkit_light_frame(p.position.xyz, p.axis_x.xyz, p.axis_y.xyz, p.axis_z.xyz));
}
#endif

#endif  // VPLKIT_VPL_LIGHT_PARAMS_H
