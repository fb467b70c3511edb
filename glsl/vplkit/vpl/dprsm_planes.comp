// SPDX-License-Identifier: MIT
// vplkit kernel: the plane records of a DPRSM (dprsm_plane.glsl), one invocation per texel: the
// GPU side of vplkit::build_dprsm_planes: planes[t] = vplkit_dprsm_view_plane_at(view, t) without a
// plane accessor, i.e. vplkit_dprsm_plane_of(c, texel t). Run it once per DPRSM and light, after
// the DPRSM is written, and read the records through VPLKIT_DPRSM_PLANE_ACCESSOR (dprsm_view.glsl).
// Interface: dprsm_planes_params.h, shared with the C++ host; the DPRSM is vec4 triplets
// (position, normal, albedo). Dispatch ceil(2 R^2 / LOCAL_SIZE) groups spread over x and y (linear
// group = x + y * gl_NumWorkGroups.x, the host's vplkit::gl::dispatch_linear). Precision:
// dprsm_plane.glsl (h `precise`; n through vplkit_unit_or_zero's inversesqrt).
#include "vplkit/vpl/dprsm_planes_params.h"
#include "vplkit/vpl/dprsm_view.glsl"

layout(local_size_x = VPLKIT_DPRSM_PLANES_LOCAL_SIZE, local_size_y = 1, local_size_z = 1) in;

layout(std430, binding = VPLKIT_DPRSM_PLANES_BINDING_DPRSM) readonly buffer vplkit_dprsm_planes_dprsm_buffer {
  vec4 vplkit_dprsm_planes_dprsm[];
};
layout(std430, binding = VPLKIT_DPRSM_PLANES_BINDING_PLANES) writeonly buffer vplkit_dprsm_planes_out_buffer {
  vec4 vplkit_dprsm_planes_out[];
};
layout(std140, binding = VPLKIT_DPRSM_PLANES_BINDING_PARAMS) uniform vplkit_dprsm_planes_uniforms {
  vplkit_dprsm_planes_params vplkit_dprsm_planes;
};

// The accessors of dprsm_view.glsl on this kernel's buffer (every referenced accessor needs a
// body: docs/glsl.md, "Accessors and Mesa's linker"). This kernel defines no plane accessor: it
// computes the records, as vplkit_dprsm_view_plane_at does without one.
vec3 vplkit_load_dprsm_position(int texel) { return vplkit_dprsm_planes_dprsm[3 * texel].xyz; }
vec3 vplkit_load_dprsm_normal(int texel) { return vplkit_dprsm_planes_dprsm[3 * texel + 1].xyz; }
vec3 vplkit_load_dprsm_albedo(int texel) { return vplkit_dprsm_planes_dprsm[3 * texel + 2].xyz; }

void main() {
  int R = vplkit_dprsm_planes.resolution;
  int t = int(gl_GlobalInvocationID.x + gl_GlobalInvocationID.y * gl_NumWorkGroups.x * gl_WorkGroupSize.x);
  if (t >= vplkit_texel_count(R)) return;
  vplkit_dprsm_view view = vplkit_dprsm_view(R, vplkit_light_params_point_light(vplkit_dprsm_planes.light));
  vplkit_dprsm_planes_out[t] = vplkit_dprsm_view_plane_at(view, t);
}
