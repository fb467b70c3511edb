// SPDX-License-Identifier: MIT
// vplkit kernel: GBG accumulation (paper Alg. 2, docs/math.md section 4), one invocation per
// G-buffer pixel: the accumulation loop of vplkit::build_gbg_weights for directions
// [dir_begin, dir_end) of every valid gather point, traced with the pack's voxel tracer; the value
// of each lit hit on a texel that carries a VPL goes to acc[texel] in 64-bit fixed point with
// 32-bit atomics (exact and order-independent), and the counters to the stats buffer.
// gbg_finish.comp then turns acc into weights and fills the holes.
// Interface: gbg_accumulate_params.h, shared with the C++ host (bindings, local size, stats
// counters, parameter block). The host zeroes acc and the stats first; dispatches over direction
// ranges that cover [0, n_dirs) once give exactly one dispatch's result (keep each range under
// llvmpipe's loop budget: docs/glsl.md). Buffers, dispatch, the fixed-point format and the choice
// of scale and max_units: docs/glsl/builders.md, "GBG".
// TRIANGLE VOXELS (#define VPLKIT_GBG_TRIANGLE_VOXELS): the rays are traced with the triangle
// voxel tracer (the first triangle met, on the triangle; docs/math.md section 7.2) instead of the
// voxel DDA, over the triangle voxel grid of the same occupancy words, with four more read-only
// SSBOs (VPLKIT_GBG_BINDING_VOXEL_*); end_tolerance_voxels is then the tracer's end tolerance and
// offset_voxels is unused.
#ifdef VPLKIT_GBG_TRIANGLE_VOXELS
#define VPLKIT_TRIANGLE_VOXELS
#endif
// Tracer: the voxel grid's by default; with VPLKIT_GBG_TRACER_BVH defined (host preamble) the
// pack's BVH (visibility/bvh_visibility.glsl: exact first hits against the triangles), its nodes and
// triangles bound at VPLKIT_GBG_BINDING_BVH_NODES / _TRIANGLES and params.bvh_node_count set.
#ifdef VPLKIT_GBG_TRACER_BVH
#define VPLKIT_USER_TRACER
#endif
#include "vplkit/builders/gbg_accumulate_params.h"
#include "vplkit/builders/gbg_weights.glsl"
#include "vplkit/core/gather_point.glsl"
#include "vplkit/visibility/bvh_visibility.glsl"
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
  return vplkit_unpack_gather_point(vplkit_gbg_gbuffer[3 * pixel], vplkit_gbg_gbuffer[3 * pixel + 1],
                                    vplkit_gbg_gbuffer[3 * pixel + 2]);
}
vec3 vplkit_load_dprsm_position(int texel) { return vplkit_gbg_dprsm[3 * texel].xyz; }
vec3 vplkit_load_dprsm_normal(int texel) { return vplkit_gbg_dprsm[3 * texel + 1].xyz; }
vec3 vplkit_load_dprsm_albedo(int texel) { return vplkit_gbg_dprsm[3 * texel + 2].xyz; }
uint vplkit_load_voxel_word(uint word_index) { return vplkit_gbg_voxels[word_index]; }

#ifdef VPLKIT_GBG_TRIANGLE_VOXELS
layout(std430, binding = VPLKIT_GBG_BINDING_VOXEL_RANK) readonly buffer vplkit_gbg_voxel_rank_buffer {
  uint vplkit_gbg_voxel_rank[];
};
layout(std430, binding = VPLKIT_GBG_BINDING_VOXEL_OFFSETS) readonly buffer vplkit_gbg_voxel_offsets_buffer {
  uint vplkit_gbg_voxel_offsets[];
};
layout(std430, binding = VPLKIT_GBG_BINDING_VOXEL_ENTRIES) readonly buffer vplkit_gbg_voxel_entries_buffer {
  uint vplkit_gbg_voxel_entries[];
};
layout(std430, binding = VPLKIT_GBG_BINDING_VOXEL_TRIANGLES) readonly buffer vplkit_gbg_voxel_triangles_buffer {
  vec4 vplkit_gbg_voxel_triangles[];
};
uint vplkit_load_voxel_rank(uint word_index) { return vplkit_gbg_voxel_rank[word_index]; }
uint vplkit_load_voxel_offset(uint index) { return vplkit_gbg_voxel_offsets[index]; }
uint vplkit_load_voxel_entry(uint index) { return vplkit_gbg_voxel_entries[index]; }
vec4 vplkit_load_voxel_triangle(uint index) { return vplkit_gbg_voxel_triangles[index]; }
#endif
// (bvh_visibility.glsl is included above, outside the #ifdef: the include resolver inlines a file
// once where it first appears and does not evaluate #if.)
#ifdef VPLKIT_GBG_TRACER_BVH
layout(std430, binding = VPLKIT_GBG_BINDING_BVH_NODES) readonly buffer vplkit_gbg_bvh_node_buffer {
  vplkit_bvh_node vplkit_gbg_bvh_nodes[];
};
layout(std430, binding = VPLKIT_GBG_BINDING_BVH_TRIANGLES) readonly buffer vplkit_gbg_bvh_triangle_buffer {
  vplkit_bvh_triangle vplkit_gbg_bvh_triangles[];
};
vplkit_bvh_node vplkit_load_bvh_node(uint index) { return vplkit_gbg_bvh_nodes[index]; }
vplkit_bvh_triangle vplkit_load_bvh_triangle(uint slot) { return vplkit_gbg_bvh_triangles[slot]; }
vplkit_ray_hit vplkit_user_trace(vec3 x, vec3 n_x, vec3 dir) {
  return vplkit_bvh_trace(vplkit_bvh(vplkit_gbg_accumulate.bvh_node_count), x, n_x, dir);
}
#else
// No BVH buffers: the BVH functions are compiled but never called.
vplkit_bvh_node vplkit_load_bvh_node(uint index) { return vplkit_bvh_node(vec3(0.0), 0u, vec3(0.0), 0u); }
vplkit_bvh_triangle vplkit_load_bvh_triangle(uint slot) {
  return vplkit_bvh_triangle(vec3(0.0), 0u, vec3(0.0), 0u, vec3(0.0), 0u);
}
#endif

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
  vplkit_voxel_grid grid = vplkit_voxel_grid(p.grid_min.xyz, p.grid_max.xyz, p.grid_resolution.xyz);
#ifdef VPLKIT_GBG_TRIANGLE_VOXELS
  vplkit_voxel_tracer tracer = vplkit_make_triangle_voxel_tracer(grid);
  tracer.end_tolerance_voxels = p.end_tolerance_voxels;
#else
  vplkit_voxel_tracer tracer = vplkit_make_voxel_tracer(grid);
  tracer.offset_voxels = p.offset_voxels;
#ifdef VPLKIT_GBG_TRACER_BVH
  tracer.user = true;
#endif
#endif
  vplkit_gbg_params params = vplkit_gbg_params(p.n_dirs, p.dmin, p.depth_tolerance, p.seed, p.accumulator, false);
  int dir_begin = max(p.dir_begin, 0);
  int dir_end = min(p.dir_end, params.n_dirs);
  ivec2 counts = vplkit_gbg_accumulate_gather_point(g, int(pixel), view, tracer, params, dir_begin, dir_end);
  if (counts.x != 0) atomicAdd(vplkit_gbg_stats[VPLKIT_GBG_STAT_HITS], uint(counts.x));
  if (counts.y != 0) atomicAdd(vplkit_gbg_stats[VPLKIT_GBG_STAT_LIT_HITS], uint(counts.y));
}
