// SPDX-License-Identifier: MIT
// Interface of tile_blocks.comp, shared by the kernel (GLSL) and its hosts (C++,
// vplkit::gpu::tile_blocks_params): default bindings, local size, the std140 parameter block.
#ifndef VPLKIT_BUILDERS_TILE_BLOCKS_PARAMS_H
#define VPLKIT_BUILDERS_TILE_BLOCKS_PARAMS_H

#include "vplkit/core/params.h"
#include "vplkit/vpl/light_params.h"

#ifndef VPLKIT_TILE_BLOCKS_BINDING_DPRSM
#define VPLKIT_TILE_BLOCKS_BINDING_DPRSM 0  // SSBO, readonly: vec4 dprsm[3 * 2 R^2]
#endif
#ifndef VPLKIT_TILE_BLOCKS_BINDING_SHARES
#define VPLKIT_TILE_BLOCKS_BINDING_SHARES 1  // SSBO, writeonly: float shares[2 R^2]
#endif
#ifndef VPLKIT_TILE_BLOCKS_BINDING_PROXIES
#define VPLKIT_TILE_BLOCKS_BINDING_PROXIES 2  // SSBO, writeonly: vec4 proxies[3 * blocks]
#endif
#ifndef VPLKIT_TILE_BLOCKS_BINDING_PARAMS
#define VPLKIT_TILE_BLOCKS_BINDING_PARAMS 3  // uniform block: tile_blocks_params
#endif
#ifndef VPLKIT_TILE_BLOCKS_LOCAL_SIZE
#define VPLKIT_TILE_BLOCKS_LOCAL_SIZE 64
#endif

#ifdef __cplusplus
namespace vplkit::gpu {
struct tile_blocks_params {
  light_params light;
#else
struct vplkit_tile_blocks_params {
  vplkit_light_params light;
#endif
  int resolution;  // R
  int block;       // B >= 1: texels per block side
  int pad0;
  int pad1;
};
#ifdef __cplusplus
static_assert(sizeof(tile_blocks_params) == sizeof(light_params) + 16);
}  // namespace vplkit::gpu
#endif

#endif  // VPLKIT_BUILDERS_TILE_BLOCKS_PARAMS_H
