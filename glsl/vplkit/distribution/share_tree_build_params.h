// SPDX-License-Identifier: MIT
// Interface of share_tree_build.comp, shared by the kernel (GLSL) and its hosts (C++, namespace
// vplkit::gpu): default bindings, local size, the std140 parameter block, and the host's dispatch
// plan (share_tree_build_groups).
#ifndef VPLKIT_DISTRIBUTION_SHARE_TREE_BUILD_PARAMS_H
#define VPLKIT_DISTRIBUTION_SHARE_TREE_BUILD_PARAMS_H

#include "vplkit/core/params.h"

#ifndef VPLKIT_SHARE_TREE_BUILD_BINDING_WEIGHTS
#define VPLKIT_SHARE_TREE_BUILD_BINDING_WEIGHTS 0  // SSBO, readonly: float weights[n]
#endif
#ifndef VPLKIT_SHARE_TREE_BUILD_BINDING_SUMS
#define VPLKIT_SHARE_TREE_BUILD_BINDING_SUMS 1  // SSBO: float sums[2 L]
#endif
#ifndef VPLKIT_SHARE_TREE_BUILD_BINDING_SHARES
#define VPLKIT_SHARE_TREE_BUILD_BINDING_SHARES 2  // SSBO: uint shares[L]
#endif
#ifndef VPLKIT_SHARE_TREE_BUILD_BINDING_PARAMS
#define VPLKIT_SHARE_TREE_BUILD_BINDING_PARAMS 3  // uniform block: share_tree_build_params
#endif
#ifndef VPLKIT_SHARE_TREE_BUILD_LOCAL_SIZE
#define VPLKIT_SHARE_TREE_BUILD_LOCAL_SIZE 256  // invocations per work group
#endif

// level: the level being written. level = log2(L) is the leaf pass (weights -> sums[L .. 2L),
// sanitized and flushed; also sums[0] = 0 and shares[0] = 0); level l < log2(L) writes the inner
// nodes [2^l, 2^(l+1)) from the level below. The host dispatches level = log2(L), log2(L) - 1,
// ..., 0 in that order, with a shader-storage barrier between them.
#ifdef __cplusplus
namespace vplkit::gpu {
struct share_tree_build_params {
#else
struct vplkit_share_tree_build_params {
#endif
  uint n;       // weights
  uint leaves;  // L: the smallest power of two >= n (share_tree_leaf_count)
  uint level;
  uint pad0;
};
#ifdef __cplusplus
static_assert(sizeof(share_tree_build_params) == 16);

// Work groups of the dispatch for `level` (its 2^level nodes, at least one group).
inline uint share_tree_build_groups(uint level, uint local_size = VPLKIT_SHARE_TREE_BUILD_LOCAL_SIZE) {
  const std::uint64_t nodes = std::uint64_t(1) << level;
  return uint((nodes + local_size - 1) / local_size);
}
}  // namespace vplkit::gpu
#endif

#endif  // VPLKIT_DISTRIBUTION_SHARE_TREE_BUILD_PARAMS_H
