// SPDX-License-Identifier: MIT
// vplkit kernel: hole-aware 3x3 median fill of both faces of a DPRSM weight array (the GPU side of
// vplkit::median_fill_dprsm; per texel: vplkit_median_fill_texel in median_fill.glsl).
//
// Interface (no #version: the host prepends "#version 430" (GL) or "#version 450" (Vulkan, plus
// "#extension GL_GOOGLE_include_directive : require"), then its #defines): median_fill_params.h,
// shared with the C++ host -- bindings (VPLKIT_MEDIAN_FILL_BINDING_*: float in[2 R^2] read,
// float out[2 R^2] written), the local size (work groups LOCAL_SIZE x LOCAL_SIZE x 1) and the
// std140 block vplkit_median_fill_params (R).
// Layout of both arrays: index = face * R * R + y * R + x (face 0 front, 1 back; as texel_grid).
// Dispatch: (ceil(R / LOCAL_SIZE), ceil(R / LOCAL_SIZE), 2) work groups; invocation (x, y, face).
// Every texel of `out` is written, holes that stay holes as +0.0. `in` and `out` must be different
// buffers (one Jacobi pass: filled values never feed other fills). Only valid texels (centre in
// the closed unit disk, vplkit_texel_is_valid) are fillable, so texels outside the disk keep 0.
// The host validates as median_fill_dprsm does (1 <= R <= 16384, finite weights): NaN or Inf
// inputs are not rejected here.
#include "vplkit/image/median_fill.glsl"
#include "vplkit/image/median_fill_params.h"
#include "vplkit/paraboloid/texel_grid.glsl"

layout(local_size_x = VPLKIT_MEDIAN_FILL_LOCAL_SIZE, local_size_y = VPLKIT_MEDIAN_FILL_LOCAL_SIZE,
       local_size_z = 1) in;

layout(std430, binding = VPLKIT_MEDIAN_FILL_BINDING_IN) readonly buffer vplkit_median_fill_in_buffer {
  float vplkit_median_fill_in[];
};
layout(std430, binding = VPLKIT_MEDIAN_FILL_BINDING_OUT) writeonly buffer vplkit_median_fill_out_buffer {
  float vplkit_median_fill_out[];
};
layout(std140, binding = VPLKIT_MEDIAN_FILL_BINDING_PARAMS) uniform vplkit_median_fill_uniforms {
  vplkit_median_fill_params vplkit_median_fill;
};

float vplkit_load_weight(int face, int x, int y) {
  int R = vplkit_median_fill.resolution;
  return vplkit_median_fill_in[vplkit_texel_index(face, x, y, R)];
}

void main() {
  int R = vplkit_median_fill.resolution;
  int x = int(gl_GlobalInvocationID.x);
  int y = int(gl_GlobalInvocationID.y);
  int face = int(gl_GlobalInvocationID.z);
  if (x >= R || y >= R || face > 1) return;
  vplkit_median_fill_out[vplkit_texel_index(face, x, y, R)] =
      vplkit_median_fill_texel(face, R, R, x, y, vplkit_texel_is_valid(x, y, R));
}
