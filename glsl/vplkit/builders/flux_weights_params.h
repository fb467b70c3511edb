// SPDX-License-Identifier: MIT
// Interface of flux_weights.comp, shared by the kernel (GLSL) and its hosts (C++,
// vplkit::gpu::flux_weights_params): default bindings, local size, the std140 parameter block.
#ifndef VPLKIT_BUILDERS_FLUX_WEIGHTS_PARAMS_H
#define VPLKIT_BUILDERS_FLUX_WEIGHTS_PARAMS_H

#include "vplkit/core/params.h"
#include "vplkit/vpl/light_params.h"

#ifndef VPLKIT_FLUX_WEIGHTS_BINDING_DPRSM
#define VPLKIT_FLUX_WEIGHTS_BINDING_DPRSM 0  // SSBO, readonly: vec4 dprsm[3 * 2 R^2]
#endif
#ifndef VPLKIT_FLUX_WEIGHTS_BINDING_WEIGHTS
#define VPLKIT_FLUX_WEIGHTS_BINDING_WEIGHTS 1  // SSBO, writeonly: float weights[2 R^2]
#endif
#ifndef VPLKIT_FLUX_WEIGHTS_BINDING_PARAMS
#define VPLKIT_FLUX_WEIGHTS_BINDING_PARAMS 2  // uniform block: flux_weights_params
#endif
#ifndef VPLKIT_FLUX_WEIGHTS_LOCAL_SIZE
#define VPLKIT_FLUX_WEIGHTS_LOCAL_SIZE 64
#endif

#ifdef __cplusplus
namespace vplkit::gpu {
struct flux_weights_params {
  light_params light;
#else
struct vplkit_flux_weights_params {
  vplkit_light_params light;
#endif
  int resolution;  // R
  int pad0;
  int pad1;
  int pad2;
};
#ifdef __cplusplus
static_assert(sizeof(flux_weights_params) == sizeof(light_params) + 16);
}  // namespace vplkit::gpu
#endif

#endif  // VPLKIT_BUILDERS_FLUX_WEIGHTS_PARAMS_H
