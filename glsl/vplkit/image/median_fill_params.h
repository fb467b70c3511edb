// SPDX-License-Identifier: MIT
// Interface of median_fill.comp, shared by the kernel (GLSL) and its hosts (C++,
// vplkit::gpu::median_fill_params): default bindings, local size, the std140 parameter block.
#ifndef VPLKIT_IMAGE_MEDIAN_FILL_PARAMS_H
#define VPLKIT_IMAGE_MEDIAN_FILL_PARAMS_H

#include "vplkit/core/params.h"

#ifndef VPLKIT_MEDIAN_FILL_BINDING_IN
#define VPLKIT_MEDIAN_FILL_BINDING_IN 0  // SSBO, readonly: float in[2 R^2]
#endif
#ifndef VPLKIT_MEDIAN_FILL_BINDING_OUT
#define VPLKIT_MEDIAN_FILL_BINDING_OUT 1  // SSBO, writeonly: float out[2 R^2]
#endif
#ifndef VPLKIT_MEDIAN_FILL_BINDING_PARAMS
#define VPLKIT_MEDIAN_FILL_BINDING_PARAMS 2  // uniform block: median_fill_params
#endif
#ifndef VPLKIT_MEDIAN_FILL_LOCAL_SIZE
#define VPLKIT_MEDIAN_FILL_LOCAL_SIZE 8  // work group LOCAL_SIZE x LOCAL_SIZE x 1
#endif

#ifdef __cplusplus
namespace vplkit::gpu {
struct median_fill_params {
#else
struct vplkit_median_fill_params {
#endif
  int resolution;  // R
  int pad0;
  int pad1;
  int pad2;
};
#ifdef __cplusplus
static_assert(sizeof(median_fill_params) == 16);
}  // namespace vplkit::gpu
#endif

#endif  // VPLKIT_IMAGE_MEDIAN_FILL_PARAMS_H
