// SPDX-License-Identifier: MIT
// Interface of vplrender's estimate kernels (estimate_<estimator>.comp and exact.comp beside this
// file), shared by the kernels (GLSL) and their host (C++, render/gpu/gpu_backend.cpp, namespace
// vplrender::gpu) in the two-language form of the pack's <kernel>_params.h (vplkit/core/params.h):
// the bindings, the local size, the specialisation defines and their values, the std140 parameter
// block and the std430 records of the buffers. tests/renderer/renderer_gpu_estimate_params_test.cpp
// asks the GL driver where every member lies and checks the C++ offsets against it.
//
// Specialisation (docs/renderer.md, "The estimate kernels"): every switch of a render that does
// not change between its dispatches is a compile-time define, never a uniform, so each variant
// carries only its own code and state. A GPU runs a uniform branch without divergence, but its
// register allocation must hold every path's live values (spills to local memory on NVIDIA) and
// its instruction cache every path's code; llvmpipe runs both sides of every branch under a mask.
#ifndef VPLRENDER_ESTIMATE_PARAMS_H
#define VPLRENDER_ESTIMATE_PARAMS_H

// VR_DPRSM_PLANES: 1 (default) the kernels read the DPRSM's plane records (binding
// VR_ESTIMATE_BINDING_DPRSM_PLANES; render/gpu/gpu_dprsm_planes.hpp) through the pack's optional
// accessor, defined here before light_params.h first includes dprsm_view.glsl; 0 the pack computes
// each record from the three surfel vectors (render_settings::dprsm_planes = false). Same values.
#ifndef __cplusplus
#ifndef VR_DPRSM_PLANES
#define VR_DPRSM_PLANES 1
#endif
#if VR_DPRSM_PLANES
#define VPLKIT_DPRSM_PLANE_ACCESSOR
#endif
#endif

#include "vplkit/core/params.h"
#include "estimate_ris_params.h"  // ris_params, the block's last member
#ifdef __cplusplus
#include <cstddef>  // offsetof
#endif
#include "vplkit/vpl/light_params.h"

// ---- bindings: each resource its own number -------------------------------------------------------
#define VR_ESTIMATE_BINDING_GBUFFER 0     // SSBO, readonly: vr_surfel gbuffer[W H]
#define VR_ESTIMATE_BINDING_DPRSM 1       // SSBO, readonly: vr_surfel dprsm[2 R^2]
#define VR_ESTIMATE_BINDING_VOXELS 2      // SSBO, readonly: uint words[] (the occupancy grid)
#define VR_ESTIMATE_BINDING_CDF_DATA 3    // SSBO, readonly: uint data[] (cdf floats as bits, then guides)
#define VR_ESTIMATE_BINDING_MIXTURES 4    // SSBO, readonly: vr_mixture_record mixtures[D]
#define VR_ESTIMATE_BINDING_STATE 5       // SSBO: vr_pixel_state states[W H] (VR_SPLIT 1 only)
#define VR_ESTIMATE_BINDING_OUT 6         // SSBO, writeonly: vec4 out[W H] (rgb: the estimate; with
                                          // VR_CLAMP_COMPENSATION_PASS first the compensation's term)
#define VR_ESTIMATE_BINDING_COMPONENTS 7  // SSBO, readonly: uint components[] (VR_SAMPLER alias / roulette),
                                          // or uint shares[D L] (VR_SAMPLER share tree: tree d at d L)
#define VR_ESTIMATE_BINDING_BVH_NODES 8   // SSBO, readonly: vplkit_bvh_node[] (exact rays)
#define VR_ESTIMATE_BINDING_BVH_TRIANGLES 9         // SSBO, readonly: vplkit_bvh_triangle[] (exact rays)
#define VR_ESTIMATE_BINDING_TRIANGLE_SHADING 10     // SSBO, readonly: vr_triangle_shading[] (exact rays)
#define VR_ESTIMATE_BINDING_SHADING_POOL 11         // SSBO, readonly: uint pool[] (exact.comp's albedos)
#define VR_ESTIMATE_BINDING_VOXEL_RANK 12           // SSBO, readonly: uint rank[] (triangle voxels)
#define VR_ESTIMATE_BINDING_VOXEL_OFFSETS 13        // SSBO, readonly: uint offsets[]
#define VR_ESTIMATE_BINDING_VOXEL_BRICKS 14          // SSBO, readonly: uint bricks[] (triangle voxels' brick level)
#define VR_ESTIMATE_BINDING_VOXEL_ENTRIES 15        // SSBO, readonly: uint entries[]
#define VR_ESTIMATE_BINDING_VOXEL_TRIANGLES 16      // SSBO, readonly: vec4 triangles[] (4 per triangle)
#define VR_ESTIMATE_BINDING_PARAMS 17               // uniform block: vr_estimate_params
#define VR_ESTIMATE_BINDING_DPRSM_PLANES 18         // SSBO, readonly: vec4 planes[2 R^2] (vplkit/vpl/dprsm_plane.glsl)
#define VR_ESTIMATE_BINDING_CLAMP_LIST 19           // SSBO: uvec4 header (indirect groups x y z, count), uint pixels[W H]
                                                    // (the clamp compensation's passes; their terms go to OUT)
