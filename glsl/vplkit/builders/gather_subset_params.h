// SPDX-License-Identifier: MIT
// Interface of gather_subset.comp, shared by the kernel (GLSL) and its hosts (C++,
// vplkit::gpu::gather_subset_params): default bindings, local size, the std140 parameter block.
#ifndef VPLKIT_BUILDERS_GATHER_SUBSET_PARAMS_H
#define VPLKIT_BUILDERS_GATHER_SUBSET_PARAMS_H

#include "vplkit/core/params.h"

#ifndef VPLKIT_GATHER_SUBSET_BINDING_GBUFFER
#define VPLKIT_GATHER_SUBSET_BINDING_GBUFFER 0  // SSBO, readonly: vec4 gbuffer[3 W H]
#endif
#ifndef VPLKIT_GATHER_SUBSET_BINDING_PIXELS
#define VPLKIT_GATHER_SUBSET_BINDING_PIXELS 1  // SSBO, writeonly: int pixels[]
#endif
#ifndef VPLKIT_GATHER_SUBSET_BINDING_PARAMS
#define VPLKIT_GATHER_SUBSET_BINDING_PARAMS 2  // uniform block: gather_subset_params
#endif
#ifndef VPLKIT_GATHER_SUBSET_LOCAL_SIZE
#define VPLKIT_GATHER_SUBSET_LOCAL_SIZE 64
#endif

#ifdef __cplusplus
#include <vplkit/builders/gather_subset.hpp>
namespace vplkit::gpu {
struct gather_subset_params {
#else
struct vplkit_gather_subset_params {
#endif
  int x0;  // the rectangle, inside the W x H image (validated by the host)
  int y0;
  int width;
  int height;
  int count;  // the C++ gather_subset_grid(rect, count): count, columns, rows, last_columns
  int columns;
  int rows;
  int last_columns;
  uint seed;           // counter_rng seed; stratum k uses stream stream_offset + k
  uint stream_offset;
  int max_attempts;
  uint out_offset;     // stratum k writes pixels[out_offset + k]
  int image_width;     // W, H
  int image_height;
  int pad0;
  int pad1;
};
#ifdef __cplusplus
static_assert(sizeof(gather_subset_params) == 64);

// The parameters of one rectangle's dispatch: the strata of gather_subset_grid(rect, count), the
// streams of stratified_gather_subset(gbuffer, rect, count, seed, stream_offset, max_attempts).
template <class T>
inline gather_subset_params make_gather_subset_params(const gbuffer_view<T>& gbuffer, const pixel_rect& rect,
                                                      int count, uint seed, uint stream_offset, int max_attempts,
                                                      uint out_offset) {
  const gather_subset_grid_shape shape = gather_subset_grid(rect, count);
  gather_subset_params p{};
  p.x0 = rect.x0;
  p.y0 = rect.y0;
  p.width = rect.width;
  p.height = rect.height;
  p.count = shape.count;
  p.columns = shape.columns;
  p.rows = shape.rows;
  p.last_columns = shape.last_columns;
  p.seed = seed;
  p.stream_offset = stream_offset;
  p.max_attempts = max_attempts;
  p.out_offset = out_offset;
  p.image_width = gbuffer.width;
  p.image_height = gbuffer.height;
  return p;
}
}  // namespace vplkit::gpu
#endif

#endif  // VPLKIT_BUILDERS_GATHER_SUBSET_PARAMS_H
