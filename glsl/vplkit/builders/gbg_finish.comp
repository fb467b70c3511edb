// SPDX-License-Identifier: MIT
// vplkit kernel: finishes the GBG weights from gbg_accumulate.comp's fixed-point sums, one
// invocation (x, y, face) per texel: w_t = acc[t] / scale / (|G| n_dirs) (the C++ gbg_finish), then
// with fill_holes the hole-aware 3x3 median fill of vplkit::gbg_fill_holes (per face, fillable =
// the texel carries a VPL), in one pass: the fill reads its neighbours' finished values straight
// from acc. Adds the reached, hole and filled counts to the stats; |G| = 0 gives all zeros.
// Interface: gbg_finish_params.h, shared with the C++ host. Dispatch (ceil(R / LOCAL_SIZE),
// ceil(R / LOCAL_SIZE), 2). Precision against the C++ (the fixed-point quantisation, <= 4 ulps of
// read-out and division): docs/glsl/builders.md, "GBG".
#include "vplkit/builders/gbg_finish_params.h"
#include "vplkit/builders/gbg_weights.glsl"
#include "vplkit/image/median_fill.glsl"
#include "vplkit/paraboloid/texel_grid.glsl"

layout(local_size_x = VPLKIT_GBG_FINISH_LOCAL_SIZE, local_size_y = VPLKIT_GBG_FINISH_LOCAL_SIZE,
       local_size_z = 1) in;

layout(std430, binding = VPLKIT_GBG_FINISH_BINDING_ACC) readonly buffer vplkit_gbg_finish_acc_buffer {
  uint vplkit_gbg_finish_acc[];
};
layout(std430, binding = VPLKIT_GBG_FINISH_BINDING_STATS) buffer vplkit_gbg_finish_stats_buffer {
  uint vplkit_gbg_finish_stats[];
};
layout(std430, binding = VPLKIT_GBG_FINISH_BINDING_DPRSM) readonly buffer vplkit_gbg_finish_dprsm_buffer {
  vec4 vplkit_gbg_finish_dprsm[];
};
layout(std430, binding = VPLKIT_GBG_FINISH_BINDING_WEIGHTS) writeonly buffer vplkit_gbg_finish_weights_buffer {
  float vplkit_gbg_finish_weights[];
};
layout(std140, binding = VPLKIT_GBG_FINISH_BINDING_PARAMS) uniform vplkit_gbg_finish_uniforms {
  vplkit_gbg_finish_params vplkit_gbg_finish;
};

vec3 vplkit_load_dprsm_position(int texel) { return vplkit_gbg_finish_dprsm[3 * texel].xyz; }
vec3 vplkit_load_dprsm_normal(int texel) { return vplkit_gbg_finish_dprsm[3 * texel + 1].xyz; }
vec3 vplkit_load_dprsm_albedo(int texel) { return vplkit_gbg_finish_dprsm[3 * texel + 2].xyz; }
// Referenced by gbg_weights.glsl's accumulation loop, not called here; they still need a body
// (docs/glsl.md, "Accessors and Mesa's linker").
void vplkit_store_gbg_hit(int texel, float value) {}
uint vplkit_load_voxel_word(uint word_index) { return 0u; }

// w_t before the fill (C++ gbg_finish).
float vplkit_gbg_finish_raw(int texel) {
  uint gather_points = vplkit_gbg_finish_stats[VPLKIT_GBG_STAT_GATHER_POINTS];
  if (gather_points == 0u) return 0.0;
  float units = vplkit_gbg_fixed_to_float(vplkit_gbg_finish_acc[2 * texel], vplkit_gbg_finish_acc[2 * texel + 1]);
  return units * vplkit_gbg_finish.inv_scale / (float(gather_points) * float(vplkit_gbg_finish.n_dirs));
}

float vplkit_load_weight(int face, int x, int y) {
  return vplkit_gbg_finish_raw(vplkit_texel_index(face, x, y, vplkit_gbg_finish.resolution));
}

void main() {
  int R = vplkit_gbg_finish.resolution;
  int x = int(gl_GlobalInvocationID.x);
  int y = int(gl_GlobalInvocationID.y);
  int face = int(gl_GlobalInvocationID.z);
  if (x >= R || y >= R || face > 1) return;
  int t = vplkit_texel_index(face, x, y, R);
  vplkit_dprsm_view view = vplkit_dprsm_view(R, vplkit_light_params_point_light(vplkit_gbg_finish.light));
  bool carries = vplkit_vpl_has_flux(vplkit_dprsm_view_vpl_at(view, t));
  float raw = vplkit_gbg_finish_raw(t);
  float w = vplkit_gbg_finish.fill_holes != 0 ? vplkit_median_fill_texel(face, R, R, x, y, carries) : raw;
  vplkit_gbg_finish_weights[t] = w;
  if (raw != 0.0) {
    atomicAdd(vplkit_gbg_finish_stats[VPLKIT_GBG_STAT_REACHED_TEXELS], 1u);
  } else if (carries) {
    atomicAdd(vplkit_gbg_finish_stats[VPLKIT_GBG_STAT_HOLES], 1u);
    if (w != 0.0) atomicAdd(vplkit_gbg_finish_stats[VPLKIT_GBG_STAT_FILLED], 1u);
  }
}
