// vplkit kernel: global weights (BRSM; DESIGN 3.4), one invocation per (texel, region): the GPU
// side of vplkit::build_global_weights and, with N regions, of vplkit::build_local_weights
// (global_weights.hpp, local_weights.hpp). Per texel it runs vplkit_global_weight_texel (global_weights.glsl):
// the mean over the region's subset of luminance(vpl_contribution), no visibility, summed in float
// in the subset's order and multiplied by 1 / |S| -- the C++ arithmetic statement for statement.
//
// Interface (no #version; the host prepends it and its #defines): global_weights_params.h, shared
// with the C++ host -- bindings (VPLKIT_GLOBAL_WEIGHTS_BINDING_*), the local size and the std140
// block vplkit_global_weights_params (light, R, N regions, pixel count W H, dmin). Buffers:
//   GBUFFER  vec4 gbuffer[3 W H]: position, normal, albedo of pixel p at 3p, 3p + 1, 3p + 2
//   DPRSM    vec4 dprsm[3 * 2 R^2], likewise per texel
//   SUBSET   int pixels[]: the N subsets back to back, flat pixel indices y * W + x; -1 (a dropped
//            stratum of gather_subset.comp), an index outside the image or a background pixel is
//            skipped and not counted (the C++ drops background entries and throws for indices
//            outside the image)
//   OFFSETS  uint offsets[N + 1]: region i's subset is pixels[offsets[i] .. offsets[i+1])
//   WEIGHTS  float weights[N * 2 R^2], region-major (weights[i * 2 R^2 + t], the layout of
//            build_local_weights; N = 1: global)
// Dispatch: (ceil(2 R^2 / LOCAL_SIZE), N, 1); invocation (texel, region).
// llvmpipe runs at most 65535 loop iterations per invocation: keep each |S_i| below ~65000 there.
// Precision against the C++ float build: the per-term float error of luminance(vpl_contribution)
// (a few ulps, FMA contraction and the GPU's normalisation) accumulated over |S| terms in the same
// order: measured in tests/parity/parity_builders_test.cpp (docs/glsl/builders.md).
#include "vplkit/builders/global_weights.glsl"
#include "vplkit/builders/global_weights_params.h"
#include "vplkit/core/gather_point.glsl"

layout(local_size_x = VPLKIT_GLOBAL_WEIGHTS_LOCAL_SIZE, local_size_y = 1, local_size_z = 1) in;

layout(std430, binding = VPLKIT_GLOBAL_WEIGHTS_BINDING_GBUFFER) readonly buffer vplkit_global_weights_gbuffer_buffer {
  vec4 vplkit_global_weights_gbuffer[];
};
layout(std430, binding = VPLKIT_GLOBAL_WEIGHTS_BINDING_DPRSM) readonly buffer vplkit_global_weights_dprsm_buffer {
  vec4 vplkit_global_weights_dprsm[];
};
layout(std430, binding = VPLKIT_GLOBAL_WEIGHTS_BINDING_SUBSET) readonly buffer vplkit_global_weights_subset_buffer {
  int vplkit_global_weights_subset[];
};
layout(std430, binding = VPLKIT_GLOBAL_WEIGHTS_BINDING_OFFSETS) readonly buffer vplkit_global_weights_offsets_buffer {
  uint vplkit_global_weights_offsets[];
};
layout(std430, binding = VPLKIT_GLOBAL_WEIGHTS_BINDING_WEIGHTS) writeonly buffer vplkit_global_weights_out_buffer {
  float vplkit_global_weights_out[];
};
layout(std140, binding = VPLKIT_GLOBAL_WEIGHTS_BINDING_PARAMS) uniform vplkit_global_weights_uniforms {
  vplkit_global_weights_params vplkit_global_weights;
};

vec3 vplkit_load_dprsm_position(int texel) { return vplkit_global_weights_dprsm[3 * texel].xyz; }
vec3 vplkit_load_dprsm_normal(int texel) { return vplkit_global_weights_dprsm[3 * texel + 1].xyz; }
vec3 vplkit_load_dprsm_albedo(int texel) { return vplkit_global_weights_dprsm[3 * texel + 2].xyz; }

uint vplkit_global_weights_first;  // this invocation's region: offsets[region]

vplkit_gather_point vplkit_load_subset_gather_point(int i) {
  int p = vplkit_global_weights_subset[vplkit_global_weights_first + uint(i)];
  if (p < 0 || p >= vplkit_global_weights.pixel_count) return vplkit_gather_point(vec3(0.0), vec3(0.0), vec3(0.0));
  return vplkit_gather_point(vplkit_global_weights_gbuffer[3 * p].xyz, vplkit_global_weights_gbuffer[3 * p + 1].xyz,
                             vplkit_global_weights_gbuffer[3 * p + 2].xyz);
}

void main() {
  int R = vplkit_global_weights.resolution;
  int n = vplkit_texel_count(R);
  int t = int(gl_GlobalInvocationID.x);
  int region = int(gl_GlobalInvocationID.y);
  if (t >= n || region >= vplkit_global_weights.regions) return;
  vplkit_global_weights_first = vplkit_global_weights_offsets[region];
  int count = int(vplkit_global_weights_offsets[region + 1] - vplkit_global_weights_first);
  vplkit_dprsm_view view = vplkit_dprsm_view(R, vplkit_light_params_point_light(vplkit_global_weights.light));
  vplkit_global_weights_out[region * n + t] = vplkit_global_weight_texel(view, t, count, vplkit_global_weights.dmin);
}
