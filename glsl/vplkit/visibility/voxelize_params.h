// SPDX-License-Identifier: MIT
// Interface of voxelize.comp, shared by the kernel (GLSL) and its hosts (C++,
// vplkit::gpu::voxelize_params): default bindings (distinct numbers, so that they also form a
// valid Vulkan set 0), local size, the std140 parameter block.
#ifndef VPLKIT_VISIBILITY_VOXELIZE_PARAMS_H
#define VPLKIT_VISIBILITY_VOXELIZE_PARAMS_H

#include "vplkit/core/params.h"

#ifndef VPLKIT_VOXELIZE_BINDING_POSITIONS
#define VPLKIT_VOXELIZE_BINDING_POSITIONS 0  // SSBO, readonly: vec4 positions[] (xyz)
#endif
#ifndef VPLKIT_VOXELIZE_BINDING_INDICES
#define VPLKIT_VOXELIZE_BINDING_INDICES 1  // SSBO, readonly: uint indices[3 T]
#endif
#ifndef VPLKIT_VOXELIZE_BINDING_WORDS
#define VPLKIT_VOXELIZE_BINDING_WORDS 2  // SSBO, read/write: uint words[ceil(nx ny nz / 32)]
#endif
#ifndef VPLKIT_VOXELIZE_BINDING_PARAMS
#define VPLKIT_VOXELIZE_BINDING_PARAMS 3  // uniform block: voxelize_params
#endif
#ifndef VPLKIT_VOXELIZE_LOCAL_SIZE
#define VPLKIT_VOXELIZE_LOCAL_SIZE 64
#endif

// Modes: 0 occupancy (the binary grid), 1 count, 2 fill (the triangle voxel grid's lists; see
// voxelize.comp). Modes 1 and 2 use the extra buffers below.
#ifndef VPLKIT_VOXELIZE_MODE
#define VPLKIT_VOXELIZE_MODE 0
#endif
#ifndef VPLKIT_VOXELIZE_BINDING_RANK
#define VPLKIT_VOXELIZE_BINDING_RANK 4  // SSBO, readonly: uint rank[word count]
#endif
#ifndef VPLKIT_VOXELIZE_BINDING_COUNTS
#define VPLKIT_VOXELIZE_BINDING_COUNTS 5  // SSBO: uint counts[occupied] (mode 2: cursors), zeroed first
#endif
#ifndef VPLKIT_VOXELIZE_BINDING_OFFSETS
#define VPLKIT_VOXELIZE_BINDING_OFFSETS 6  // SSBO, readonly: uint offsets[occupied + 1] (mode 2)
#endif
#ifndef VPLKIT_VOXELIZE_BINDING_ENTRIES
#define VPLKIT_VOXELIZE_BINDING_ENTRIES 7  // SSBO, writeonly: uint entries[offsets[occupied]] (mode 2)
#endif

#ifdef __cplusplus
namespace vplkit::gpu {
struct voxelize_params {
#else
struct vplkit_voxelize_params {
#endif
  vec4 bounds_min;   // xyz: the grid's bounds
  vec4 bounds_max;
  ivec4 resolution;  // xyz: nx, ny, nz
  uint triangle_count;
  float margin_voxels;  // the C++ default is 1e-4 (voxelize_default_margin)
  uint pad0;
  uint pad1;
};
#ifdef __cplusplus
static_assert(sizeof(voxelize_params) == 64);
}  // namespace vplkit::gpu
#endif

#endif  // VPLKIT_VISIBILITY_VOXELIZE_PARAMS_H
