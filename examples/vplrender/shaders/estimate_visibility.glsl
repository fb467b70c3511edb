// SPDX-License-Identifier: MIT
// vplrender's estimate kernels: what V(x, y) and the gathering rays are decided against
// (VR_VISIBILITY, written by render/gpu/gpu_visibility.hpp): the one place the kernels choose.
//   VR_VISIBILITY_PAPER_VOXELS: the paper's binary voxel test on the occupancy words;
//   VR_VISIBILITY_EXACT: the scene's BVH through the pack's user visibility and tracer hooks;
//   VR_VISIBILITY_TRIANGLE_VOXELS (the default): the triangles the voxel grid lists (no
//     self-occlusion at the ends or at junctions, docs/math.md section 7.2).
// vr_make_visibility and vr_make_tracer are what the kernels use; the kind is a constant of the
// variant, so after inlining the pack's callables keep only its code. This file comes first in a
// kernel (it includes estimate_io.glsl): the VPLKIT_* macros must be defined before
// visibility_callables.glsl is first included.
// The includes stay outside the #if: the include resolver inlines each file once wherever it first
// appears and does not evaluate #if.
#ifndef VPLRENDER_ESTIMATE_VISIBILITY_GLSL
#define VPLRENDER_ESTIMATE_VISIBILITY_GLSL

#include "estimate_params.h"

#ifndef VR_VISIBILITY
#define VR_VISIBILITY VR_VISIBILITY_TRIANGLE_VOXELS
#endif
#if VR_VISIBILITY == VR_VISIBILITY_EXACT
#define VPLKIT_USER_VISIBILITY
#define VPLKIT_USER_TRACER
#define VPLKIT_USER_TRACER_WITHIN
#elif VR_VISIBILITY == VR_VISIBILITY_TRIANGLE_VOXELS
#define VPLKIT_TRIANGLE_VOXELS
#define VPLKIT_VOXEL_BRICKS
#endif
// The near-surface test asks one plane per voxel whose triangles share one (the grid's planes, in
// the triangles' buffer below; the same answers as asking every listed triangle).
#define VPLKIT_VOXEL_NEAR_PLANES
// The triangle voxel lists' near-surface test (triangle_voxel_near.glsl) serves the triangle voxel
// tracer and, with exact rays, the clamp's compensation (estimate_clamp_compensation.glsl). The
// resolver inlines a file where it first appears: here, under the condition of both users (its
// dependency voxel_grid.glsl first, outside it, as every kernel needs that).
#include "vplkit/visibility/voxel_grid.glsl"
#if defined(VPLKIT_TRIANGLE_VOXELS) || (defined(VR_CLAMP_COMPENSATION) && VR_VISIBILITY == VR_VISIBILITY_EXACT)
#include "vplkit/visibility/triangle_voxel_near.glsl"
#endif
#include "ray_scene.glsl"
#include "vplkit/visibility/bvh_visibility.glsl"
#include "vplkit/visibility/visibility_callables.glsl"
#include "estimate_io.glsl"  // after the macros: it includes visibility_callables.glsl too

layout(std430, binding = VR_ESTIMATE_BINDING_VOXELS) restrict readonly buffer VrVoxels { uint vr_voxels[]; };
uint vplkit_load_voxel_word(uint word_index) { return vr_voxels[word_index]; }
vplkit_voxel_grid vr_grid() {
  return vplkit_voxel_grid(vr_params.grid_min.xyz, vr_params.grid_max.xyz, vr_params.grid_resolution.xyz);
}

