// vplkit kernel: GBG accumulation (paper Alg. 2, DESIGN 3.4), one invocation per G-buffer pixel:
// the GPU side of the accumulation loop of vplkit::build_gbg_weights (gbg_weights.hpp), with the
// pack's voxel tracer (the GPU has no host tracer: vplkit_voxel_tracer over the voxel grid below).
// For every valid gather point: directions [dir_begin, dir_end) of its n_dirs cosine rays, the
// voxel DDA hit, vplkit_dprsm_lookup, and for a lit hit on a texel that carries a VPL the chosen
// accumulator's value added to acc[texel] in 64-bit FIXED POINT with 32-bit atomics.
// Then gbg_finish.comp turns acc into weights w_t = acc / (|G| n_dirs) and fills holes.
//
// Interface (no #version: the host prepends "#version 430" (GL) or "#version 450" (Vulkan, plus
// "#extension GL_GOOGLE_include_directive : require"), then its #defines):
//   VPLKIT_GBG_BINDING_GBUFFER  (default 0) SSBO, std430, readonly:
//                               vec4 gbuffer[3 * W * H]: position, normal, albedo of pixel p at
//                               3p, 3p + 1, 3p + 2 (xyz; p = y * W + x; zero normal = background)
//   VPLKIT_GBG_BINDING_DPRSM    (default 1) SSBO, std430, readonly: vec4 dprsm[3 * 2 R^2], likewise
//                               per texel (index = face * R * R + y * R + x)
//   VPLKIT_GBG_BINDING_VOXELS   (default 2) SSBO, std430, readonly: uint words[] of the voxel grid
//                               (visibility/voxel_grid.glsl layout, as vplkit::voxel_grid::words())
//   VPLKIT_GBG_BINDING_ACC      (default 3) SSBO, std430: uint acc[2 * 2 R^2], (lo, hi) per texel;
//                               ZEROED by the host before the first dispatch
//   VPLKIT_GBG_BINDING_STATS    (default 4) SSBO, std430: uint stats[8], ZEROED by the host:
//                               [0] |G| valid gather points (counted when count_gather_points),
//                               [1] hits, [2] lit hits (as vplkit::gbg_stats), [3] saturated hits;
//                               [4..6] are gbg_finish.comp's
//   VPLKIT_GBG_BINDING_PARAMS   (default 0) uniform block, std140, vplkit_gbg_block below
//   VPLKIT_GBG_LOCAL_SIZE       (default 64)
// Dispatch: ceil(W * H / LOCAL_SIZE) invocations in x, spread over y when above 65535 groups
// (pixel = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * LOCAL_SIZE).
// Several dispatches over direction ranges [dir_begin, dir_end) that cover [0, n_dirs) once give
// exactly the result of one dispatch over all of them (the fixed-point sum does not depend on the
// order of the adds); set count_gather_points = 1 in exactly one of them. Why ranges: llvmpipe
// (Mesa 22.3) runs at most 65535 loop iterations per invocation and then silently leaves every
// loop; one ray marches up to nx + ny + nz voxels, so keep (dir_end - dir_begin) * (nx + ny + nz +
// 8) below 65535 there (docs/glsl/builders.md). GPUs have no such limit.
//
// FIXED POINT (gbg_weights.glsl): units = roundEven(min(v * scale, max_units)) per lit hit, summed
// exactly in 64 bits. Precision: <= 0.5 / scale absolute per hit (0 when v * scale >= 2^24), the
// per-texel sum exact and order-independent (bit-identical on every device), read back within
// 1.5 float ulps. No overflow while (hits of one texel) * max_units < 2^64: take
// max_units = 2^(63 - ceil(log2(|G| n_dirs))) and scale = 2^floor(log2(max_units / v_bound)) for a
// bound v_bound of the per-hit value (formulas in gbg_weights.glsl); hits above it saturate at
// max_units and are counted in stats[3].
#include "vplkit/builders/gbg_weights.glsl"
#include "vplkit/core/gather_point.glsl"
#include "vplkit/visibility/visibility_callables.glsl"

#ifndef VPLKIT_GBG_BINDING_GBUFFER
#define VPLKIT_GBG_BINDING_GBUFFER 0
#endif
#ifndef VPLKIT_GBG_BINDING_DPRSM
#define VPLKIT_GBG_BINDING_DPRSM 1
#endif
#ifndef VPLKIT_GBG_BINDING_VOXELS
#define VPLKIT_GBG_BINDING_VOXELS 2
#endif
#ifndef VPLKIT_GBG_BINDING_ACC
#define VPLKIT_GBG_BINDING_ACC 3
#endif
#ifndef VPLKIT_GBG_BINDING_STATS
#define VPLKIT_GBG_BINDING_STATS 4
#endif
#ifndef VPLKIT_GBG_BINDING_PARAMS
#define VPLKIT_GBG_BINDING_PARAMS 0
#endif
#ifndef VPLKIT_GBG_LOCAL_SIZE
#define VPLKIT_GBG_LOCAL_SIZE 64
#endif

layout(local_size_x = VPLKIT_GBG_LOCAL_SIZE, local_size_y = 1, local_size_z = 1) in;

