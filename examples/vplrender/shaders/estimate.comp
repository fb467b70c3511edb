// vplrender's estimator kernel (--backend gpu): one invocation per pixel, the GLSL pack's
// estimators over the renderer's buffers. Compiled once per method with VR_METHOD defined by the
// host (gpu_backend.cpp puts "#version 430" first and the define in the preamble).
//
// Passes: llvmpipe (Mesa 22.3) runs at most 65535 loop iterations per invocation and silently
// leaves every loop after that (docs/glsl/estimators.md), so the host splits the samples (texels
// for the reference) into ranges [u_begin, u_end) small enough for that budget and dispatches this
// kernel once per range. Between passes each pixel keeps its float sum (and the Neumaier
// compensation of the reference) and its counter_rng in the state buffer: the sequence of float
// operations and random numbers is exactly that of one C++ loop (cpu_backend.cpp), whatever the
// split. The last pass writes sum / N (as the C++ estimators divide), plus the direct light when
// u_direct is set (vr_direct_light: cpu_backend.cpp's direct_light() statement for statement), to
// the RGBA32F output; the host applies max(., 0) and the finite guard as the CPU backend does.
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
#include "vplkit/estimators/gathering_estimator.glsl"
#include "vplkit/estimators/local_estimator.glsl"
#include "vplkit/estimators/mis_estimator.glsl"
#include "vplkit/estimators/vpl_sampling_estimator.glsl"
#include "vplkit/estimators/vpl_sum.glsl"
#include "vplkit/sampling/rng.glsl"
#include "vplkit/visibility/visibility_callables.glsl"
#include "vplkit/vpl/dprsm_lookup.glsl"

