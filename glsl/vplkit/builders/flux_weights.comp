// SPDX-License-Identifier: MIT
// vplkit kernel: flux weights (light-power sampling, the candidate source of the resampled
// estimators), one invocation per texel: the GPU side of vplkit::build_flux_weights. Writes
// weights[t] = vplkit_flux_weight_texel (builders/flux_weights.glsl): luminance(Phi_t), 0 where the
// texel carries no VPL. Interface: flux_weights_params.h, shared with the C++ host; the DPRSM is
// vec4 triplets (position, normal, albedo). Dispatch ceil(2 R^2 / LOCAL_SIZE) groups spread over x
// and y (linear group = x + y * gl_NumWorkGroups.x; the host's vplkit::gl::dispatch_linear).
// Per texel a few products and one division (the solid angle): docs/glsl/builders.md.
#include "vplkit/builders/flux_weights.glsl"
#include "vplkit/builders/flux_weights_params.h"

layout(local_size_x = VPLKIT_FLUX_WEIGHTS_LOCAL_SIZE, local_size_y = 1, local_size_z = 1) in;

layout(std430, binding = VPLKIT_FLUX_WEIGHTS_BINDING_DPRSM) readonly buffer vplkit_flux_weights_dprsm_buffer {
  vec4 vplkit_flux_weights_dprsm[];
};
layout(std430, binding = VPLKIT_FLUX_WEIGHTS_BINDING_WEIGHTS) writeonly buffer vplkit_flux_weights_out_buffer {
  float vplkit_flux_weights_out[];
};
layout(std140, binding = VPLKIT_FLUX_WEIGHTS_BINDING_PARAMS) uniform vplkit_flux_weights_uniforms {
  vplkit_flux_weights_params vplkit_flux_weights;
};

vec3 vplkit_load_dprsm_position(int texel) { return vplkit_flux_weights_dprsm[3 * texel].xyz; }
vec3 vplkit_load_dprsm_normal(int texel) { return vplkit_flux_weights_dprsm[3 * texel + 1].xyz; }
vec3 vplkit_load_dprsm_albedo(int texel) { return vplkit_flux_weights_dprsm[3 * texel + 2].xyz; }

void main() {
  int R = vplkit_flux_weights.resolution;
  int t = int(gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x);
  if (t >= vplkit_texel_count(R)) return;
  vplkit_dprsm_view view = vplkit_dprsm_view(R, vplkit_light_params_point_light(vplkit_flux_weights.light));
  vplkit_flux_weights_out[t] = vplkit_flux_weight_texel(view, t);
}
