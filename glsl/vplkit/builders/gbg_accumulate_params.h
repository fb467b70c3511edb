// SPDX-License-Identifier: MIT
// Interface of gbg_accumulate.comp, shared by the kernel (GLSL) and its hosts (C++,
// vplkit::gpu::gbg_accumulate_params): default bindings, local size, the stats counters, the
// std140 parameter block.
#ifndef VPLKIT_BUILDERS_GBG_ACCUMULATE_PARAMS_H
#define VPLKIT_BUILDERS_GBG_ACCUMULATE_PARAMS_H

#include "vplkit/core/params.h"
#include "vplkit/vpl/light_params.h"

#ifndef VPLKIT_GBG_BINDING_GBUFFER
#define VPLKIT_GBG_BINDING_GBUFFER 0  // SSBO, readonly: vec4 gbuffer[3 W H]
#endif
#ifndef VPLKIT_GBG_BINDING_DPRSM
#define VPLKIT_GBG_BINDING_DPRSM 1  // SSBO, readonly: vec4 dprsm[3 * 2 R^2]
#endif
#ifndef VPLKIT_GBG_BINDING_VOXELS
#define VPLKIT_GBG_BINDING_VOXELS 2  // SSBO, readonly: uint words[] of the voxel grid
#endif
#ifndef VPLKIT_GBG_BINDING_ACC
#define VPLKIT_GBG_BINDING_ACC 3  // SSBO: uint acc[2 * 2 R^2], (lo, hi) per texel, zeroed first
#endif
#ifndef VPLKIT_GBG_BINDING_STATS
#define VPLKIT_GBG_BINDING_STATS 4  // SSBO: uint stats[VPLKIT_GBG_STATS_SIZE], zeroed first
#endif
#ifndef VPLKIT_GBG_BINDING_BVH_NODES
#define VPLKIT_GBG_BINDING_BVH_NODES 10  // SSBO, readonly, VPLKIT_GBG_TRACER_BVH only: vplkit_bvh_node[]
#endif
#ifndef VPLKIT_GBG_BINDING_BVH_TRIANGLES
#define VPLKIT_GBG_BINDING_BVH_TRIANGLES 11  // SSBO, readonly, VPLKIT_GBG_TRACER_BVH only: vplkit_bvh_triangle[]
#endif
#ifndef VPLKIT_GBG_BINDING_PARAMS
#define VPLKIT_GBG_BINDING_PARAMS 5  // uniform block: gbg_accumulate_params
#endif
// With VPLKIT_GBG_TRIANGLE_VOXELS: the triangle voxel grid's arrays (visibility/triangle_voxel_grid.glsl
// layout, as the C++ triangle_voxel_grid's), all readonly SSBOs.
#ifndef VPLKIT_GBG_BINDING_VOXEL_RANK
#define VPLKIT_GBG_BINDING_VOXEL_RANK 6  // uint rank[]
#endif
#ifndef VPLKIT_GBG_BINDING_VOXEL_OFFSETS
#define VPLKIT_GBG_BINDING_VOXEL_OFFSETS 7  // uint offsets[]
#endif
#ifndef VPLKIT_GBG_BINDING_VOXEL_ENTRIES
#define VPLKIT_GBG_BINDING_VOXEL_ENTRIES 8  // uint entries[]
#endif
#ifndef VPLKIT_GBG_BINDING_VOXEL_TRIANGLES
#define VPLKIT_GBG_BINDING_VOXEL_TRIANGLES 9  // vec4 triangles[] (4 per triangle)
#endif
#ifndef VPLKIT_GBG_LOCAL_SIZE
#define VPLKIT_GBG_LOCAL_SIZE 64
#endif

// The stats buffer, shared with gbg_finish.comp (as the C++ gbg_stats).
#define VPLKIT_GBG_STAT_GATHER_POINTS 0   // |G|, counted where count_gather_points is set
#define VPLKIT_GBG_STAT_HITS 1
#define VPLKIT_GBG_STAT_LIT_HITS 2
#define VPLKIT_GBG_STAT_SATURATED_HITS 3  // hits whose units were clamped to max_units
#define VPLKIT_GBG_STAT_REACHED_TEXELS 4  // gbg_finish.comp: raw weight != 0
#define VPLKIT_GBG_STAT_HOLES 5           // gbg_finish.comp: raw weight 0, carries a VPL
#define VPLKIT_GBG_STAT_FILLED 6          // gbg_finish.comp: holes the fill made non-zero
#define VPLKIT_GBG_STATS_SIZE 8

#ifdef __cplusplus
namespace vplkit::gpu {
struct gbg_accumulate_params {
  light_params light;
#else
struct vplkit_gbg_accumulate_params {
  vplkit_light_params light;
#endif
  vec4 grid_min;          // xyz: voxel grid bounds
  vec4 grid_max;
  ivec4 grid_resolution;  // xyz
  int width;              // G-buffer W, H
  int height;
  int resolution;         // DPRSM R
  int n_dirs;             // NBDIR
  int accumulator;        // 0 paper, 1 gathering (vplkit_gbg_accumulator_*)
  int dir_begin;          // this dispatch's directions [dir_begin, dir_end)
  int dir_end;
  int count_gather_points;  // 1 in exactly one dispatch of a build
  uint seed;                // streams are pixel indices
  uint bvh_node_count;      // VPLKIT_GBG_TRACER_BVH: the hierarchy's node count (0: empty)
  uint pad1;
  uint pad2;
  float dmin;
  float depth_tolerance;
  float offset_voxels;         // the voxel tracer's lift off the surface (the C++ default 1.75)
  float end_tolerance_voxels;  // VPLKIT_GBG_TRIANGLE_VOXELS: the tracer's end tolerance (0.01)
  float scale;      // fixed point: units per unit of value (a power of two)
  float max_units;  // <= 2^63
  float pad4;
  float pad5;
};
#ifdef __cplusplus
static_assert(sizeof(gbg_accumulate_params) == 208);
}  // namespace vplkit::gpu
#endif

#endif  // VPLKIT_BUILDERS_GBG_ACCUMULATE_PARAMS_H
