// SPDX-License-Identifier: MIT
// Interface of tile_weights.comp, shared by the kernel (GLSL) and its hosts (C++,
// vplkit::gpu::tile_weights_params): default bindings, local size, the std140 parameter block.
#ifndef VPLKIT_BUILDERS_TILE_WEIGHTS_PARAMS_H
#define VPLKIT_BUILDERS_TILE_WEIGHTS_PARAMS_H

#include "vplkit/core/params.h"

#ifndef VPLKIT_TILE_WEIGHTS_BINDING_GBUFFER
#define VPLKIT_TILE_WEIGHTS_BINDING_GBUFFER 0  // SSBO, readonly: vec4 gbuffer[3 * W H]
#endif
#ifndef VPLKIT_TILE_WEIGHTS_BINDING_SUBSET
#define VPLKIT_TILE_WEIGHTS_BINDING_SUBSET 1  // SSBO, readonly: int pixels[] (the tiles' points)
#endif
#ifndef VPLKIT_TILE_WEIGHTS_BINDING_OFFSETS
#define VPLKIT_TILE_WEIGHTS_BINDING_OFFSETS 2  // SSBO, readonly: uint offsets[tiles + 1]
#endif
#ifndef VPLKIT_TILE_WEIGHTS_BINDING_PROXIES
#define VPLKIT_TILE_WEIGHTS_BINDING_PROXIES 3  // SSBO, readonly: vec4 proxies[3 * blocks] (tile_blocks.comp's)
#endif
#ifndef VPLKIT_TILE_WEIGHTS_BINDING_WEIGHTS
#define VPLKIT_TILE_WEIGHTS_BINDING_WEIGHTS 4  // SSBO, writeonly: float weights[tiles * blocks]
#endif
#ifndef VPLKIT_TILE_WEIGHTS_BINDING_PARAMS
#define VPLKIT_TILE_WEIGHTS_BINDING_PARAMS 5  // uniform block: tile_weights_params
#endif
#ifndef VPLKIT_TILE_WEIGHTS_LOCAL_SIZE
#define VPLKIT_TILE_WEIGHTS_LOCAL_SIZE 64
#endif

#ifdef __cplusplus
namespace vplkit::gpu {
struct tile_weights_params {
#else
struct vplkit_tile_weights_params {
#endif
  int blocks;       // 2 P^2
  int tiles;
  int pixel_count;  // W H: subset entries outside [0, W H) are skipped
  float dmin;
};
#ifdef __cplusplus
static_assert(sizeof(tile_weights_params) == 16);
}  // namespace vplkit::gpu
#endif

#endif  // VPLKIT_BUILDERS_TILE_WEIGHTS_PARAMS_H
