// SPDX-License-Identifier: MIT
// vplrender's estimate kernels (estimate_*.comp, exact.comp): what every one of them reads and
// writes per pixel. The parameter block, the G-buffer and DPRSM accessors of the pack, the pixel
// an invocation shades, and the pass glue (estimate_params.h's VR_SPLIT):
//   VR_SPLIT 0: one dispatch runs the pixel's units [begin, end) = all of them, the state lives in
//     registers and the estimate is written at the end: no storage round trip.
//   VR_SPLIT 1: the host splits the units into ranges (llvmpipe's loop budget) and dispatches once
//     per range; the state goes to the state buffer between them and the last range writes the
//     estimate. Consecutive ranges perform exactly the float operations and draws of one range.
// Random numbers: vplkit_make_counter_rng(seed, pixel), the CPU backend's stream per pixel.
#ifndef VPLRENDER_ESTIMATE_IO_GLSL
#define VPLRENDER_ESTIMATE_IO_GLSL

#include "estimate_params.h"
#include "vplkit/core/gather_point.glsl"
#include "vplkit/estimators/estimator_state.glsl"
#include "vplkit/estimators/vpl_sum.glsl"
#include "vplkit/sampling/rng.glsl"
#include "vplkit/vpl/direct_light.glsl"
#include "vplkit/vpl/dprsm_view.glsl"
#include "vplkit/vpl/light_params.h"

layout(local_size_x = VR_ESTIMATE_LOCAL_SIZE) in;

layout(std140, binding = VR_ESTIMATE_BINDING_PARAMS) uniform VrEstimateParams { vr_estimate_params vr_params; };
layout(std430, binding = VR_ESTIMATE_BINDING_GBUFFER) restrict readonly buffer VrGbuffer { vr_surfel vr_gbuffer[]; };
layout(std430, binding = VR_ESTIMATE_BINDING_DPRSM) restrict readonly buffer VrDprsm { vr_surfel vr_dprsm[]; };
#if VR_DPRSM_PLANES
layout(std430, binding = VR_ESTIMATE_BINDING_DPRSM_PLANES) restrict readonly buffer VrDprsmPlanes { vec4 vr_dprsm_planes[]; };
#endif
#ifdef VR_CLAMP_COMPENSATION_PASS
// The clamp compensation's passes leave each pixel's term here (clamp_compensation.comp); the
// estimate kernel reads it in its last pass and writes the estimate over it. Not a block of its
// own: llvmpipe allows 16 storage blocks per compute shader, and ris's kernel binds 16 already.
layout(std430, binding = VR_ESTIMATE_BINDING_OUT) restrict buffer VrOut { vec4 vr_out[]; };
#else
layout(std430, binding = VR_ESTIMATE_BINDING_OUT) restrict writeonly buffer VrOut { vec4 vr_out[]; };
#endif
#if VR_SPLIT
layout(std430, binding = VR_ESTIMATE_BINDING_STATE) restrict buffer VrState { vr_pixel_state vr_states[]; };
#endif

vplkit_gather_point vplkit_load_gather_point(int pixel) {
  vr_surfel s = vr_gbuffer[pixel];  // 48 contiguous bytes, once per invocation
  return vplkit_unpack_gather_point(s.position, s.normal, s.albedo);
}
vec3 vplkit_load_dprsm_position(int texel) { return vr_dprsm[texel].position.xyz; }
vec3 vplkit_load_dprsm_normal(int texel) { return vr_dprsm[texel].normal.xyz; }
vec3 vplkit_load_dprsm_albedo(int texel) { return vr_dprsm[texel].albedo.xyz; }
// The texel's plane record (estimate_params.h defines VPLKIT_DPRSM_PLANE_ACCESSOR): 16 bytes, once
// per neighbour of the patch sampler's hidden test instead of 3 x 16 bytes and a normalisation.
#if VR_DPRSM_PLANES
vec4 vplkit_load_dprsm_plane(int texel) { return vr_dprsm_planes[texel]; }
#endif

// The pixel of this invocation (flat index; groups spread over y past the x limit, as
// vplkit::gl::dispatch_linear lays them out), and whether it lies in the image.
uint vr_pixel() {
  return gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x;
}
bool vr_in_image(uint p) { return p < uint(vr_params.width) * uint(vr_params.height); }

vplkit_dprsm_view vr_view() {
  return vplkit_dprsm_view(vr_params.resolution, vplkit_light_params_point_light(vr_params.light));
}

// The estimator's units of this dispatch (with VR_CLAMP_COMPENSATION the units from
// clamp_first_unit on are the compensation's directions: estimate_clamp_compensation.glsl).
#ifdef VR_CLAMP_COMPENSATION
int vr_begin() { return min(vr_params.begin, vr_params.clamp_first_unit); }
int vr_end() { return min(vr_params.end, vr_params.clamp_first_unit); }
#else
int vr_begin() { return vr_params.begin; }
int vr_end() { return vr_params.end; }
#endif

// True in the dispatch that writes the estimate.
bool vr_last_pass() {
#if VR_SPLIT
  return vr_params.last_pass != 0;
#else
  return true;
#endif
}

// The estimators' state (sum, random stream) at the start of this dispatch, and after it.
vplkit_estimator_state vr_begin_estimate(uint p) {
#if VR_SPLIT
  if (vr_params.first_pass == 0) {
    vr_pixel_state s = vr_states[p];
    return vplkit_estimator_state(s.sum.xyz, vplkit_counter_rng(s.rng.x, s.rng.y));
  }
#endif
  return vplkit_make_estimator_state(vplkit_make_counter_rng(vr_params.seed, p));
}
void vr_keep_estimate(uint p, vplkit_estimator_state est) {
#if VR_SPLIT
  if (vr_params.last_pass == 0)
    vr_states[p] = vr_pixel_state(vec4(est.sum, 0.0), vec4(0.0), uvec4(est.rng.key, est.rng.counter, 0u, 0u));
#endif
}

// The reference's compensated sum, likewise.
vplkit_vpl_sum_state vr_begin_sum(uint p) {
#if VR_SPLIT
  if (vr_params.first_pass == 0) {
    vr_pixel_state s = vr_states[p];
    return vplkit_vpl_sum_state(s.sum.xyz, s.comp.xyz);
  }
#endif
  return vplkit_make_vpl_sum_state();
}
void vr_keep_sum(uint p, vplkit_vpl_sum_state sum) {
#if VR_SPLIT
  if (vr_params.last_pass == 0) vr_states[p] = vr_pixel_state(vec4(sum.sum, 0.0), vec4(sum.compensation, 0.0), uvec4(0u));
#endif
}

// The pixel's value: e (the indirect estimate) plus the direct light with VR_DIRECT, 0 off the
// scene; the host applies max(., 0) and the finite guard as the CPU backend does.
void vr_write_estimate(uint p, vplkit_gather_point gp, bool valid, vec3 e) {
  vec3 c = vec3(0.0);
  if (valid) {
    c = e;
#if VR_DIRECT
    c += vplkit_direct_light(gp, vr_view());
#endif
  }
  vr_out[p] = vec4(c, 1.0);
}

#endif  // VPLRENDER_ESTIMATE_IO_GLSL
