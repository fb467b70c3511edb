// SPDX-License-Identifier: MIT
// vplrender's estimator kernel (--backend gpu): one invocation per pixel, glue between the
// renderer's buffers and the GLSL pack's estimators. Compiled once per method with VR_METHOD
// defined by the host (gpu_backend.cpp puts "#version 430" first and the define in the preamble).
//
// Passes: under llvmpipe's loop budget (docs/glsl.md: 65535 loop iterations per invocation, then
// every loop is left silently) the host splits the samples (texels for the
// reference) into ranges [u_begin, u_end) small enough for that budget and dispatches this kernel
// once per range. Each pass runs the pack's range form of the method's estimator
// (vplkit_estimate_*_range, vplkit_exhaustive_vpl_sum_range) on the pixel's state, kept in the
// state buffer between passes; consecutive ranges perform exactly the float operations and draws
// of the one-shot estimator, i.e. of the C++ loop of cpu_backend.cpp, whatever the split. The last
// pass writes the estimator's _finish, plus vplkit_direct_light when u_direct is set, to the
// RGBA32F output; the host applies max(., 0) and the finite guard as the CPU backend does.
//
// Random numbers: vplkit_make_counter_rng(u_seed, pixel), the CPU backend's stream per pixel (the
// patch reference reads it at fixed counters, so every pass starts from the pixel's fresh stream).
// Distributions: defensive mixtures as CDF + guide arrays and the mixture scalars (pack
// distribution/defensive_mixture.glsl). Built on the GPU for global, local, gbg, mis and
// mis-as-published (gpu_cdf.cpp: cdf_build.comp, the same layout); the vr_dist_* layout below is
// also what an upload of C++ vplkit::make_vpl_distribution objects fills.
#define VR_REFERENCE 0
#define VR_VPL_SAMPLING 1
#define VR_LOCAL 2
#define VR_GATHER 3
#define VR_MIS 4

