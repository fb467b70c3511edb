// vplkit kernel: hole-aware 3x3 median fill of both faces of a DPRSM weight array (the GPU side of
// vplkit::median_fill_dprsm; per texel: vplkit_median_fill_texel in median_fill.glsl).
//
// Interface (no #version: the host prepends "#version 430" (GL) or "#version 450" (Vulkan, plus
// "#extension GL_GOOGLE_include_directive : require"), then its #defines):
//   VPLKIT_MEDIAN_FILL_BINDING_IN      (default 0)  SSBO, std430, readonly:  float in[2 * R * R]
//   VPLKIT_MEDIAN_FILL_BINDING_OUT     (default 1)  SSBO, std430, writeonly: float out[2 * R * R]
//   VPLKIT_MEDIAN_FILL_BINDING_PARAMS  (default 2)  uniform block, std140:   int resolution (R)
//   VPLKIT_MEDIAN_FILL_LOCAL_SIZE      (default 8)  work group = LOCAL_SIZE x LOCAL_SIZE x 1
// Layout of both arrays: index = face * R * R + y * R + x (face 0 front, 1 back; as texel_grid).
// Dispatch: (ceil(R / LOCAL_SIZE), ceil(R / LOCAL_SIZE), 2) work groups; invocation (x, y, face).
// Every texel of `out` is written, holes that stay holes as +0.0. `in` and `out` must be different
// buffers (one Jacobi pass: filled values never feed other fills). Only valid texels (centre in
// the closed unit disk, vplkit_texel_is_valid) are fillable, so texels outside the disk keep 0.
// The host validates as median_fill_dprsm does (1 <= R <= 16384, finite weights): NaN or Inf
// inputs are not rejected here.
#include "vplkit/image/median_fill.glsl"
#include "vplkit/paraboloid/texel_grid.glsl"

#ifndef VPLKIT_MEDIAN_FILL_BINDING_IN
#define VPLKIT_MEDIAN_FILL_BINDING_IN 0
#endif
#ifndef VPLKIT_MEDIAN_FILL_BINDING_OUT
#define VPLKIT_MEDIAN_FILL_BINDING_OUT 1
#endif
#ifndef VPLKIT_MEDIAN_FILL_BINDING_PARAMS
#define VPLKIT_MEDIAN_FILL_BINDING_PARAMS 2
#endif
#ifndef VPLKIT_MEDIAN_FILL_LOCAL_SIZE
#define VPLKIT_MEDIAN_FILL_LOCAL_SIZE 8
#endif

layout(local_size_x = VPLKIT_MEDIAN_FILL_LOCAL_SIZE, local_size_y = VPLKIT_MEDIAN_FILL_LOCAL_SIZE,
       local_size_z = 1) in;

layout(std430, binding = VPLKIT_MEDIAN_FILL_BINDING_IN) readonly buffer vplkit_median_fill_in_buffer {
  float vplkit_median_fill_in[];
};
layout(std430, binding = VPLKIT_MEDIAN_FILL_BINDING_OUT) writeonly buffer vplkit_median_fill_out_buffer {
  float vplkit_median_fill_out[];
};
layout(std140, binding = VPLKIT_MEDIAN_FILL_BINDING_PARAMS) uniform vplkit_median_fill_params {
  int vplkit_median_fill_resolution;
};

float vplkit_load_weight(int face, int x, int y) {
  int R = vplkit_median_fill_resolution;
  return vplkit_median_fill_in[vplkit_texel_index(face, x, y, R)];
}

void main() {
  int R = vplkit_median_fill_resolution;
  int x = int(gl_GlobalInvocationID.x);
  int y = int(gl_GlobalInvocationID.y);
  int face = int(gl_GlobalInvocationID.z);
  if (x >= R || y >= R || face > 1) return;
  vplkit_median_fill_out[vplkit_texel_index(face, x, y, R)] =
      vplkit_median_fill_texel(face, R, R, x, y, vplkit_texel_is_valid(x, y, R));
}
