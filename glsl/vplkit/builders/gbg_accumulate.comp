// vplkit kernel: GBG accumulation (paper Alg. 2, DESIGN 3.4), one invocation per G-buffer pixel:
// the GPU side of the accumulation loop of vplkit::build_gbg_weights (gbg_weights.hpp), with the
// pack's voxel tracer (the GPU has no host tracer: vplkit_voxel_tracer over the voxel grid below).
// For every valid gather point: directions [dir_begin, dir_end) of its n_dirs cosine rays, the
// voxel DDA hit, vplkit_dprsm_lookup, and for a lit hit on a texel that carries a VPL the chosen
// accumulator's value added to acc[texel] in 64-bit FIXED POINT with 32-bit atomics.
// Then gbg_finish.comp turns acc into weights w_t = acc / (|G| n_dirs) and fills holes.
//
// Interface (no #version: the host prepends "#version 430" (GL) or "#version 450" (Vulkan, plus
// "#extension GL_GOOGLE_include_directive : require"), then its #defines): gbg_accumulate_params.h,
// shared with the C++ host -- bindings (VPLKIT_GBG_BINDING_*), the local size, the stats counters
// and the std140 block vplkit_gbg_accumulate_params. Buffers:
//   GBUFFER  vec4 gbuffer[3 W H]: position, normal, albedo of pixel p at 3p, 3p + 1, 3p + 2 (xyz;
//            p = y * W + x; zero normal = background)
//   DPRSM    vec4 dprsm[3 * 2 R^2], likewise per texel (index = face * R * R + y * R + x)
//   VOXELS   uint words[] of the voxel grid (visibility/voxel_grid.glsl, as voxel_grid::words())
//   ACC      uint acc[2 * 2 R^2], (lo, hi) per texel; ZEROED by the host before the first dispatch
//   STATS    uint stats[VPLKIT_GBG_STATS_SIZE], ZEROED by the host: |G| (counted where
//            count_gather_points is set), hits, lit hits (as vplkit::gbg_stats), saturated hits;
//            the rest are gbg_finish.comp's
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
// max_units and are counted (VPLKIT_GBG_STAT_SATURATED_HITS).
#include "vplkit/builders/gbg_accumulate_params.h"
#include "vplkit/builders/gbg_weights.glsl"
#include "vplkit/core/gather_point.glsl"
#include "vplkit/visibility/visibility_callables.glsl"

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
layout(std140, binding = VPLKIT_GBG_BINDING_PARAMS) uniform vplkit_gbg_accumulate_uniforms {
  vplkit_gbg_accumulate_params vplkit_gbg_accumulate;
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
  float scale = vplkit_gbg_accumulate.scale, max_units = vplkit_gbg_accumulate.max_units;
  if (vplkit_gbg_fixed_saturates(value, scale, max_units)) atomicAdd(vplkit_gbg_stats[VPLKIT_GBG_STAT_SATURATED_HITS], 1u);
  uvec2 q = vplkit_gbg_fixed_units(value, scale, max_units);
  if (q.x != 0u) {
    uint old = atomicAdd(vplkit_gbg_acc[2 * texel], q.x);
    if (old + q.x < old) q.y += 1u;
  }
  if (q.y != 0u) atomicAdd(vplkit_gbg_acc[2 * texel + 1], q.y);
}

void main() {
  vplkit_gbg_accumulate_params p = vplkit_gbg_accumulate;
  uint pixel = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * uint(VPLKIT_GBG_LOCAL_SIZE);
  if (pixel >= uint(p.width) * uint(p.height)) return;
  vplkit_gather_point g = vplkit_load_gather_point(int(pixel));
  if (!vplkit_gather_point_valid(g)) return;
  if (p.count_gather_points != 0) atomicAdd(vplkit_gbg_stats[VPLKIT_GBG_STAT_GATHER_POINTS], 1u);

  vplkit_dprsm_view view = vplkit_dprsm_view(p.resolution, vplkit_light_params_point_light(p.light));
  vplkit_voxel_tracer tracer =
      vplkit_make_voxel_tracer(vplkit_voxel_grid(p.grid_min.xyz, p.grid_max.xyz, p.grid_resolution.xyz));
  tracer.offset_voxels = p.offset_voxels;
  vplkit_gbg_params params = vplkit_gbg_params(p.n_dirs, p.dmin, p.depth_tolerance, p.seed, p.accumulator, false);
  int dir_begin = max(p.dir_begin, 0);
  int dir_end = min(p.dir_end, params.n_dirs);
  ivec2 counts = vplkit_gbg_accumulate_gather_point(g, int(pixel), view, tracer, params, dir_begin, dir_end);
  if (counts.x != 0) atomicAdd(vplkit_gbg_stats[VPLKIT_GBG_STAT_HITS], uint(counts.x));
  if (counts.y != 0) atomicAdd(vplkit_gbg_stats[VPLKIT_GBG_STAT_LIT_HITS], uint(counts.y));
}