// Visibility (VR_VISIBILITY, defined by the host beside VR_METHOD: render/gpu/gpu_visibility.hpp):
// what V(x, y) and the gathering rays are decided against. 0: the paper's binary voxel test on the
// occupancy words (binding 2). 1: exact, the scene's BVH (bindings 8 and 9, u_bvh_node_count)
// through the pack's user visibility and tracer hooks. 2 (the default): the triangles the voxel
// grid lists (the words at binding 2, rank, offsets, entries and triangles at 10-13, bricks at 14; no
// self-occlusion at the ends or at junctions, docs/math.md section 7.2). This block is the only
// place the kernel chooses; vr_make_visibility and vr_make_tracer are what main() uses. The
// includes stay outside the #if: the include resolver inlines each file once wherever it first
// appears and does not evaluate #if.
#define VR_VISIBILITY_PAPER_VOXELS 0
#define VR_VISIBILITY_EXACT 1
#define VR_VISIBILITY_TRIANGLE_VOXELS 2
#ifndef VR_VISIBILITY
#define VR_VISIBILITY VR_VISIBILITY_TRIANGLE_VOXELS
#endif
#if VR_VISIBILITY == VR_VISIBILITY_EXACT
#define VPLKIT_USER_VISIBILITY
#define VPLKIT_USER_TRACER
#elif VR_VISIBILITY == VR_VISIBILITY_TRIANGLE_VOXELS
#define VPLKIT_TRIANGLE_VOXELS
#define VPLKIT_VOXEL_BRICKS
#endif
#include "vplkit/visibility/bvh_visibility.glsl"
#include "vplkit/visibility/visibility_callables.glsl"
#include "ray_scene.glsl"
#if VR_VISIBILITY == VR_VISIBILITY_EXACT
layout(std430, binding = 8) readonly buffer VrBvhNodes { vplkit_bvh_node vr_bvh_nodes[]; };
layout(std430, binding = 9) readonly buffer VrBvhTriangles { vplkit_bvh_triangle vr_bvh_triangles[]; };
uniform uint u_bvh_node_count;
vplkit_bvh_node vplkit_load_bvh_node(uint index) { return vr_bvh_nodes[index]; }
vplkit_bvh_triangle vplkit_load_bvh_triangle(uint slot) { return vr_bvh_triangles[slot]; }
bool vplkit_user_visible(vec3 x, vec3 n_x, vec3 y, vec3 n_y) {
  return vplkit_bvh_visible(vplkit_bvh(u_bvh_node_count), x, n_x, y, n_y);
}
// The hits' shading normals (ray_scene.glsl, as render/cpu/ray_scene.cpp's trace gives them):
// the per-triangle corner normals at binding 10 (the triangle voxel lists' slot, unused here).
layout(std430, binding = 10) readonly buffer VrTriangleShading { vr_triangle_shading vr_triangle_shadings[]; };
vr_triangle_shading vr_load_triangle_shading(uint triangle) { return vr_triangle_shadings[triangle]; }
uint vr_load_shading_word(uint index) { return 0u; }  // albedos: exact.comp's; not read here
// vplkit_bvh_trace, with the hit's interpolated shading normal.
vplkit_ray_hit vplkit_user_trace(vec3 x, vec3 n_x, vec3 dir) {
  vplkit_bvh b = vplkit_bvh(u_bvh_node_count);
  vplkit_bvh_hit h = vplkit_bvh_closest_hit(b, vplkit_bvh_offset_point(x, n_x, vplkit_bvh_surface_offset(b)), dir);
  vplkit_ray_hit r = vplkit_ray_hit(h.hit, vec3(0.0), vec3(0.0), vec3(0.0));
  if (h.hit) {
    r.position = h.position;
    r.normal = h.normal;
    r.shading_normal = vr_shading_normal(h);
  }
  return r;
}
vplkit_visibility vr_make_visibility(vplkit_voxel_grid grid) {
  return vplkit_visibility(vplkit_visibility_user, grid, 0.0, 0.0, 0.0);
}
// VR_LIT_SHADOW_RAY (the host's --lit-test shadow-ray): gathering's lit test by a BVH shadow ray.
vplkit_voxel_tracer vr_make_tracer(vplkit_voxel_grid grid) {
  vplkit_voxel_tracer tr = vplkit_voxel_tracer(grid, 0.0, true, false, 0.0, false, vplkit_make_always_visible());
#ifdef VR_LIT_SHADOW_RAY
  tr = vplkit_tracer_with_light_visibility(tr, vr_make_visibility(grid));
#endif
  return tr;
}
#else
// No BVH buffers: the pack's BVH functions (and ray_scene.glsl's) are compiled but never called.
vplkit_bvh_node vplkit_load_bvh_node(uint index) { return vplkit_bvh_node(vec3(0.0), 0u, vec3(0.0), 0u); }
vr_triangle_shading vr_load_triangle_shading(uint triangle) {
  return vr_triangle_shading(vec4(0.0), vec4(0.0), vec4(0.0), vec4(0.0), vec2(0.0), 0u, 0u);
}
uint vr_load_shading_word(uint index) { return 0u; }
vplkit_bvh_triangle vplkit_load_bvh_triangle(uint slot) {
  return vplkit_bvh_triangle(vec3(0.0), 0u, vec3(0.0), 0u, vec3(0.0), 0u);
}
#if VR_VISIBILITY == VR_VISIBILITY_TRIANGLE_VOXELS
// The triangle voxel grid beside the occupancy words (triangle_voxel_grid.glsl's layout).
layout(std430, binding = 10) readonly buffer VrVoxelRank { uint vr_voxel_rank[]; };
layout(std430, binding = 11) readonly buffer VrVoxelOffsets { uint vr_voxel_offsets[]; };
layout(std430, binding = 12) readonly buffer VrVoxelEntries { uint vr_voxel_entries[]; };
layout(std430, binding = 13) readonly buffer VrVoxelTriangles { vec4 vr_voxel_triangles[]; };
uint vplkit_load_voxel_rank(uint word_index) { return vr_voxel_rank[word_index]; }
uint vplkit_load_voxel_offset(uint index) { return vr_voxel_offsets[index]; }
uint vplkit_load_voxel_entry(uint index) { return vr_voxel_entries[index]; }
vec4 vplkit_load_voxel_triangle(uint index) { return vr_voxel_triangles[index]; }
// The brick level the marches skip empty space with (voxel_bricks.glsl).
layout(std430, binding = 14) readonly buffer VrVoxelBricks { uint vr_voxel_bricks[]; };
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

