// vplkit kernel: stratified gather subset (DESIGN 3.4), one invocation per stratum: the GPU side of
// vplkit::stratified_gather_subset (gather_subset.hpp) for one rectangle -- the whole image for the
// global CDF, region i with stream_offset = i * count for the local CDFs (dispatch once per region,
// writing at out_offset = the region's first entry). Exact: the same pixels as the C++ (integer
// arithmetic and one correctly rounded float product per coordinate, the bit-exact counter_rng).
// Difference in layout: the C++ list leaves dropped strata (all max_attempts picks background) out;
// here stratum k always writes pixels[out_offset + k], -1 when dropped, which
// global_weights.comp skips: the same weights.
//
// Interface (no #version; the host prepends it and its #defines):
//   VPLKIT_GATHER_SUBSET_BINDING_GBUFFER  (default 0) SSBO, std430, readonly: vec4 gbuffer[3 W H]
//                                         (position, normal, albedo of pixel p at 3p .. 3p + 2;
//                                         only the validity of a pixel is read)
//   VPLKIT_GATHER_SUBSET_BINDING_PIXELS   (default 1) SSBO, std430, writeonly: int pixels[]
//   VPLKIT_GATHER_SUBSET_BINDING_PARAMS   (default 0) uniform block, std140:
//     ivec4 rect   (x0, y0, width, height) inside the W x H image (validated by the host)
//     ivec4 shape  (count, columns, rows, last_columns) = the C++ gather_subset_grid(rect, count)
//     uvec4 rng    (seed, stream_offset, max_attempts, out_offset)
//     ivec4 image  (W, H)
//   VPLKIT_GATHER_SUBSET_LOCAL_SIZE       (default 64)
// Dispatch: ceil(count / LOCAL_SIZE) groups.
#include "vplkit/builders/gather_subset.glsl"
#include "vplkit/core/gather_point.glsl"

#ifndef VPLKIT_GATHER_SUBSET_BINDING_GBUFFER
#define VPLKIT_GATHER_SUBSET_BINDING_GBUFFER 0
#endif
#ifndef VPLKIT_GATHER_SUBSET_BINDING_PIXELS
#define VPLKIT_GATHER_SUBSET_BINDING_PIXELS 1
#endif
#ifndef VPLKIT_GATHER_SUBSET_BINDING_PARAMS
#define VPLKIT_GATHER_SUBSET_BINDING_PARAMS 0
#endif
#ifndef VPLKIT_GATHER_SUBSET_LOCAL_SIZE
#define VPLKIT_GATHER_SUBSET_LOCAL_SIZE 64
#endif

layout(local_size_x = VPLKIT_GATHER_SUBSET_LOCAL_SIZE, local_size_y = 1, local_size_z = 1) in;

layout(std430, binding = VPLKIT_GATHER_SUBSET_BINDING_GBUFFER) readonly buffer vplkit_gather_subset_gbuffer_buffer {
  vec4 vplkit_gather_subset_gbuffer[];
};
layout(std430, binding = VPLKIT_GATHER_SUBSET_BINDING_PIXELS) writeonly buffer vplkit_gather_subset_pixels_buffer {
  int vplkit_gather_subset_pixels[];
};
layout(std140, binding = VPLKIT_GATHER_SUBSET_BINDING_PARAMS) uniform vplkit_gather_subset_block {
  ivec4 vplkit_gather_subset_rect;
  ivec4 vplkit_gather_subset_shape;
  uvec4 vplkit_gather_subset_rng;
  ivec4 vplkit_gather_subset_image;
};

vplkit_gather_point vplkit_load_gather_point(int pixel) {
  return vplkit_gather_point(vplkit_gather_subset_gbuffer[3 * pixel].xyz, vplkit_gather_subset_gbuffer[3 * pixel + 1].xyz,
                             vplkit_gather_subset_gbuffer[3 * pixel + 2].xyz);
}

void main() {
  int k = int(gl_GlobalInvocationID.x);
  ivec4 s = vplkit_gather_subset_shape;
  if (k >= s.x) return;
  ivec4 r = vplkit_gather_subset_rect;
  uvec4 q = vplkit_gather_subset_rng;
  vplkit_gather_subset_pixels[q.w + uint(k)] = vplkit_gather_subset_pick(
      vplkit_gbuffer_view(vplkit_gather_subset_image.x, vplkit_gather_subset_image.y), vplkit_pixel_rect(r.x, r.y, r.z, r.w),
      vplkit_gather_subset_grid_shape(s.x, s.y, s.z, s.w), k, q.x, q.y, int(q.z));
}
