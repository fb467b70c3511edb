// vplkit kernel: global weights (BRSM; DESIGN 3.4), one invocation per (texel, region): the GPU
// side of vplkit::build_global_weights and, with N regions, of vplkit::build_local_weights
// (global_weights.hpp, local_weights.hpp). Per texel it runs vplkit_global_weight_texel (global_weights.glsl):
// the mean over the region's subset of luminance(vpl_contribution), no visibility, summed in float
// in the subset's order and multiplied by 1 / |S| -- the C++ arithmetic statement for statement.
//
// Interface (no #version; the host prepends it and its #defines):
//   VPLKIT_GLOBAL_WEIGHTS_BINDING_GBUFFER  (default 0) SSBO, std430, readonly: vec4 gbuffer[3 W H],
//                                          position, normal, albedo of pixel p at 3p, 3p + 1, 3p + 2
//   VPLKIT_GLOBAL_WEIGHTS_BINDING_DPRSM    (default 1) SSBO, std430, readonly: vec4 dprsm[3 * 2 R^2],
//                                          likewise per texel
//   VPLKIT_GLOBAL_WEIGHTS_BINDING_SUBSET   (default 2) SSBO, std430, readonly: int pixels[]: the
//                                          N subsets back to back, flat pixel indices y * W + x;
//                                          -1 (a dropped stratum of gather_subset.comp), an index
//                                          outside the image or a background pixel is skipped and
//                                          not counted (the C++ drops background entries and
//                                          throws for indices outside the image)
//   VPLKIT_GLOBAL_WEIGHTS_BINDING_OFFSETS  (default 3) SSBO, std430, readonly: uint offsets[N + 1];
//                                          region i's subset is pixels[offsets[i] .. offsets[i+1])
//   VPLKIT_GLOBAL_WEIGHTS_BINDING_WEIGHTS  (default 4) SSBO, std430, writeonly:
//                                          float weights[N * 2 R^2], region-major (weights[i * 2 R^2
//                                          + t], the layout of build_local_weights; N = 1: global)
//   VPLKIT_GLOBAL_WEIGHTS_BINDING_PARAMS   (default 0) uniform block, std140,
//                                          vplkit_global_weights_block below
//   VPLKIT_GLOBAL_WEIGHTS_LOCAL_SIZE       (default 64)
// Dispatch: (ceil(2 R^2 / LOCAL_SIZE), N, 1); invocation (texel, region).
// llvmpipe runs at most 65535 loop iterations per invocation: keep each |S_i| below ~65000 there.
// Precision against the C++ float build: the per-term float error of luminance(vpl_contribution)
// (a few ulps, FMA contraction and the GPU's normalisation) accumulated over |S| terms in the same
// order: measured in tests/parity/parity_builders_test.cpp (docs/glsl/builders.md).
#include "vplkit/builders/global_weights.glsl"
#include "vplkit/core/gather_point.glsl"

#ifndef VPLKIT_GLOBAL_WEIGHTS_BINDING_GBUFFER
#define VPLKIT_GLOBAL_WEIGHTS_BINDING_GBUFFER 0
#endif
#ifndef VPLKIT_GLOBAL_WEIGHTS_BINDING_DPRSM
#define VPLKIT_GLOBAL_WEIGHTS_BINDING_DPRSM 1
#endif
#ifndef VPLKIT_GLOBAL_WEIGHTS_BINDING_SUBSET
#define VPLKIT_GLOBAL_WEIGHTS_BINDING_SUBSET 2
#endif
#ifndef VPLKIT_GLOBAL_WEIGHTS_BINDING_OFFSETS
#define VPLKIT_GLOBAL_WEIGHTS_BINDING_OFFSETS 3
#endif
#ifndef VPLKIT_GLOBAL_WEIGHTS_BINDING_WEIGHTS
#define VPLKIT_GLOBAL_WEIGHTS_BINDING_WEIGHTS 4
#endif
#ifndef VPLKIT_GLOBAL_WEIGHTS_BINDING_PARAMS
#define VPLKIT_GLOBAL_WEIGHTS_BINDING_PARAMS 0
#endif
#ifndef VPLKIT_GLOBAL_WEIGHTS_LOCAL_SIZE
#define VPLKIT_GLOBAL_WEIGHTS_LOCAL_SIZE 64
#endif

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
layout(std140, binding = VPLKIT_GLOBAL_WEIGHTS_BINDING_PARAMS) uniform vplkit_global_weights_block {
  vec4 vplkit_global_weights_light_position;   // xyz: c
  vec4 vplkit_global_weights_light_intensity;  // xyz: I_s
  vec4 vplkit_global_weights_light_axis_x;     // xyz: the DPRSM's light frame
  vec4 vplkit_global_weights_light_axis_y;
  vec4 vplkit_global_weights_light_axis_z;
  ivec4 vplkit_global_weights_sizes;           // x: R, y: N regions, z: pixel count W * H
  vec4 vplkit_global_weights_reals;            // x: dmin
};

vec3 vplkit_load_dprsm_position(int texel) { return vplkit_global_weights_dprsm[3 * texel].xyz; }
vec3 vplkit_load_dprsm_normal(int texel) { return vplkit_global_weights_dprsm[3 * texel + 1].xyz; }
vec3 vplkit_load_dprsm_albedo(int texel) { return vplkit_global_weights_dprsm[3 * texel + 2].xyz; }

uint vplkit_global_weights_first;  // this invocation's region: offsets[region]

vplkit_gather_point vplkit_load_subset_gather_point(int i) {
  int p = vplkit_global_weights_subset[vplkit_global_weights_first + uint(i)];
  if (p < 0 || p >= vplkit_global_weights_sizes.z) return vplkit_gather_point(vec3(0.0), vec3(0.0), vec3(0.0));
  return vplkit_gather_point(vplkit_global_weights_gbuffer[3 * p].xyz, vplkit_global_weights_gbuffer[3 * p + 1].xyz,
                             vplkit_global_weights_gbuffer[3 * p + 2].xyz);
}

void main() {
  int R = vplkit_global_weights_sizes.x;
  int n = vplkit_texel_count(R);
  int t = int(gl_GlobalInvocationID.x);
  int region = int(gl_GlobalInvocationID.y);
  if (t >= n || region >= vplkit_global_weights_sizes.y) return;
  vplkit_global_weights_first = vplkit_global_weights_offsets[region];
  int count = int(vplkit_global_weights_offsets[region + 1] - vplkit_global_weights_first);
  vplkit_light_frame frame = vplkit_light_frame(vplkit_global_weights_light_position.xyz,
                                                vplkit_global_weights_light_axis_x.xyz,
                                                vplkit_global_weights_light_axis_y.xyz,
                                                vplkit_global_weights_light_axis_z.xyz);
  vplkit_dprsm_view view = vplkit_dprsm_view(
      R, vplkit_point_light(vplkit_global_weights_light_position.xyz, vplkit_global_weights_light_intensity.xyz, frame));
  vplkit_global_weights_out[region * n + t] =
      vplkit_global_weight_texel(view, t, count, vplkit_global_weights_reals.x);
}
