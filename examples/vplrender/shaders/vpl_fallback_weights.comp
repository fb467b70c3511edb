// SPDX-License-Identifier: MIT
// The defensive fallback's weights on the GPU: 1 where a DPRSM texel carries a VPL, else 0 --
// the weights of vplkit::make_vpl_fallback (builders/vpl_distribution.hpp), which cdf_build.comp then
// turns into the uniform distribution over the VPL texels. One invocation per texel; the host
// (gpu_cdf.cpp) prepends "#version 430".
//
// "Carries a VPL" is vplkit_vpl_has_flux (vpl/vpl.glsl, as the C++): flux > 0 in some channel,
// i.e. albedo > 0, the texel inside its face's disk (solid angle > 0) and the surface facing the
// light. Only the last test involves rounding (a dot product against 0), so CPU and GPU can
// disagree only for a surface seen exactly edge-on from the light.
layout(local_size_x = 64) in;

#include "vplkit/vpl/dprsm_view.glsl"

struct vr_surfel {
  vec4 position;
  vec4 normal;
  vec4 albedo;
};
layout(std430, binding = 0) readonly buffer VrDprsm { vr_surfel vr_dprsm[]; };
layout(std430, binding = 1) writeonly buffer VrWeights { float vr_weights[]; };

uniform int u_dprsm_res;
uniform vec3 u_light_pos;
uniform vec3 u_light_int;
uniform vec3 u_frame_pos;
uniform vec3 u_axis_x;
uniform vec3 u_axis_y;
uniform vec3 u_axis_z;
uniform uint u_offset;  // first weight written: texel t goes to vr_weights[u_offset + t]

vec3 vplkit_load_dprsm_position(int texel) { return vr_dprsm[texel].position.xyz; }
vec3 vplkit_load_dprsm_normal(int texel) { return vr_dprsm[texel].normal.xyz; }
vec3 vplkit_load_dprsm_albedo(int texel) { return vr_dprsm[texel].albedo.xyz; }

void main() {
  vplkit_dprsm_view view = vplkit_dprsm_view(
      u_dprsm_res, vplkit_point_light(u_light_pos, u_light_int,
                                      vplkit_light_frame(u_frame_pos, u_axis_x, u_axis_y, u_axis_z)));
  // Groups spread over x and y past GL_MAX_COMPUTE_WORK_GROUP_COUNT (vplkit::gl::dispatch_linear).
  int t = int(gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x);
  if (t >= vplkit_dprsm_view_texel_count(view)) return;
  vr_weights[u_offset + uint(t)] = vplkit_vpl_has_flux(vplkit_dprsm_view_vpl_at(view, t)) ? 1.0 : 0.0;
}