layout(std430, binding = VPLKIT_GBG_BINDING_GBUFFER) readonly buffer vplkit_gbg_gbuffer_buffer {
  vec4 vplkit_gbg_gbuffer[];
};
layout(std430, binding = VPLKIT_GBG_BINDING_DPRSM) readonly buffer vplkit_gbg_dprsm_buffer {
  vec4 vplkit_gbg_dprsm[];
};
layout(std430, binding = VPLKIT_GBG_BINDING_VOXELS) readonly buffer vplkit_gbg_voxel_buffer {
  uint vplkit_gbg_voxels[];
};
layout(std430, binding = VPLKIT_GBG_BINDING_ACC) buffer vplkit_gbg_acc_buffer {
  uint vplkit_gbg_acc[];
};
layout(std430, binding = VPLKIT_GBG_BINDING_STATS) buffer vplkit_gbg_stats_buffer {
  uint vplkit_gbg_stats[];
};
layout(std140, binding = VPLKIT_GBG_BINDING_PARAMS) uniform vplkit_gbg_block {
  vec4 vplkit_gbg_light_position;   // xyz: c (also the light frame's position)
  vec4 vplkit_gbg_light_intensity;  // xyz: I_s
  vec4 vplkit_gbg_light_axis_x;     // xyz: the DPRSM's light frame
  vec4 vplkit_gbg_light_axis_y;
  vec4 vplkit_gbg_light_axis_z;
  vec4 vplkit_gbg_grid_min;         // xyz: voxel grid bounds
  vec4 vplkit_gbg_grid_max;
  ivec4 vplkit_gbg_grid_res;        // xyz: voxel grid resolution
  ivec4 vplkit_gbg_sizes;           // x: G-buffer width W, y: height H, z: DPRSM R, w: n_dirs
  ivec4 vplkit_gbg_options;         // x: accumulator (0 paper, 1 gathering), y: dir_begin,
                                    // z: dir_end, w: count_gather_points (0 / 1)
  uvec4 vplkit_gbg_seed;            // x: seed (streams are pixel indices)
  vec4 vplkit_gbg_reals;            // x: dmin, y: depth_tolerance, z: tracer offset_voxels (1.75)
  vec4 vplkit_gbg_fixed;            // x: scale, y: max_units (<= 2^63)
};

vplkit_gather_point vplkit_load_gather_point(int pixel) {
  return vplkit_gather_point(vplkit_gbg_gbuffer[3 * pixel].xyz, vplkit_gbg_gbuffer[3 * pixel + 1].xyz,
                             vplkit_gbg_gbuffer[3 * pixel + 2].xyz);
}
vec3 vplkit_load_dprsm_position(int texel) { return vplkit_gbg_dprsm[3 * texel].xyz; }
vec3 vplkit_load_dprsm_normal(int texel) { return vplkit_gbg_dprsm[3 * texel + 1].xyz; }
vec3 vplkit_load_dprsm_albedo(int texel) { return vplkit_gbg_dprsm[3 * texel + 2].xyz; }
uint vplkit_load_voxel_word(uint word_index) { return vplkit_gbg_voxels[word_index]; }

// 64-bit add as two 32-bit atomics: the low word's carry is detected from the value it had just
// before this add (atomicAdd returns it), so every wrap of the low word adds 1 to the high word
// exactly once, whatever the order of the adds.
void vplkit_store_gbg_hit(int texel, float value) {
  float scale = vplkit_gbg_fixed.x, max_units = vplkit_gbg_fixed.y;
  if (vplkit_gbg_fixed_saturates(value, scale, max_units)) atomicAdd(vplkit_gbg_stats[3], 1u);
  uvec2 q = vplkit_gbg_fixed_units(value, scale, max_units);
  if (q.x != 0u) {
    uint old = atomicAdd(vplkit_gbg_acc[2 * texel], q.x);
    if (old + q.x < old) q.y += 1u;
  }
  if (q.y != 0u) atomicAdd(vplkit_gbg_acc[2 * texel + 1], q.y);
}

void main() {
  uint pixel = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * uint(VPLKIT_GBG_LOCAL_SIZE);
  if (pixel >= uint(vplkit_gbg_sizes.x) * uint(vplkit_gbg_sizes.y)) return;
  vplkit_gather_point g = vplkit_load_gather_point(int(pixel));
  if (!vplkit_gather_point_valid(g)) return;
  if (vplkit_gbg_options.w != 0) atomicAdd(vplkit_gbg_stats[0], 1u);

  vplkit_light_frame frame = vplkit_light_frame(vplkit_gbg_light_position.xyz, vplkit_gbg_light_axis_x.xyz,
                                                vplkit_gbg_light_axis_y.xyz, vplkit_gbg_light_axis_z.xyz);
  vplkit_dprsm_view view = vplkit_dprsm_view(
      vplkit_gbg_sizes.z, vplkit_point_light(vplkit_gbg_light_position.xyz, vplkit_gbg_light_intensity.xyz, frame));
  vplkit_voxel_tracer tracer = vplkit_make_voxel_tracer(
      vplkit_voxel_grid(vplkit_gbg_grid_min.xyz, vplkit_gbg_grid_max.xyz, vplkit_gbg_grid_res.xyz));
  tracer.offset_voxels = vplkit_gbg_reals.z;
  vplkit_gbg_params params = vplkit_gbg_params(vplkit_gbg_sizes.w, vplkit_gbg_reals.x, vplkit_gbg_reals.y,
                                               vplkit_gbg_seed.x, vplkit_gbg_options.x, false);
  int dir_begin = max(vplkit_gbg_options.y, 0);
  int dir_end = min(vplkit_gbg_options.z, params.n_dirs);
  ivec2 counts = vplkit_gbg_accumulate_gather_point(g, int(pixel), view, tracer, params, dir_begin, dir_end);
  if (counts.x != 0) atomicAdd(vplkit_gbg_stats[1], uint(counts.x));
  if (counts.y != 0) atomicAdd(vplkit_gbg_stats[2], uint(counts.y));
}
