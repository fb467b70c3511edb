// SPDX-License-Identifier: MIT
// Interface of gbg_finish.comp, shared by the kernel (GLSL) and its hosts (C++,
// vplkit::gpu::gbg_finish_params): default bindings, local size, the std140 parameter block. The
// stats counters are gbg_accumulate_params.h's.
#ifndef VPLKIT_BUILDERS_GBG_FINISH_PARAMS_H
#define VPLKIT_BUILDERS_GBG_FINISH_PARAMS_H

#include "vplkit/builders/gbg_accumulate_params.h"
#include "vplkit/core/params.h"
#include "vplkit/vpl/light_params.h"

#ifndef VPLKIT_GBG_FINISH_BINDING_ACC
#define VPLKIT_GBG_FINISH_BINDING_ACC 0  // SSBO, readonly: uint acc[2 * 2 R^2]
#endif
#ifndef VPLKIT_GBG_FINISH_BINDING_STATS
#define VPLKIT_GBG_FINISH_BINDING_STATS 1  // SSBO: gbg_accumulate.comp's stats
#endif
#ifndef VPLKIT_GBG_FINISH_BINDING_DPRSM
#define VPLKIT_GBG_FINISH_BINDING_DPRSM 2  // SSBO, readonly: vec4 dprsm[3 * 2 R^2]
#endif
#ifndef VPLKIT_GBG_FINISH_BINDING_WEIGHTS
#define VPLKIT_GBG_FINISH_BINDING_WEIGHTS 3  // SSBO, writeonly: float weights[2 R^2]
#endif
#ifndef VPLKIT_GBG_FINISH_BINDING_PARAMS
#define VPLKIT_GBG_FINISH_BINDING_PARAMS 4  // uniform block: gbg_finish_params
#endif
#ifndef VPLKIT_GBG_FINISH_LOCAL_SIZE
#define VPLKIT_GBG_FINISH_LOCAL_SIZE 8  // work group LOCAL_SIZE x LOCAL_SIZE x 1
#endif

#ifdef __cplusplus
namespace vplkit::gpu {
struct gbg_finish_params {
  light_params light;
#else
struct vplkit_gbg_finish_params {
  vplkit_light_params light;
#endif
  int resolution;  // R
  int n_dirs;
  int fill_holes;  // 0 / 1
  int pad0;
  float inv_scale;  // 1 / gbg_accumulate_params::scale
  float pad1;
  float pad2;
  float pad3;
};
#ifdef __cplusplus
static_assert(sizeof(gbg_finish_params) == 112);
}  // namespace vplkit::gpu
#endif

#endif  // VPLKIT_BUILDERS_GBG_FINISH_PARAMS_H