// The triangle voxel grid beside the occupancy words (triangle_voxel_grid.glsl's layout): the
// triangle voxel visibility's, and with exact rays the clamp compensation's near-surface test
// (estimate_clamp_compensation.glsl; the BVH tracer cannot say what lies within dmin).
#if VR_VISIBILITY == VR_VISIBILITY_TRIANGLE_VOXELS || (defined(VR_CLAMP_COMPENSATION) && VR_VISIBILITY == VR_VISIBILITY_EXACT)
layout(std430, binding = VR_ESTIMATE_BINDING_VOXEL_RANK) restrict readonly buffer VrVoxelRank { uint vr_voxel_rank[]; };
layout(std430, binding = VR_ESTIMATE_BINDING_VOXEL_OFFSETS) restrict readonly buffer VrVoxelOffsets {
  uint vr_voxel_offsets[];
};
layout(std430, binding = VR_ESTIMATE_BINDING_VOXEL_ENTRIES) restrict readonly buffer VrVoxelEntries {
  uint vr_voxel_entries[];
};
layout(std430, binding = VR_ESTIMATE_BINDING_VOXEL_TRIANGLES) restrict readonly buffer VrVoxelTriangles {
  vec4 vr_voxel_triangles[];
};
uint vplkit_load_voxel_rank(uint word_index) { return vr_voxel_rank[word_index]; }
uint vplkit_load_voxel_offset(uint index) { return vr_voxel_offsets[index]; }
uint vplkit_load_voxel_entry(uint index) { return vr_voxel_entries[index]; }
vec4 vplkit_load_voxel_triangle(uint index) { return vr_voxel_triangles[index]; }
// The grid's planes follow the triangles in their buffer (raster/gpu_scene_buffers.hpp), one vec4
// per occupied voxel plus one, so that they end where the buffer does and start offsets' length
// (occupied + 1) before its end: a kernel that asks them needs no binding of its own (the estimate
// kernels with the compensation are at llvmpipe's 16 storage blocks).
vec4 vplkit_load_voxel_near_plane(uint occupied_index) {
  return vr_voxel_triangles[uint(vr_voxel_triangles.length() - vr_voxel_offsets.length()) + occupied_index];
}
#endif

