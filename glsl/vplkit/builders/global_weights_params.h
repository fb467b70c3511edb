// SPDX-License-Identifier: MIT
// Interface of global_weights.comp, shared by the kernel (GLSL) and its hosts (C++,
// vplkit::gpu::global_weights_params): default bindings, local size, the std140 parameter block.
#ifndef VPLKIT_BUILDERS_GLOBAL_WEIGHTS_PARAMS_H
#define VPLKIT_BUILDERS_GLOBAL_WEIGHTS_PARAMS_H

#include "vplkit/core/params.h"
#include "vplkit/vpl/light_params.h"

#ifndef VPLKIT_GLOBAL_WEIGHTS_BINDING_GBUFFER
#define VPLKIT_GLOBAL_WEIGHTS_BINDING_GBUFFER 0  // SSBO, readonly: vec4 gbuffer[3 W H]
#endif
#ifndef VPLKIT_GLOBAL_WEIGHTS_BINDING_DPRSM
#define VPLKIT_GLOBAL_WEIGHTS_BINDING_DPRSM 1  // SSBO, readonly: vec4 dprsm[3 * 2 R^2]
#endif
#ifndef VPLKIT_GLOBAL_WEIGHTS_BINDING_SUBSET
#define VPLKIT_GLOBAL_WEIGHTS_BINDING_SUBSET 2  // SSBO, readonly: int pixels[]
#endif
#ifndef VPLKIT_GLOBAL_WEIGHTS_BINDING_OFFSETS
#define VPLKIT_GLOBAL_WEIGHTS_BINDING_OFFSETS 3  // SSBO, readonly: uint offsets[N + 1]
#endif
#ifndef VPLKIT_GLOBAL_WEIGHTS_BINDING_WEIGHTS
#define VPLKIT_GLOBAL_WEIGHTS_BINDING_WEIGHTS 4  // SSBO, writeonly: float weights[N * 2 R^2]
#endif
#ifndef VPLKIT_GLOBAL_WEIGHTS_BINDING_PARAMS
#define VPLKIT_GLOBAL_WEIGHTS_BINDING_PARAMS 5  // uniform block: global_weights_params
#endif
#ifndef VPLKIT_GLOBAL_WEIGHTS_LOCAL_SIZE
#define VPLKIT_GLOBAL_WEIGHTS_LOCAL_SIZE 64
#endif

#ifdef __cplusplus
namespace vplkit::gpu {
struct global_weights_params {
  light_params light;
#else
struct vplkit_global_weights_params {
  vplkit_light_params light;
#endif
  int resolution;   // R
  int regions;      // N
  int pixel_count;  // W H: subset entries outside [0, W H) are skipped
  int pad0;
  float dmin;
  float pad1;
  float pad2;
  float pad3;
};
#ifdef __cplusplus
static_assert(sizeof(global_weights_params) == 112);
}  // namespace vplkit::gpu
#endif

#endif  // VPLKIT_BUILDERS_GLOBAL_WEIGHTS_PARAMS_H
