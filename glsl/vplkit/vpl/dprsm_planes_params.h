// SPDX-License-Identifier: MIT
// Interface of dprsm_planes.comp, shared by the kernel (GLSL) and its hosts (C++,
// vplkit::gpu::dprsm_planes_params): default bindings, local size, the std140 parameter block, and
// the output record's layout (vplkit::dprsm_plane<float>, a std430 vec4).
#ifndef VPLKIT_VPL_DPRSM_PLANES_PARAMS_H
#define VPLKIT_VPL_DPRSM_PLANES_PARAMS_H

#include "vplkit/core/params.h"
#include "vplkit/vpl/light_params.h"

#ifndef VPLKIT_DPRSM_PLANES_BINDING_DPRSM
#define VPLKIT_DPRSM_PLANES_BINDING_DPRSM 0  // SSBO, readonly: vec4 dprsm[3 * 2 R^2] (position, normal, albedo)
#endif
#ifndef VPLKIT_DPRSM_PLANES_BINDING_PLANES
#define VPLKIT_DPRSM_PLANES_BINDING_PLANES 1  // SSBO, writeonly: vec4 planes[2 R^2] (dprsm_plane.glsl)
#endif
#ifndef VPLKIT_DPRSM_PLANES_BINDING_PARAMS
#define VPLKIT_DPRSM_PLANES_BINDING_PARAMS 2  // uniform block: dprsm_planes_params
#endif
#ifndef VPLKIT_DPRSM_PLANES_LOCAL_SIZE
#define VPLKIT_DPRSM_PLANES_LOCAL_SIZE 256
#endif

#ifdef __cplusplus
#include <vplkit/vpl/dprsm_plane.hpp>

#include <cstddef>
#include <type_traits>
namespace vplkit::gpu {
struct dprsm_planes_params {
  light_params light;
#else
struct vplkit_dprsm_planes_params {
  vplkit_light_params light;
#endif
  int resolution;  // R: 2 R^2 texels
  int pad0;
  int pad1;
  int pad2;
};
#ifdef __cplusplus
static_assert(sizeof(dprsm_planes_params) == 96);
// The kernel writes vec4(normal, height): the C++ record must be that std430 vec4.
static_assert(sizeof(dprsm_plane<float>) == 16 && offsetof(dprsm_plane<float>, height) == 12 &&
              std::is_standard_layout_v<dprsm_plane<float>>);
}  // namespace vplkit::gpu
#endif

#endif  // VPLKIT_VPL_DPRSM_PLANES_PARAMS_H