// A G-buffer pixel or a DPRSM texel: xyz used, w ignored (std430 vec3 arrays take 16 bytes anyway).
struct vr_surfel {
  vec4 position;
  vec4 normal;
  vec4 albedo;
};
struct vr_state {
  vec4 sum;
  vec4 comp;   // Neumaier compensation (reference only)
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

// cpu_backend.cpp direct_light(): the direct light at a valid gather point through the DPRSM
// shadow test (0 in shadow). Same statements and order; the tolerance formula is the C++ one.
vec3 vr_direct_light(vplkit_gather_point gp, vplkit_dprsm_view view) {
  vec3 to_light = view.light.position - gp.position;
  float d = length(to_light);
  if (!(d > 0.0)) return vec3(0.0);
  float cos_a = dot(normalize(gp.normal), to_light / d);
  if (!(cos_a > 0.0)) return vec3(0.0);
  float tan_a = min(20.0, sqrt(max(0.0, 1.0 - cos_a * cos_a)) / cos_a);
  float tol = d * (4.0 / float(view.resolution)) * (0.5 + tan_a) + 1e-4 * d;
  vplkit_dprsm_lookup_result r = vplkit_dprsm_lookup(view, gp.position, tol);
  if (!r.lit) return vec3(0.0);
  return vplkit_reflected_radiance(view.light.position, view.light.intensity, gp.position, gp.normal, gp.albedo);
}

void main() {
  // Groups are spread over y past 65535 (the host's dispatch); pixel = flat invocation index.
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
  vplkit_counter_rng rng = vplkit_counter_rng(st.rng.x, st.rng.y);
  vplkit_dprsm_view view = vplkit_dprsm_view(
      u_dprsm_res, vplkit_point_light(u_light_pos, u_light_int,
                                      vplkit_light_frame(u_frame_pos, u_axis_x, u_axis_y, u_axis_z)));
  vplkit_voxel_grid grid = vplkit_voxel_grid(u_grid_min, u_grid_max, u_grid_res);
  vplkit_visibility visibility = vplkit_make_voxel_visibility(grid);
  vplkit_voxel_tracer tracer = vplkit_make_voxel_tracer(grid);
  bool valid = vplkit_gather_point_valid(gp);
  vec3 sum = st.sum.xyz;
  if (valid) {
#if VR_METHOD == VR_REFERENCE
    // vplkit_exhaustive_vpl_sum_range's Neumaier loop with its state kept across passes (the C++
    // sums in double; this is as accurate in practice, vpl_sum.glsl).
    precise vec3 s_sum = sum;
    precise vec3 s_comp = st.comp.xyz;
    for (int t = u_begin; t < u_end; ++t) {
      vec3 c = vplkit_vpl_visible_contribution(gp, view, t, visibility, u_dmin);
      precise vec3 s = s_sum + c;
      precise vec3 big = mix(c, s_sum, greaterThanEqual(abs(s_sum), abs(c)));
      precise vec3 small = mix(s_sum, c, greaterThanEqual(abs(s_sum), abs(c)));
      s_comp += (big - s) + small;
      s_sum = s;
    }
    sum = s_sum;
    st.comp = vec4(s_comp, 0.0);
#elif VR_METHOD == VR_VPL_SAMPLING
    // vplkit_estimate_vpl_sampling's loop, samples u_begin .. u_end - 1.
    for (int k = u_begin; k < u_end; ++k)
      sum += vplkit_vpl_sampling_sample(gp, view, 0u, vplkit_rng_next_unit(rng), visibility, u_dmin);
#elif VR_METHOD == VR_LOCAL
    // vplkit_estimate_local's loop (combination u_local_combination), rounds u_begin .. u_end - 1.
    uint n_texels = uint(vplkit_dprsm_view_texel_count(view));
    for (int r = u_begin; r < u_end; ++r)
      for (int i = 0; i < u_n_dists; ++i) {
        vplkit_discrete_sample s = vplkit_estimator_distribution_sample(uint(i), vplkit_rng_next_unit(rng));
        float pmf_i = s.pmf;
        if (!(pmf_i > 0.0) || s.index >= n_texels) continue;
        vec3 c = vplkit_vpl_visible_contribution(gp, view, int(s.index), visibility, u_dmin);
        if (!(c.x > 0.0 || c.y > 0.0 || c.z > 0.0)) continue;
        float divisor = u_local_combination == vplkit_local_balance
                            ? vplkit_local_mixture_pmf_sum(0u, u_n_dists, s.index)
                            : pmf_i * float(u_n_dists);
        sum += vplkit_estimator_finite_or_zero(vec3(vplkit_mis_div(c.x, divisor), vplkit_mis_div(c.y, divisor),
                                                    vplkit_mis_div(c.z, divisor)));
      }
#elif VR_METHOD == VR_GATHER
    // vplkit_estimate_gathering's loop, directions u_begin .. u_end - 1.
    vplkit_orthonormal_basis frame = vplkit_make_orthonormal_basis(gp.normal);
    for (int k = u_begin; k < u_end; ++k) {
      float u0 = vplkit_rng_next_unit(rng);
      float u1 = vplkit_rng_next_unit(rng);
      sum += vplkit_gathering_sample(gp, view, frame, vplkit_sample_cosine_hemisphere(vec2(u0, u1)), tracer,
                                     u_depth_tol);
    }
#elif VR_METHOD == VR_MIS
    // vplkit_estimate_mis's loop, j = u_begin .. u_end - 1.
    float n1 = float(u_n_dirs), n2 = float(u_n_vpls);
    vplkit_orthonormal_basis frame = vplkit_make_orthonormal_basis(gp.normal);
    for (int j = u_begin; j < u_end; ++j) {
      if (j < u_n_vpls)
        sum += vplkit_mis_vpl_sample(gp, view, 0u, vplkit_rng_next_unit(rng), visibility, n1, n2, u_mis_mode);
      if (j < u_n_dirs) {
        float u0 = vplkit_rng_next_unit(rng);
        float u1 = vplkit_rng_next_unit(rng);
        sum += vplkit_mis_gathering_sample(gp, view, 0u, frame, vplkit_sample_cosine_hemisphere(vec2(u0, u1)),
                                           tracer, u_depth_tol, n1, n2, u_mis_mode);
      }
    }
#endif
  }
  st.sum = vec4(sum, 0.0);
  st.rng = uvec4(rng.key, rng.counter, 0u, 0u);
  vr_states[p] = st;
  if (u_last_pass != 0) {
    vec3 e = vec3(0.0);
    if (valid) {
#if VR_METHOD == VR_REFERENCE
      precise vec3 total = sum + st.comp.xyz;
      e = total;
#elif VR_METHOD == VR_VPL_SAMPLING || VR_METHOD == VR_LOCAL
      e = sum / float(u_n_samples);
#elif VR_METHOD == VR_GATHER
      e = sum / float(u_n_dirs);
#elif VR_METHOD == VR_MIS
      e = u_mis_mode == vplkit_mis_as_published ? sum / float(u_n_dirs > 0 ? u_n_dirs : u_n_vpls) : sum;
#endif
      if (u_direct != 0) e += vr_direct_light(gp, view);
    }
    vr_out[p] = vec4(e, 1.0);
  }
}
