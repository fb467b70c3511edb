// SPDX-License-Identifier: MIT
// Interface of prefix_sum.comp, shared by the kernel (GLSL) and its hosts (C++,
// vplkit::gpu::prefix_sum_params): default bindings (distinct numbers, so that they also form a
// valid Vulkan set 0), local size, elements per invocation, the std140 parameter block.
#ifndef VPLKIT_VISIBILITY_PREFIX_SUM_PARAMS_H
#define VPLKIT_VISIBILITY_PREFIX_SUM_PARAMS_H

#include "vplkit/core/params.h"

#ifndef VPLKIT_PREFIX_SUM_BINDING_INPUT
#define VPLKIT_PREFIX_SUM_BINDING_INPUT 0  // SSBO, readonly: uint in[count]
#endif
#ifndef VPLKIT_PREFIX_SUM_BINDING_OUTPUT
#define VPLKIT_PREFIX_SUM_BINDING_OUTPUT 1  // SSBO, writeonly: uint out[count (+ 1 with write_total)]
#endif
#ifndef VPLKIT_PREFIX_SUM_BINDING_CARRY
#define VPLKIT_PREFIX_SUM_BINDING_CARRY 2  // SSBO: uint carry[1], zeroed first; the total after the last chunk
#endif
#ifndef VPLKIT_PREFIX_SUM_BINDING_PARAMS
#define VPLKIT_PREFIX_SUM_BINDING_PARAMS 3  // uniform block: prefix_sum_params
#endif
#ifndef VPLKIT_PREFIX_SUM_LOCAL_SIZE
#define VPLKIT_PREFIX_SUM_LOCAL_SIZE 256  // invocations of the one work group
#endif
#ifndef VPLKIT_PREFIX_SUM_PER_INVOCATION
#define VPLKIT_PREFIX_SUM_PER_INVOCATION 64  // consecutive elements per invocation
#endif

#ifdef __cplusplus
namespace vplkit::gpu {
struct prefix_sum_params {
#else
struct vplkit_prefix_sum_params {
#endif
  uint count;        // elements
  uint begin;        // this dispatch's chunk: [begin, begin + LOCAL_SIZE * PER_INVOCATION)
  uint bit_count;    // 1: sum bitCount(in[i]) (the rank of an occupancy grid); 0: sum in[i]
  uint write_total;  // 1: also write out[count] (offsets: one entry more than counts)
};
#ifdef __cplusplus
static_assert(sizeof(prefix_sum_params) == 16);
}  // namespace vplkit::gpu
#endif

#endif  // VPLKIT_VISIBILITY_PREFIX_SUM_PARAMS_H
