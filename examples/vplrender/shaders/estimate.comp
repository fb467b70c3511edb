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
// Random numbers: vplkit_make_counter_rng(u_seed, pixel), the CPU backend's stream per pixel.
// Distributions: defensive mixtures as CDF + guide arrays and the mixture scalars (pack
// distribution/defensive_mixture.glsl). Built on the GPU for global, local, gbg, mis and
// mis-as-published (gpu_cdf.cpp: cdf_build.comp, the same layout); the vr_dist_* layout below is
// also what an upload of C++ vplkit::make_vpl_distribution objects fills.
#define VR_REFERENCE 0
#define VR_VPL_SAMPLING 1
#define VR_LOCAL 2
#define VR_GATHER 3
#define VR_MIS 4

layout(local_size_x = 64) in;

#include "vplkit/core/gather_point.glsl"
#include "vplkit/distribution/defensive_mixture.glsl"
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
uniform int u_local_combination;   // vplkit_local_balance or vplkit_local_average (--local-combination)

vplkit_gather_point vplkit_load_gather_point(int pixel) {
  return vplkit_gather_point(vr_gbuffer[pixel].position.xyz, vr_gbuffer[pixel].normal.xyz,
                             vr_gbuffer[pixel].albedo.xyz);
}
vec3 vplkit_load_dprsm_position(int texel) { return vr_dprsm[texel].position.xyz; }
vec3 vplkit_load_dprsm_normal(int texel) { return vr_dprsm[texel].normal.xyz; }
vec3 vplkit_load_dprsm_albedo(int texel) { return vr_dprsm[texel].albedo.xyz; }
uint vplkit_load_voxel_word(uint word_index) { return vr_voxels[word_index]; }
float vplkit_load_cdf(uint slot, uint i) {
  return uintBitsToFloat(vr_dist_data[vr_dist_meta[u_slot_base + 2u * slot] + i]);
}
uint vplkit_load_guide(uint slot, uint j) { return vr_dist_data[vr_dist_meta[u_slot_base + 2u * slot + 1u] + j]; }

vplkit_defensive_mixture vr_mixture(uint d) {
  uint b = 12u * d;
  vplkit_discrete_cdf learned = vplkit_discrete_cdf(vr_dist_meta[b], vr_dist_meta[b + 1u], vr_dist_meta[b + 2u],
                                                    uintBitsToFloat(vr_dist_meta[b + 3u]));
  vplkit_discrete_cdf fallback = vplkit_discrete_cdf(vr_dist_meta[b + 4u], vr_dist_meta[b + 5u],
                                                     vr_dist_meta[b + 6u], uintBitsToFloat(vr_dist_meta[b + 7u]));
  return vplkit_defensive_mixture(learned, fallback, uintBitsToFloat(vr_dist_meta[b + 8u]),
                                  uintBitsToFloat(vr_dist_meta[b + 9u]), uintBitsToFloat(vr_dist_meta[b + 10u]));
}
vplkit_discrete_sample vplkit_estimator_distribution_sample(uint distribution, float u) {
  // --cdf-search: both searches return the same index and pmf (uniform branch, no divergence).
  if (u_cdf_search != 0) return vplkit_defensive_mixture_sample_binary_search(vr_mixture(distribution), u);
  return vplkit_defensive_mixture_sample(vr_mixture(distribution), u);
}
float vplkit_estimator_distribution_pmf(uint distribution, uint index) {
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
  vplkit_visibility visibility = vplkit_make_voxel_visibility(grid);
  vplkit_voxel_tracer tracer = vplkit_make_voxel_tracer(grid);
  bool valid = vplkit_gather_point_valid(gp);
  if (valid) {
#if VR_METHOD == VR_REFERENCE
    vplkit_exhaustive_vpl_sum_range(gp, view, ref, u_begin, u_end, visibility, u_dmin);
#elif VR_METHOD == VR_VPL_SAMPLING
    vplkit_estimate_vpl_sampling_range(gp, view, 0u, est, u_begin, u_end, visibility, u_dmin);
#elif VR_METHOD == VR_LOCAL
    vplkit_estimate_local_range(gp, view, 0u, u_n_dists, est, u_begin, u_end, visibility, u_dmin,
                                u_local_combination);
#elif VR_METHOD == VR_GATHER
    vplkit_estimate_gathering_range(gp, view, est, u_begin, u_end, tracer, u_depth_tol);
#elif VR_METHOD == VR_MIS
    vplkit_estimate_mis_range(gp, view, 0u, est, u_begin, u_end, u_n_dirs, u_n_vpls, tracer, visibility,
                              u_depth_tol, u_mis_mode);
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
      e = vplkit_exhaustive_vpl_sum_finish(ref);
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