#define VR_ESTIMATE_LOCAL_SIZE 64                   // invocations per work group, one per pixel

// ---- specialisation defines (the host writes each into the kernel's preamble) --------------------
// VR_VISIBILITY: what V(x, y) and the gathering rays are decided against (render/gpu/gpu_visibility.hpp
// writes it; estimate_visibility.glsl reads it).
#define VR_VISIBILITY_PAPER_VOXELS 0
#define VR_VISIBILITY_EXACT 1
#define VR_VISIBILITY_TRIANGLE_VOXELS 2
// VR_SAMPLER: how a distribution turns u into a texel (--sampler, --face-selection, --cdf-search).
#define VR_SAMPLER_CDF_GUIDE 0   // the mixtures' CDFs, guide table (vplkit_defensive_mixture_sample)
#define VR_SAMPLER_CDF_BINARY 1  // the mixtures' CDFs, plain binary search (same index and pmf)
#define VR_SAMPLER_ALIAS 2       // the components' alias tables (binding 7)
#define VR_SAMPLER_ROULETTE 3    // the components' face roulettes (binding 7)
#define VR_SAMPLER_SHARE_TREE 4  // the learned parts as share trees (binding 7), drawn from a tree stream
// The tree stream's key salt (VR_SAMPLER_SHARE_TREE): vplkit_rng_key(pixel key, salt), as the CPU's
// render/share_tree_mixture.hpp share_tree_stream (its share_tree_stream_salt, checked there).
#define VR_SHARE_TREE_STREAM_SALT 0x5E72EEu
// VR_VPL_MODE: vplkit_vpl_point (0) or vplkit_vpl_patch (1) (--vpl-mode).
// VR_LOCAL_COMBINATION: vplkit_local_balance (0) or vplkit_local_average (1) (--local-combination).
// VR_VARIANT: the method's variant of its estimator (render/method_traits.cpp; mis: the
//   vplkit_mis_solid_angle (0) or vplkit_mis_as_published (1) weights).
// VR_SPLIT: 0 one dispatch does every sample (no state buffer); 1 the samples are split into ranges
//   [begin, end) dispatched one after another (llvmpipe's loop budget, render/gpu/loop_budget.hpp),
//   the pixel's state kept in the state buffer between them.
// VR_DIRECT: 1 adds vplkit_direct_light (--direct) to the estimate.
// VR_LIT_SHADOW_RAY (defined or not): gathering's lit test by a shadow ray (--lit-test shadow-ray).
// VR_CLAMP_COMPENSATION (defined or not): the clamp's compensation (see its block below).
// VR_CLAMP_COMPENSATION_PASS (defined or not, with VR_CLAMP_COMPENSATION): the estimate kernel adds
//   the term clamp_compensation.comp's passes left in the out buffer (VR_ESTIMATE_BINDING_OUT)
//   (--clamp-compensation-pass compacted) instead of tracing its directions itself (inline).
// VR_CLAMP_PASS: clamp_compensation.comp's pass (docs/renderer.md, "The clamp compensation's passes").
#define VR_CLAMP_PASS_MARK 0        // per pixel: the term 0, the pixel listed where the test says maybe
#define VR_CLAMP_PASS_DISPATCH 1    // one invocation: the list's count into the indirect work groups
#define VR_CLAMP_PASS_DIRECTIONS 2  // per listed pixel: directions [begin, end), the term at the last
#ifndef __cplusplus
#ifndef VR_SAMPLER
#define VR_SAMPLER VR_SAMPLER_CDF_GUIDE
#endif
#ifndef VR_VPL_MODE
#define VR_VPL_MODE 1
#endif
#ifndef VR_LOCAL_COMBINATION
#define VR_LOCAL_COMBINATION 0
#endif
#ifndef VR_VARIANT
#define VR_VARIANT 0
#endif
#ifndef VR_SPLIT
#define VR_SPLIT 0
#endif
#ifndef VR_DIRECT
#define VR_DIRECT 0
#endif
#endif

// Distribution ids at and above this are the face roulettes' CDFs in the components buffer:
// VR_COMPONENT_SLOT + 2 k + face (k = 2 d + c: mixture d's learned part c = 0, its fallback c = 1).
#define VR_COMPONENT_SLOT 0x80000000u
// Distribution ids from this one up to VR_COMPONENT_SLOT are the tiles' block CDFs in the tile
// buffer (VR_RIS_TILES, estimate_tiles.glsl): VR_TILE_SLOT + d is tile d's.
#define VR_TILE_SLOT 0x40000000u