layout(local_size_x = 64) in;

#include "vplkit/core/gather_point.glsl"
#include "vplkit/distribution/alias_table.glsl"
#include "vplkit/distribution/defensive_mixture.glsl"
#include "vplkit/distribution/flat_face_roulette.glsl"
#include "vplkit/estimators/estimator_state.glsl"
#include "vplkit/estimators/gathering_estimator.glsl"
#include "vplkit/estimators/local_estimator.glsl"
#include "vplkit/estimators/mis_estimator.glsl"
#include "vplkit/estimators/vpl_sampling_estimator.glsl"
#include "vplkit/estimators/vpl_sum.glsl"
#include "vplkit/sampling/rng.glsl"
#include "vplkit/visibility/visibility_callables.glsl"
#include "vplkit/vpl/direct_light.glsl"

// A G-buffer pixel or a DPRSM texel: xyz used, w ignored (std430 vec3 arrays take 16 bytes anyway).
struct vr_surfel {
  vec4 position;
  vec4 normal;
  vec4 albedo;
};
// A pixel's estimator state between passes: vplkit_estimator_state (sum, rng), or for the
// reference vplkit_vpl_sum_state (sum, compensation).
struct vr_state {
  vec4 sum;
  vec4 comp;   // the reference's compensation
  uvec4 rng;   // key, counter
};

layout(std430, binding = 0) readonly buffer VrGbuffer { vr_surfel vr_gbuffer[]; };
layout(std430, binding = 1) readonly buffer VrDprsm { vr_surfel vr_dprsm[]; };
layout(std430, binding = 2) readonly buffer VrVoxels { uint vr_voxels[]; };
// CDF floats (as bits) and guide entries of every discrete_cdf, back to back.
layout(std430, binding = 3) readonly buffer VrDistData { uint vr_dist_data[]; };
// 12 uints per mixture d (learned id, size, m, total bits, fallback id, size, m, total bits,
// effective eps, fallback scale, learned scale bits, 0), then from u_slot_base two uints per
// discrete_cdf slot: offsets of its cdf and its guide in vr_dist_data.
layout(std430, binding = 4) readonly buffer VrDistMeta { uint vr_dist_meta[]; };
layout(std430, binding = 5) buffer VrState { vr_state vr_states[]; };
layout(std430, binding = 6) writeonly buffer VrOut { vec4 vr_out[]; };
// --sampler alias / --face-selection roulette: each mixture's components (k = 2 d + c, c = 0 the
// learned part, 1 the fallback), built on the host (render/mixture_components.hpp) and packed by
// gpu_backend.cpp's pack_components: 12 uints per component, then the arrays they point into.
layout(std430, binding = 7) readonly buffer VrComponents { uint vr_components[]; };

