// vplkit kernel: finishes the GBG weights from gbg_accumulate.comp's fixed-point sums, one
// invocation per texel: w_t = acc[t] / scale / (|G| n_dirs) (the C++ gbg_finish), then, when
// fill_holes is set, the hole-aware 3x3 lower-median fill of vplkit::gbg_fill_holes, per face,
// fillable = the texel carries a VPL (vplkit_vpl_has_flux): texels without a VPL stay exactly 0.
// One pass does both: the fill reads its neighbours' finished values straight from acc (the
// conversion is a pure function of acc, so this equals finishing first and filling second).
//
// Interface (no #version; the host prepends it and its #defines): gbg_finish_params.h, shared with
// the C++ host -- bindings (VPLKIT_GBG_FINISH_BINDING_*), the local size (work groups LOCAL_SIZE x
// LOCAL_SIZE x 1) and the std140 block vplkit_gbg_finish_params (light, R, n_dirs, fill_holes,
// 1 / scale). Buffers:
//   ACC      uint acc[2 * 2 R^2] of gbg_accumulate.comp
//   STATS    gbg_accumulate.comp's stats: reads |G|, adds the reached texels (raw weight != 0),
//            holes (raw 0, carries a VPL) and filled holes (a hole the fill made non-zero) -- zero
//            them before, as the whole buffer is zeroed before accumulating
//   DPRSM    vec4 dprsm[3 * 2 R^2] (as gbg_accumulate.comp; read for the fillable mask)
//   WEIGHTS  float weights[2 R^2], written
// Dispatch: (ceil(R / LOCAL_SIZE), ceil(R / LOCAL_SIZE), 2); invocation (x, y, face).
//
// Precision against the C++ (which sums the float hit values in double and divides once):
// the fixed-point quantisation of gbg_accumulate.comp (<= 0.5 / scale per hit), the read-out
// float(hi) 2^32 + float(lo) (<= 1.5 ulps), the product by 1 / scale (exact for a power of two)
// and one float division by float(|G|) * float(n_dirs) (exact below 2^24; GLSL division within
// 2.5 ulps): <= (H_t 0.5 / scale) / (|G| n_dirs) + 4 ulps of w_t, H_t the hits of texel t, plus the
// float difference of the hit values themselves (docs/glsl/builders.md). No valid gather point
// (|G| = 0) gives all zeros.
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
// Referenced by gbg_weights.glsl's accumulation loop, not called here (Mesa wants them defined).
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