#if VR_VISIBILITY == VR_VISIBILITY_EXACT
layout(std430, binding = VR_ESTIMATE_BINDING_BVH_NODES) restrict readonly buffer VrBvhNodes { vplkit_bvh_node vr_bvh_nodes[]; };
layout(std430, binding = VR_ESTIMATE_BINDING_BVH_TRIANGLES) restrict readonly buffer VrBvhTriangles {
  vplkit_bvh_triangle vr_bvh_triangles[];
};
vplkit_bvh_node vplkit_load_bvh_node(uint index) { return vr_bvh_nodes[index]; }
vplkit_bvh_triangle vplkit_load_bvh_triangle(uint slot) { return vr_bvh_triangles[slot]; }
bool vplkit_user_visible(vec3 x, vec3 n_x, vec3 y, vec3 n_y) {
  return vplkit_bvh_visible(vplkit_bvh(vr_params.bvh_node_count), x, n_x, y, n_y);
}
// The hits' shading normals (ray_scene.glsl, as render/cpu/ray_scene.cpp's trace gives them): the
// per-triangle corner normals.
layout(std430, binding = VR_ESTIMATE_BINDING_TRIANGLE_SHADING) restrict readonly buffer VrTriangleShading {
  vr_triangle_shading vr_triangle_shadings[];
};
vr_triangle_shading vr_load_triangle_shading(uint triangle) { return vr_triangle_shadings[triangle]; }
uint vr_load_shading_word(uint index) { return 0u; }  // albedos: exact.comp's; not read here
// The BVH's closest hit from x (lifted by the BVH's surface offset along n_x) along dir for t in
// (0, t_max] of the lifted ray, as vplkit_bvh_trace gives it, with the hit's interpolated shading
// normal.
vplkit_ray_hit vr_trace_bvh(vec3 x, vec3 n_x, vec3 dir, float offset, float t_max) {
  vplkit_bvh b = vplkit_bvh(vr_params.bvh_node_count);
  vplkit_bvh_hit h = vplkit_bvh_closest_hit(b, vplkit_bvh_offset_point(x, n_x, offset), dir, 0.0, t_max);
  vplkit_ray_hit r = vplkit_ray_hit(h.hit, vec3(0.0), vec3(0.0), vec3(0.0));
  if (h.hit) {
    r.position = h.position;
    r.normal = h.normal;
    r.shading_normal = vr_shading_normal(h);
  }
  return r;
}
vplkit_ray_hit vplkit_user_trace(vec3 x, vec3 n_x, vec3 dir) {
  return vr_trace_bvh(x, n_x, dir, vplkit_bvh_surface_offset(vplkit_bvh(vr_params.bvh_node_count)), vplkit_bvh_infinity());
}
// vplkit_user_trace's hit when it lies within reach of x (the clamp's compensation asks within
// dmin), by a traversal that stops at t = (reach + offset) / |dir|: the ray starts offset from x,
// so no hit within reach of x lies farther along it, and the walk visits only the nodes near x
// instead of the whole ray's. Beyond reach, no hit or a farther one (the trace_within protocol).
vplkit_ray_hit vplkit_user_trace_within(vec3 x, vec3 n_x, vec3 dir, float reach) {
  float offset = vplkit_bvh_surface_offset(vplkit_bvh(vr_params.bvh_node_count));
  // Widened by 1e-5 relative, far above the rounding of the sum and the division (GLSL's 2.5 ulp),
  // so a hit at exactly reach is never lost; a farther hit returned is allowed.
  return vr_trace_bvh(x, n_x, dir, offset, (reach + offset) / length(dir) * (1.0 + 1e-5));
}
vplkit_visibility vr_make_visibility(vplkit_voxel_grid grid) {
  return vplkit_visibility(vplkit_visibility_user, grid, 0.0, 0.0, 0.0, 0.0);
}
// VR_LIT_SHADOW_RAY (--lit-test shadow-ray): gathering's lit test by a BVH shadow ray.
vplkit_voxel_tracer vr_make_tracer(vplkit_voxel_grid grid) {
  vplkit_voxel_tracer tr =
      vplkit_voxel_tracer(grid, 0.0, true, false, 0.0, false, vplkit_make_always_visible(), false, 0.0, 0u);
#ifdef VR_LIT_SHADOW_RAY
  tr = vplkit_tracer_with_light_visibility(tr, vr_make_visibility(grid));
#endif
  return tr;
}
#else
// No BVH buffers: the pack's BVH functions (and ray_scene.glsl's) are compiled but never called.
vplkit_bvh_node vplkit_load_bvh_node(uint index) { return vplkit_bvh_node(vec3(0.0), 0u, vec3(0.0), 0u); }
vplkit_bvh_triangle vplkit_load_bvh_triangle(uint slot) {
  return vplkit_bvh_triangle(vec3(0.0), 0u, vec3(0.0), 0u, vec3(0.0), 0u);
}
vr_triangle_shading vr_load_triangle_shading(uint triangle) {
  return vr_triangle_shading(vec4(0.0), vec4(0.0), vec4(0.0), vec4(0.0), vec2(0.0), 0u, 0u);
}
uint vr_load_shading_word(uint index) { return 0u; }
#if VR_VISIBILITY == VR_VISIBILITY_TRIANGLE_VOXELS
// The brick level the marches skip empty space with (voxel_bricks.glsl).
layout(std430, binding = VR_ESTIMATE_BINDING_VOXEL_BRICKS) restrict readonly buffer VrVoxelBricks {
  uint vr_voxel_bricks[];
};
uint vplkit_load_voxel_brick_word(uint word_index) { return vr_voxel_bricks[word_index]; }
vplkit_visibility vr_make_visibility(vplkit_voxel_grid grid) { return vplkit_make_triangle_voxel_visibility(grid); }
vplkit_voxel_tracer vr_make_tracer(vplkit_voxel_grid grid) { return vplkit_make_triangle_voxel_tracer(grid); }
#elif VR_VISIBILITY == VR_VISIBILITY_PAPER_VOXELS
vplkit_visibility vr_make_visibility(vplkit_voxel_grid grid) { return vplkit_make_voxel_visibility(grid); }
vplkit_voxel_tracer vr_make_tracer(vplkit_voxel_grid grid) { return vplkit_make_voxel_tracer(grid); }
#else
#error "VR_VISIBILITY must be VR_VISIBILITY_PAPER_VOXELS, VR_VISIBILITY_EXACT or VR_VISIBILITY_TRIANGLE_VOXELS"
#endif
#endif

#endif  // VPLRENDER_ESTIMATE_VISIBILITY_GLSL
