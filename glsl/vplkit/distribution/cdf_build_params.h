// SPDX-License-Identifier: MIT
// Interface of cdf_build.comp, shared by the kernel (GLSL) and its hosts (C++, namespace
// vplkit::gpu): default bindings, local size and items per invocation, the std140 parameter block,
// and the std430 records of the blocks scratch buffer and the per-distribution info the host reads.
#ifndef VPLKIT_DISTRIBUTION_CDF_BUILD_PARAMS_H
#define VPLKIT_DISTRIBUTION_CDF_BUILD_PARAMS_H

#include "vplkit/core/params.h"

#ifndef VPLKIT_CDF_BUILD_BINDING_WEIGHTS
#define VPLKIT_CDF_BUILD_BINDING_WEIGHTS 0  // SSBO, readonly: float weights[D n]
#endif
#ifndef VPLKIT_CDF_BUILD_BINDING_CDF
#define VPLKIT_CDF_BUILD_BINDING_CDF 1  // SSBO: float cdf[D (n + 1)]
#endif
#ifndef VPLKIT_CDF_BUILD_BINDING_GUIDE
#define VPLKIT_CDF_BUILD_BINDING_GUIDE 2  // SSBO: uint guide[D (m + 1)]
#endif
#ifndef VPLKIT_CDF_BUILD_BINDING_BLOCKS
#define VPLKIT_CDF_BUILD_BINDING_BLOCKS 3  // SSBO, scratch: cdf_build_block blocks[D B]
#endif
#ifndef VPLKIT_CDF_BUILD_BINDING_INFO
#define VPLKIT_CDF_BUILD_BINDING_INFO 4  // SSBO: cdf_build_info info[D]
#endif
#ifndef VPLKIT_CDF_BUILD_BINDING_PARAMS
#define VPLKIT_CDF_BUILD_BINDING_PARAMS 5  // uniform block: cdf_build_params
#endif
#ifndef VPLKIT_CDF_BUILD_LOCAL_SIZE
#define VPLKIT_CDF_BUILD_LOCAL_SIZE 256  // invocations per work group
#endif
#ifndef VPLKIT_CDF_BUILD_ITEMS
#define VPLKIT_CDF_BUILD_ITEMS 4  // weights per invocation
#endif
// Weights per block: B = ceil(n / VPLKIT_CDF_BUILD_BLOCK) blocks per distribution.
#define VPLKIT_CDF_BUILD_BLOCK (VPLKIT_CDF_BUILD_LOCAL_SIZE * VPLKIT_CDF_BUILD_ITEMS)

// The accumulator: double, or (hi, lo) floats with VPLKIT_CDF_BUILD_FLOAT_FLOAT (8 bytes either
// way). The C++ side reads the default kernel's double.
#if defined(__cplusplus) || !defined(VPLKIT_CDF_BUILD_FLOAT_FLOAT)
#define VPLKIT_CDF_BUILD_ACC double
#else
#define VPLKIT_CDF_BUILD_ACC vec2
#endif

#ifdef __cplusplus
namespace vplkit::gpu {
struct cdf_build_params {
#else
struct vplkit_cdf_build_params {
#endif
  uint n;     // weights per distribution
  uint pass;  // 1..6 (unless the kernel was compiled with VPLKIT_CDF_BUILD_PASS)
  uint pad0;
  uint pad1;
};

// Per block of one distribution (scratch). sum / offset: the accumulator; max_bits /
// prefix_max_bits: float bits of the block's largest normalised value and of the largest one in
// all earlier blocks (non-negative floats order like their bits).
#ifdef __cplusplus
struct cdf_build_block {
#else
struct vplkit_cdf_build_block {
#endif
  VPLKIT_CDF_BUILD_ACC sum;
  VPLKIT_CDF_BUILD_ACC offset;
  uint max_bits;
  uint prefix_max_bits;
  uint zeroed;
  uint pad;
};

// Per distribution: sum (the accumulator, internal), total (the sum rounded to float: the
// descriptor's total; +Inf past the float range), zeroed (weights that were negative, NaN or Inf).
#ifdef __cplusplus
struct cdf_build_info {
#else
struct vplkit_cdf_build_info {
#endif
  VPLKIT_CDF_BUILD_ACC sum;
  float total;
  uint zeroed;
};
#ifdef __cplusplus
static_assert(sizeof(cdf_build_params) == 16);
static_assert(sizeof(cdf_build_block) == 32);
static_assert(sizeof(cdf_build_info) == 16);

// Whether the host must dispatch `pass` (1..6) for n weights with `block` = LOCAL_SIZE x ITEMS
// weights per block. Passes 1, 3 and 5 always. Passes 2 and 4 scan the block records only when
// there are more blocks than one chunk of `block` of them (n > 2^20 with the defaults); otherwise
// passes 3 and 5 do that work themselves and 2 and 4 return at once. Pass 5 writes the guide, so
// pass 6 (the same guide again) is never needed: 3 dependent dispatches up to 2^20 weights, 5
// above. Dispatching every pass gives the same output.
inline bool cdf_build_pass_needed(uint pass, uint n, uint block = VPLKIT_CDF_BUILD_BLOCK) {
  if (pass == 6) return false;
  if (pass != 2 && pass != 4) return true;
  const std::uint64_t blocks = (std::uint64_t(n) + block - 1) / block;
  return blocks > block;
}
}  // namespace vplkit::gpu
#endif

#endif  // VPLKIT_DISTRIBUTION_CDF_BUILD_PARAMS_H