uniform int u_width;
uniform int u_height;
uniform int u_dprsm_res;
uniform vec3 u_light_pos;
uniform vec3 u_light_int;
uniform vec3 u_frame_pos;
uniform vec3 u_axis_x;
uniform vec3 u_axis_y;
uniform vec3 u_axis_z;
uniform vec3 u_grid_min;
uniform vec3 u_grid_max;
uniform ivec3 u_grid_res;
uniform float u_dmin;
uniform float u_depth_tol;
uniform uint u_seed;
uniform int u_begin;       // this pass's range of samples / rounds / directions / texels
uniform int u_end;
uniform int u_first_pass;  // 1: start the pixel's state
uniform int u_last_pass;   // 1: write the estimate
uniform int u_n_dirs;
uniform int u_n_vpls;
uniform int u_n_samples;   // VPL sampling: samples; local: rounds
uniform int u_n_dists;
uniform int u_mis_mode;
uniform uint u_slot_base;
uniform int u_direct;  // 1: add the direct light (--direct) in the last pass
uniform int u_cdf_search;          // 0: guide table (vplkit_defensive_mixture_sample), 1: plain binary search
uniform int u_sampler;             // 0: the mixtures' CDFs, 1: alias tables, 2: face roulettes (binding 7)
uniform int u_local_combination;   // vplkit_local_balance or vplkit_local_average (--local-combination)
uniform int u_vpl_mode;            // vplkit_vpl_point or vplkit_vpl_patch (--vpl-mode), with u_depth_tol as window
uniform int u_strata;              // the patch reference's strata per texel side (m of m x m)

vplkit_gather_point vplkit_load_gather_point(int pixel) {
  return vplkit_unpack_gather_point(vr_gbuffer[pixel].position, vr_gbuffer[pixel].normal, vr_gbuffer[pixel].albedo);
}
vec3 vplkit_load_dprsm_position(int texel) { return vr_dprsm[texel].position.xyz; }
vec3 vplkit_load_dprsm_normal(int texel) { return vr_dprsm[texel].normal.xyz; }
vec3 vplkit_load_dprsm_albedo(int texel) { return vr_dprsm[texel].albedo.xyz; }
uint vplkit_load_voxel_word(uint word_index) { return vr_voxels[word_index]; }
// Slots from VR_COMPONENT_SLOT on are the roulettes' face CDFs in vr_components: slot
// VR_COMPONENT_SLOT + 2 k + face, its offsets at 12 k + 3 face.
const uint VR_COMPONENT_SLOT = 0x80000000u;
uint vr_face_record(uint slot) { return 12u * ((slot - VR_COMPONENT_SLOT) >> 1u) + 3u * (slot & 1u); }
float vplkit_load_cdf(uint slot, uint i) {
  if (slot >= VR_COMPONENT_SLOT) return uintBitsToFloat(vr_components[vr_components[vr_face_record(slot)] + i]);
  return uintBitsToFloat(vr_dist_data[vr_dist_meta[u_slot_base + 2u * slot] + i]);
}
uint vplkit_load_guide(uint slot, uint j) {
  if (slot >= VR_COMPONENT_SLOT) return vr_components[vr_components[vr_face_record(slot) + 1u] + j];
  return vr_dist_data[vr_dist_meta[u_slot_base + 2u * slot + 1u] + j];
}
vplkit_alias_bin vplkit_load_alias_bin(uint table, uint j) {
  uint b = vr_components[12u * table] + 3u * j;
  return vplkit_alias_bin(uintBitsToFloat(vr_components[b]), uintBitsToFloat(vr_components[b + 1u]),
                          vr_components[b + 2u]);
}

