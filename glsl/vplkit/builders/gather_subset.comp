// SPDX-License-Identifier: MIT
// vplkit kernel: stratified gather subset (docs/math.md section 4), one invocation per stratum: the
// GPU side of vplkit::stratified_gather_subset for one rectangle -- the whole image for the global
// weights, region i with stream_offset = i * count for the local ones (one dispatch per region).
// Exact: the C++ pixels (integer arithmetic, one correctly rounded float product per coordinate,
// the bit-exact counter_rng). Stratum k always writes pixels[out_offset + k], -1 when dropped
// (the C++ list leaves it out; global_weights.comp skips -1: the same weights). Interface:
// gather_subset_params.h, shared with the C++ host (make_gather_subset_params fills it). Dispatch:
// ceil(count / LOCAL_SIZE) groups. docs/glsl/builders.md.
#include "vplkit/builders/gather_subset.glsl"
#include "vplkit/builders/gather_subset_params.h"
#include "vplkit/core/gather_point.glsl"

layout(local_size_x = VPLKIT_GATHER_SUBSET_LOCAL_SIZE, local_size_y = 1, local_size_z = 1) in;

layout(std430, binding = VPLKIT_GATHER_SUBSET_BINDING_GBUFFER) readonly buffer vplkit_gather_subset_gbuffer_buffer {
  vec4 vplkit_gather_subset_gbuffer[];
};
layout(std430, binding = VPLKIT_GATHER_SUBSET_BINDING_PIXELS) writeonly buffer vplkit_gather_subset_pixels_buffer {
  int vplkit_gather_subset_pixels[];
};
layout(std140, binding = VPLKIT_GATHER_SUBSET_BINDING_PARAMS) uniform vplkit_gather_subset_uniforms {
  vplkit_gather_subset_params vplkit_gather_subset;
};

vplkit_gather_point vplkit_load_gather_point(int pixel) {
  return vplkit_unpack_gather_point(vplkit_gather_subset_gbuffer[3 * pixel], vplkit_gather_subset_gbuffer[3 * pixel + 1],
                                    vplkit_gather_subset_gbuffer[3 * pixel + 2]);
}

void main() {
  int k = int(gl_GlobalInvocationID.x);
  vplkit_gather_subset_params p = vplkit_gather_subset;
  if (k >= p.count) return;
  vplkit_gather_subset_pixels[p.out_offset + uint(k)] = vplkit_gather_subset_pick(
      vplkit_gbuffer_view(p.image_width, p.image_height), vplkit_pixel_rect(p.x0, p.y0, p.width, p.height),
      vplkit_gather_subset_grid_shape(p.count, p.columns, p.rows, p.last_columns), k, p.seed, p.stream_offset,
      p.max_attempts);
}
