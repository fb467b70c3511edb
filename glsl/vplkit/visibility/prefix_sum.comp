// SPDX-License-Identifier: MIT
// vplkit kernel: exclusive prefix sum of a uint array, in chunks (the GPU side of
// vplkit::voxel_occupancy_rank and of the triangle voxel grid's offsets; voxelize.comp's modes).
//   out[i] = sum of f(in[j]) for j < i, for i < count; and, with write_total, out[count] = the sum
//   of all, where f(w) = w, or bitCount(w) in bit-count mode (rank of an occupancy grid).
// Interface: prefix_sum_params.h, shared with the C++ host. Dispatch: ONE work group, once per
// chunk of LOCAL_SIZE * PER_INVOCATION elements, in order (begin = 0, chunk, 2 chunk, ...), with
// glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT) between: each chunk starts from the carry the
// previous one left (the host zeroes the carry first). Why chunks of one work group: simple and
// exact (integer sums, any order), and every loop of an invocation stays at 2 * PER_INVOCATION +
// LOCAL_SIZE iterations, far below llvmpipe's loop budget (docs/glsl.md). A 128^3 occupancy (65536
// words) takes 4 dispatches. Sums must stay below 2^32 (the host checks the total).
#include "vplkit/visibility/prefix_sum_params.h"

layout(local_size_x = VPLKIT_PREFIX_SUM_LOCAL_SIZE, local_size_y = 1, local_size_z = 1) in;

layout(std430, binding = VPLKIT_PREFIX_SUM_BINDING_INPUT) readonly buffer vplkit_prefix_sum_input_buffer {
  uint vplkit_prefix_sum_in[];
};
layout(std430, binding = VPLKIT_PREFIX_SUM_BINDING_OUTPUT) writeonly buffer vplkit_prefix_sum_output_buffer {
  uint vplkit_prefix_sum_out[];
};
layout(std430, binding = VPLKIT_PREFIX_SUM_BINDING_CARRY) buffer vplkit_prefix_sum_carry_buffer {
  uint vplkit_prefix_sum_carry[];
};
layout(std140, binding = VPLKIT_PREFIX_SUM_BINDING_PARAMS) uniform vplkit_prefix_sum_uniforms {
  vplkit_prefix_sum_params vplkit_prefix_sum;
};

shared uint vplkit_prefix_sum_partial[VPLKIT_PREFIX_SUM_LOCAL_SIZE];

uint vplkit_prefix_sum_value(uint i) {
  uint w = vplkit_prefix_sum_in[i];
  return vplkit_prefix_sum.bit_count != 0u ? uint(bitCount(w)) : w;
}

void main() {
  uint lane = gl_LocalInvocationIndex;
  uint n = vplkit_prefix_sum.count;
  uint first = vplkit_prefix_sum.begin + lane * uint(VPLKIT_PREFIX_SUM_PER_INVOCATION);
  uint sum = 0u;
  for (uint k = 0u; k < uint(VPLKIT_PREFIX_SUM_PER_INVOCATION); ++k)
    if (first + k < n) sum += vplkit_prefix_sum_value(first + k);
  vplkit_prefix_sum_partial[lane] = sum;
  memoryBarrierShared();
  barrier();
  if (lane == 0u) {
    // Exclusive scan of the lanes' sums, starting from the carry of the previous chunks.
    uint running = vplkit_prefix_sum_carry[0];
    for (uint l = 0u; l < uint(VPLKIT_PREFIX_SUM_LOCAL_SIZE); ++l) {
      uint s = vplkit_prefix_sum_partial[l];
      vplkit_prefix_sum_partial[l] = running;
      running += s;
    }
    vplkit_prefix_sum_carry[0] = running;
    uint end = vplkit_prefix_sum.begin + uint(VPLKIT_PREFIX_SUM_LOCAL_SIZE * VPLKIT_PREFIX_SUM_PER_INVOCATION);
    if (vplkit_prefix_sum.write_total != 0u && end >= n) vplkit_prefix_sum_out[n] = running;
  }
  memoryBarrierShared();
  barrier();
  uint prefix = vplkit_prefix_sum_partial[lane];
  for (uint k = 0u; k < uint(VPLKIT_PREFIX_SUM_PER_INVOCATION); ++k) {
    if (first + k >= n) break;
    vplkit_prefix_sum_out[first + k] = prefix;
    prefix += vplkit_prefix_sum_value(first + k);
  }
}