vplkit_defensive_mixture vr_mixture(uint d) {
  uint b = 12u * d;
  vplkit_discrete_cdf learned = vplkit_discrete_cdf(vr_dist_meta[b], vr_dist_meta[b + 1u], vr_dist_meta[b + 2u],
                                                    uintBitsToFloat(vr_dist_meta[b + 3u]));
  vplkit_discrete_cdf fallback = vplkit_discrete_cdf(vr_dist_meta[b + 4u], vr_dist_meta[b + 5u],
                                                     vr_dist_meta[b + 6u], uintBitsToFloat(vr_dist_meta[b + 7u]));
  return vplkit_defensive_mixture(learned, fallback, uintBitsToFloat(vr_dist_meta[b + 8u]),
                                  uintBitsToFloat(vr_dist_meta[b + 9u]), uintBitsToFloat(vr_dist_meta[b + 10u]));
}
// Component k as the C++ alias_table / flat_face_roulette (the roulette's scalars as uploaded).
vplkit_alias_table vr_alias(uint k) {
  return vplkit_alias_table(k, vr_components[12u * k + 10u], uintBitsToFloat(vr_components[12u * k + 2u]));
}
vplkit_flat_face_roulette vr_roulette(uint k) {
  uint r = 12u * k;
  uint n = vr_components[r + 10u], m = vr_components[r + 11u];
  vplkit_discrete_cdf front = vplkit_discrete_cdf(VR_COMPONENT_SLOT + 2u * k, n, m, uintBitsToFloat(vr_components[r + 2u]));
  vplkit_discrete_cdf back = vplkit_discrete_cdf(VR_COMPONENT_SLOT + 2u * k + 1u, n, m,
                                                 uintBitsToFloat(vr_components[r + 5u]));
  vplkit_face_roulette f = vplkit_face_roulette(front, back, uintBitsToFloat(vr_components[r + 6u]),
                                                uintBitsToFloat(vr_components[r + 7u]),
                                                uintBitsToFloat(vr_components[r + 8u]),
                                                uintBitsToFloat(vr_components[r + 9u]));
  return vplkit_make_flat_face_roulette(f, u_dprsm_res);
}
vplkit_discrete_sample vr_component_sample(uint k, float u) {
  if (u_sampler == 1) return vplkit_alias_table_sample(vr_alias(k), u);
  return vplkit_flat_face_roulette_sample(vr_roulette(k), u);
}
float vr_component_pmf(uint k, uint i) {
  if (u_sampler == 1) return vplkit_alias_table_pmf(vr_alias(k), i);
  return vplkit_flat_face_roulette_pmf(vr_roulette(k), i);
}
// render/mixture_components.hpp's resampled_mixture: the mixture's split, its components replaced.
float vr_resampled_pmf(vplkit_defensive_mixture m, uint d, uint i) {
  return vplkit_defensive_mixture_pmf(m.effective_eps, vr_component_pmf(2u * d, i), vr_component_pmf(2u * d + 1u, i));
}
vplkit_discrete_sample vr_resampled_sample(uint d, float u) {
  vplkit_defensive_mixture m = vr_mixture(d);
  if (vplkit_defensive_mixture_empty(m)) return vplkit_discrete_sample(0u, 0.0);
  float e = m.effective_eps;
  u = vplkit_discrete_clamp_u(u);
  uint i = u < e ? vr_component_sample(2u * d + 1u, vplkit_discrete_clamp_u(u * m.fallback_scale)).index
                 : vr_component_sample(2u * d, vplkit_discrete_clamp_u((u - e) * m.learned_scale)).index;
  return vplkit_discrete_sample(i, vr_resampled_pmf(m, d, i));
}

vplkit_discrete_sample vplkit_estimator_distribution_sample(uint distribution, float u) {
  // Uniform branches (no divergence). --cdf-search: both searches return the same index and pmf.
  if (u_sampler != 0) return vr_resampled_sample(distribution, u);
  if (u_cdf_search != 0) return vplkit_defensive_mixture_sample_binary_search(vr_mixture(distribution), u);
  return vplkit_defensive_mixture_sample(vr_mixture(distribution), u);
}
float vplkit_estimator_distribution_pmf(uint distribution, uint index) {
  if (u_sampler != 0) return vr_resampled_pmf(vr_mixture(distribution), distribution, index);
  return vplkit_defensive_mixture_pmf(vr_mixture(distribution), index);
}