#ifdef __cplusplus
namespace vplrender::gpu {
using vplkit::gpu::ivec4;
using vplkit::gpu::light_params;
using vplkit::gpu::uint;
using vplkit::gpu::uvec4;
using vplkit::gpu::vec4;
struct estimate_params {
  light_params light;
#else
struct vr_estimate_params {
  vplkit_light_params light;
#endif
  vec4 grid_min;          // xyz: the voxel grid's bounds
  vec4 grid_max;
  ivec4 grid_resolution;  // xyz
  int width;              // the G-buffer's W, H
  int height;
  int resolution;         // the DPRSM's R
  int n_dirs;             // gathering directions (gather, mis, exact)
  int n_vpls;             // VPL samples (mis)
  int n_samples;          // the count the estimate divides by: VPL samples, or local rounds
  int n_distributions;    // D mixtures (local: one per region)
  int strata;             // the patch reference's strata per texel side
  int begin;              // this dispatch's units (samples, rounds, directions, texels) [begin, end)
  int end;
  int first_pass;         // VR_SPLIT 1: 1 starts the pixel's state, 0 reads it back
  int last_pass;          // VR_SPLIT 1: 1 writes the estimate, 0 keeps the state
  uint seed;              // the pixels' random streams: vplkit_make_counter_rng(seed, pixel)
  uint bvh_node_count;    // exact rays: the hierarchy's node count (0: empty)
  uint cdf_stride;        // distribution k's cdf at data[k cdf_stride] (n + 1 floats)
  uint guide_base;        // ... and its guide at data[guide_base + k guide_stride] (m + 1 uints)
  uint guide_stride;
  uint pad0;
  uint pad1;
  uint pad2;
  float dmin;             // the VPL distance clamp
  float depth_tolerance;  // gathering look-ups and patch VPLs
  float surface_offset;   // exact.comp: ray_scene::surface_offset()
  float pad3;             // the four floats fill one std140 row

  // ---- the clamp's compensation (VR_CLAMP_COMPENSATION; --clamp-compensation on) ----------------
  // docs/math.md, "The clamp's compensation": clamp_dirs cosine directions per gather point from
  // vplkit_clamp_compensation_stream, as the CPU backend draws them. They are the kernel's units
  // [clamp_first_unit, clamp_first_unit + clamp_dirs), after the estimator's own [0, clamp_first_unit),
  // so a split render cuts both with one [begin, end). 0 without the define. With
  // VR_CLAMP_COMPENSATION_PASS the estimator's units are all [0, clamp_first_unit) and the
  // directions are clamp_compensation.comp's [begin, end); clamp_max_groups_x is the indirect
  // dispatch's largest group count on x (GL_MAX_COMPUTE_WORK_GROUP_COUNT).
  int clamp_dirs;
  int clamp_first_unit;
  int clamp_max_groups_x;
  int clamp_pad1;

  // ---- the RIS kernels' parameters (estimate_ris_params.h; 0 for every other kernel) ------------
#ifdef __cplusplus
  ris_params ris;
#else
  vr_ris_params ris;
#endif
};

// One defensive mixture of the per-frame distributions (std430, 48 bytes: three vector loads, made
// once per invocation by the kernels that sample one mixture). learned / fallback: the two
// vplkit_discrete_cdf as (distribution index in the CDF data, size, guide size, total as float
// bits); mix: (effective eps, fallback scale, learned scale, 0), the host's defensive_mixture values.
// VR_SAMPLER_SHARE_TREE: learned is the share tree instead, (tree index, size, leaves L, the tree's
// total as float bits): vplkit_share_tree's fields.
#ifdef __cplusplus
struct mixture_record {
#else
struct vr_mixture_record {
#endif
  uvec4 learned;
  uvec4 fallback;
  vec4 mix;
};

// A pixel's state between the dispatches of a split render (VR_SPLIT 1; std430, 48 bytes): the
// estimators' vplkit_estimator_state (sum, rng key and counter), or the reference's
// vplkit_vpl_sum_state (sum, compensation). With VR_CLAMP_COMPENSATION the clamp compensation's
// estimator state takes the lanes neither uses (estimate_clamp_compensation.glsl): its sum in
// (sum.w, comp.w, rng.z as float bits), its stream's counter in rng.w.
#ifdef __cplusplus
struct pixel_state {
#else
struct vr_pixel_state {
#endif
  vec4 sum;   // xyz
  vec4 comp;  // xyz: the reference's compensation
  uvec4 rng;  // x key, y counter
};

// A G-buffer pixel or a DPRSM texel (std430, 48 bytes; raster/gpu_scene_buffers.hpp uploads them):
// xyz used, w ignored (a vec3 array would take 16 bytes per element anyway).
#ifdef __cplusplus
struct surfel {
#else
struct vr_surfel {
#endif
  vec4 position;
  vec4 normal;
  vec4 albedo;
};

#ifdef __cplusplus
static_assert(sizeof(estimate_params) == 304);  // the light, 3 vec4, 24 scalars, the compensation's 4, ris
static_assert(offsetof(estimate_params, ris) == 240);  // std140: a struct member on a 16-byte boundary
static_assert(sizeof(mixture_record) == 48 && sizeof(pixel_state) == 48 && sizeof(surfel) == 48);
}  // namespace vplrender::gpu
#endif

#endif  // VPLRENDER_ESTIMATE_PARAMS_H
