// vplkit kernel: stratified gather subset (DESIGN 3.4), one invocation per stratum: the GPU side of
// vplkit::stratified_gather_subset (gather_subset.hpp) for one rectangle -- the whole image for the
// global CDF, region i with stream_offset = i * count for the local CDFs (dispatch once per region,
// writing at out_offset = the region's first entry). Exact: the same pixels as the C++ (integer
// arithmetic and one correctly rounded float product per coordinate, the bit-exact counter_rng).
// Difference in layout: the C++ list leaves dropped strata (all max_attempts picks background) out;
// here stratum k always writes pixels[out_offset + k], -1 when dropped, which
// global_weights.comp skips: the same weights.
//
// Interface (no #version; the host prepends it and its #defines): gather_subset_params.h, shared
// with the C++ host -- bindings (VPLKIT_GATHER_SUBSET_BINDING_*: the G-buffer as vec4 gbuffer[3 W H]
// of which only the validity of a pixel is read; int pixels[] written), the local size and the
// std140 block vplkit_gather_subset_params (the rectangle inside the W x H image, validated by the
// host; the grid shape of the C++ gather_subset_grid(rect, count); seed, stream_offset,
// max_attempts, out_offset).
// Dispatch: ceil(count / LOCAL_SIZE) groups.
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
  return vplkit_gather_point(vplkit_gather_subset_gbuffer[3 * pixel].xyz, vplkit_gather_subset_gbuffer[3 * pixel + 1].xyz,
                             vplkit_gather_subset_gbuffer[3 * pixel + 2].xyz);
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