void main() {
  // Groups are spread over y past the x limit (vplkit::gl::dispatch_linear); pixel = flat index.
  uint p = gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x;
  if (p >= uint(u_width) * uint(u_height)) return;
  vplkit_gather_point gp = vplkit_load_gather_point(int(p));
  vr_state st;
  if (u_first_pass != 0) {
    vplkit_counter_rng r0 = vplkit_make_counter_rng(u_seed, p);
    st.sum = vec4(0.0);
    st.comp = vec4(0.0);
    st.rng = uvec4(r0.key, r0.counter, 0u, 0u);
  } else {
    st = vr_states[p];
  }
  vplkit_estimator_state est = vplkit_estimator_state(st.sum.xyz, vplkit_counter_rng(st.rng.x, st.rng.y));
  vplkit_vpl_sum_state ref = vplkit_vpl_sum_state(st.sum.xyz, st.comp.xyz);
  vplkit_dprsm_view view = vplkit_dprsm_view(
      u_dprsm_res, vplkit_point_light(u_light_pos, u_light_int,
                                      vplkit_light_frame(u_frame_pos, u_axis_x, u_axis_y, u_axis_z)));
  vplkit_voxel_grid grid = vplkit_voxel_grid(u_grid_min, u_grid_max, u_grid_res);
  vplkit_visibility visibility = vr_make_visibility(grid);
  vplkit_voxel_tracer tracer = vr_make_tracer(grid);
  bool valid = vplkit_gather_point_valid(gp);
  if (valid) {
#if VR_METHOD == VR_REFERENCE
    if (u_vpl_mode == vplkit_vpl_patch)
      vplkit_exhaustive_vpl_patch_sum_range(gp, view, ref, u_begin, u_end, vplkit_make_counter_rng(u_seed, p), u_strata,
                                            visibility, u_dmin, u_depth_tol);
    else
      vplkit_exhaustive_vpl_sum_range(gp, view, ref, u_begin, u_end, visibility, u_dmin);
#elif VR_METHOD == VR_VPL_SAMPLING
    vplkit_estimate_vpl_sampling_range(gp, view, 0u, est, u_begin, u_end, visibility, u_dmin, u_vpl_mode,
                                       u_depth_tol);
#elif VR_METHOD == VR_LOCAL
    vplkit_estimate_local_range(gp, view, 0u, u_n_dists, est, u_begin, u_end, visibility, u_dmin,
                                u_local_combination, u_vpl_mode, u_depth_tol);
#elif VR_METHOD == VR_GATHER
    vplkit_estimate_gathering_range(gp, view, est, u_begin, u_end, tracer, u_depth_tol);
#elif VR_METHOD == VR_MIS
    vplkit_estimate_mis_range(gp, view, 0u, est, u_begin, u_end, u_n_dirs, u_n_vpls, tracer, visibility,
                              u_depth_tol, u_mis_mode, u_vpl_mode);
#endif
  }
#if VR_METHOD == VR_REFERENCE
  st.sum = vec4(ref.sum, 0.0);
  st.comp = vec4(ref.compensation, 0.0);
#else
  st.sum = vec4(est.sum, 0.0);
  st.rng = uvec4(est.rng.key, est.rng.counter, 0u, 0u);
#endif
  vr_states[p] = st;
  if (u_last_pass != 0) {
    vec3 e = vec3(0.0);
    if (valid) {
#if VR_METHOD == VR_REFERENCE
      e = u_vpl_mode == vplkit_vpl_patch ? vplkit_exhaustive_vpl_patch_sum_finish(ref, u_strata)
                                         : vplkit_exhaustive_vpl_sum_finish(ref);
#elif VR_METHOD == VR_VPL_SAMPLING
      e = vplkit_estimate_vpl_sampling_finish(est, u_n_samples);
#elif VR_METHOD == VR_LOCAL
      e = vplkit_estimate_local_finish(est, u_n_samples);
#elif VR_METHOD == VR_GATHER
      e = vplkit_estimate_gathering_finish(est, u_n_dirs);
#elif VR_METHOD == VR_MIS
      e = vplkit_estimate_mis_finish(est, u_n_dirs, u_n_vpls, u_mis_mode);
#endif
      if (u_direct != 0) e += vplkit_direct_light(gp, view);
    }
    vr_out[p] = vec4(e, 1.0);
  }
}
