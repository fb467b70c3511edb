// SPDX-License-Identifier: MIT
// vplkit kernel: global weights (BRSM; docs/math.md section 4), one invocation per (texel, region):
// the GPU side of vplkit::build_global_weights and, with N regions, of build_local_weights. Per
// texel it runs vplkit_global_weight_texel over the region's subset pixels[offsets[i] ..
// offsets[i + 1]) (entries -1, outside the image or background are skipped and not counted) and
// writes weights[i * 2 R^2 + t] (region-major; N = 1: global) -- the C++ float arithmetic
// statement for statement. Interface: global_weights_params.h, shared with the C++ host; the
// G-buffer and the DPRSM are vec4 triplets (position, normal, albedo). Dispatch
// ceil(2 R^2 / LOCAL_SIZE) groups spread over x and y (linear group = x + y * gl_NumWorkGroups.x:
// R = 2048 needs 131072 groups, past the GL minimum of 65535 per axis) and N on z (the host's
// vplkit::gl::dispatch_linear); under llvmpipe's loop budget (docs/glsl.md) keep each |S_i| below
// ~65000. Precision: docs/glsl/builders.md.
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
  if (p < 0 || p >= vplkit_global_weights.pixel_count) return vplkit_unpack_gather_point(vec4(0.0), vec4(0.0), vec4(0.0));
  return vplkit_unpack_gather_point(vplkit_global_weights_gbuffer[3 * p], vplkit_global_weights_gbuffer[3 * p + 1],
                                    vplkit_global_weights_gbuffer[3 * p + 2]);
}

void main() {
  int R = vplkit_global_weights.resolution;
  int n = vplkit_texel_count(R);
  int t = int(gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x);
  int region = int(gl_GlobalInvocationID.z);
  if (t >= n || region >= vplkit_global_weights.regions) return;
  vplkit_global_weights_first = vplkit_global_weights_offsets[region];
  int count = int(vplkit_global_weights_offsets[region + 1] - vplkit_global_weights_first);
  vplkit_dprsm_view view = vplkit_dprsm_view(R, vplkit_light_params_point_light(vplkit_global_weights.light));
  vplkit_global_weights_out[region * n + t] = vplkit_global_weight_texel(view, t, count, vplkit_global_weights.dmin);
}
