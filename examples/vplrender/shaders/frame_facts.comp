// SPDX-License-Identifier: MIT
// The facts of a frame whose G-buffer and DPRSM live on the GPU that the host needs as numbers
// (render/frame_buffers.hpp, frame_facts): the report's and the lighting warnings' pixel counts and
// the GBG builder's fixed-point bound, counted here instead of over a read-back. One invocation
// per G-buffer pixel and per DPRSM texel (max of the two); atomics on integers, so the counts are
// exact and independent of the order. The host prepends "#version 430".
//   vr_facts[0] pixels with a surface (normal != 0: gbuffer_data::valid_count)
//   vr_facts[1] pixels that are gather points (vplkit_gather_point_valid)
//   vr_facts[2] pixels the light reaches directly (vplkit_direct_light > 0 in some channel, as
//               count_directly_lit_pixels)
//   vr_facts[3] float bits of the smallest distance from the light to a texel that saw a surface
//               (albedo != 0); non-negative floats order as their bits. Start: +Inf.
layout(local_size_x = 64) in;

#include "vplkit/vpl/direct_light.glsl"

struct vr_surfel {
  vec4 position;
  vec4 normal;
  vec4 albedo;
};
layout(std430, binding = 0) readonly buffer VrGbuffer { vr_surfel vr_gbuffer[]; };
layout(std430, binding = 1) readonly buffer VrDprsm { vr_surfel vr_dprsm[]; };
layout(std430, binding = 2) buffer VrFacts { uint vr_facts[]; };

uniform int u_pixels;  // W H
uniform int u_dprsm_res;
uniform vec3 u_light_pos;
uniform vec3 u_light_int;
uniform vec3 u_frame_pos;
uniform vec3 u_axis_x;
uniform vec3 u_axis_y;
uniform vec3 u_axis_z;

vec3 vplkit_load_dprsm_position(int texel) { return vr_dprsm[texel].position.xyz; }
vec3 vplkit_load_dprsm_normal(int texel) { return vr_dprsm[texel].normal.xyz; }
vec3 vplkit_load_dprsm_albedo(int texel) { return vr_dprsm[texel].albedo.xyz; }
vplkit_gather_point vplkit_load_gather_point(int pixel) {
  return vplkit_unpack_gather_point(vr_gbuffer[pixel].position, vr_gbuffer[pixel].normal, vr_gbuffer[pixel].albedo);
}

// Each work group counts in shared memory first and adds its totals with one atomic each: a
// single global counter hit by every invocation (half a million for a 2 x 512^2 DPRSM) would
// serialise in the GPU's cache.
shared uint vr_counts[4];

void main() {
  if (gl_LocalInvocationIndex == 0u) {
    vr_counts[0] = 0u;
    vr_counts[1] = 0u;
    vr_counts[2] = 0u;
    vr_counts[3] = 0x7F800000u;
  }
  memoryBarrierShared();
  memoryBarrierShared();
  barrier();
  vplkit_dprsm_view view = vplkit_dprsm_view(
      u_dprsm_res, vplkit_point_light(u_light_pos, u_light_int,
                                      vplkit_light_frame(u_frame_pos, u_axis_x, u_axis_y, u_axis_z)));
  // Groups spread over x and y past GL_MAX_COMPUTE_WORK_GROUP_COUNT (vplkit::gl::dispatch_linear).
  int i = int(gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x);
  if (i < u_pixels) {
    if (vr_gbuffer[i].normal.xyz != vec3(0.0)) atomicAdd(vr_counts[0], 1u);
    vplkit_gather_point gp = vplkit_load_gather_point(i);
    if (vplkit_gather_point_valid(gp)) {
      atomicAdd(vr_counts[1], 1u);
      vec3 c = vplkit_direct_light(gp, view);
      if (c.x > 0.0 || c.y > 0.0 || c.z > 0.0) atomicAdd(vr_counts[2], 1u);
    }
  }
  if (i < vplkit_dprsm_view_texel_count(view) && vr_dprsm[i].albedo.xyz != vec3(0.0)) {
    atomicMin(vr_counts[3], floatBitsToUint(length(vr_dprsm[i].position.xyz - u_light_pos)));
  }
  memoryBarrierShared();
  memoryBarrierShared();
  barrier();
  if (gl_LocalInvocationIndex == 0u) {
    if (vr_counts[0] != 0u) atomicAdd(vr_facts[0], vr_counts[0]);
    if (vr_counts[1] != 0u) atomicAdd(vr_facts[1], vr_counts[1]);
    if (vr_counts[2] != 0u) atomicAdd(vr_facts[2], vr_counts[2]);
    if (vr_counts[3] != 0x7F800000u) atomicMin(vr_facts[3], vr_counts[3]);
  }
}
