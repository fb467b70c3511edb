// SPDX-License-Identifier: MIT
// vplkit kernel: builds a share tree on the GPU from float weights, in the layout share_tree.glsl
// samples: the GPU side of the vplkit::share_tree<float> build, bit for bit. One dispatch per
// level, leaves first (share_tree_build_params.h: level = log2(L), then log2(L) - 1 down to 0, a
// shader-storage barrier between them, share_tree_build_groups(level) groups each); nothing needs
// clearing first. Each inner node is one `precise` float add of its two children (in the C++
// order, left + right) and its share is vplkit_share_tree_share, integer arithmetic on the bits
// of the sums: every sum is 0 or a sum of normal floats, so neither flushing nor the division
// ulp of a GPU can change a bit. Rejected weights (negative, NaN, infinite) count as 0, like the
// C++ sanitized(); a float total past FLT_MAX leaves sums[1] = +Inf (the C++ build throws; the
// sampler reads it as empty).
// Layout: level l is the contiguous node range [2^l, 2^(l+1)); invocation t of the level writes
// node 2^l + t from children 2^(l+1) + 2t and + 2t + 1, so a warp reads one contiguous run of
// 2 x 32 floats and writes 32 contiguous sums and shares (coalesced). log2(L) + 1 dependent
// dispatches (20 at L = 2^19); the upper levels are a few groups each, latency-bound.
#include "vplkit/distribution/share_tree_build_params.h"
#include "vplkit/core/constants.glsl"
#include "vplkit/distribution/share_tree_share.glsl"

layout(local_size_x = VPLKIT_SHARE_TREE_BUILD_LOCAL_SIZE, local_size_y = 1, local_size_z = 1) in;

layout(std430, binding = VPLKIT_SHARE_TREE_BUILD_BINDING_WEIGHTS) readonly buffer vplkit_share_tree_build_weights_buffer {
  float vplkit_share_tree_build_weights[];
};
layout(std430, binding = VPLKIT_SHARE_TREE_BUILD_BINDING_SUMS) buffer vplkit_share_tree_build_sums_buffer {
  float vplkit_share_tree_build_sums[];
};
layout(std430, binding = VPLKIT_SHARE_TREE_BUILD_BINDING_SHARES) buffer vplkit_share_tree_build_shares_buffer {
  uint vplkit_share_tree_build_shares[];
};
layout(std140, binding = VPLKIT_SHARE_TREE_BUILD_BINDING_PARAMS) uniform vplkit_share_tree_build_uniforms {
  vplkit_share_tree_build_params vplkit_share_tree_build;
};

void main() {
  uint t = gl_GlobalInvocationID.x;
  uint level = vplkit_share_tree_build.level;
  uint leaves = vplkit_share_tree_build.leaves;
  if (t >= (1u << level)) return;
  if ((1u << level) == leaves) {
    // Leaf pass: the C++ weight_value of a valid weight, 0 for a rejected one and the padding.
    float w = t < vplkit_share_tree_build.n ? vplkit_share_tree_build_weights[t] : 0.0;
    bool valid = w > -vplkit_FLT_MIN && w <= vplkit_FLT_MAX;
    vplkit_share_tree_build_sums[leaves + t] = (valid && w >= vplkit_FLT_MIN) ? w : 0.0;
    if (t == 0u) {
      vplkit_share_tree_build_sums[0] = 0.0;
      vplkit_share_tree_build_shares[0] = 0u;
    }
    return;
  }
  uint k = (1u << level) + t;
  float left = vplkit_share_tree_build_sums[2u * k];
  float right = vplkit_share_tree_build_sums[2u * k + 1u];
  precise float sum = left + right;
  vplkit_share_tree_build_sums[k] = sum;
  vplkit_share_tree_build_shares[k] = vplkit_share_tree_share(left, right);
}
