// SPDX-License-Identifier: MIT
// vplrender's --method exact kernel (--backend gpu): one invocation per pixel, the CPU backend's
// estimate_exact (render/cpu/exact_estimator.cpp) through exact_estimator.glsl, on the frame's BVH
// and shading buffers (raster/gpu_bvh.hpp, raster/gpu_scene_shading.hpp). gpu_backend.cpp puts
// "#version 430" first.
//
// Passes, as estimate.comp: under llvmpipe's loop budget (docs/glsl.md) the host splits the
// directions into ranges [u_begin, u_end) and dispatches once per range; the pixel's sum and random
// stream stay in the state buffer between passes, so every split draws and adds what the CPU's one
// loop does. The gather point's geometric normal (one BVH query) is found again in every pass: the
// same query gives the same normal. The last pass writes the estimate, plus vplkit_direct_light
// when u_direct is set, to the RGBA32F output; the host applies max(., 0) and the finite guard as
// the CPU backend does.
//
// Random numbers: vplkit_make_counter_rng(u_seed, pixel), per direction u0 then u1 (the CPU's).
// Eight storage blocks, the GL 4.3 minimum per compute shader; the bindings are estimate.comp's
// where the buffers are the same (gpu_backend.cpp binds both kernels alike).
layout(local_size_x = 64) in;

#include "exact_estimator.glsl"
#include "vplkit/core/gather_point.glsl"
#include "vplkit/estimators/estimator_state.glsl"
#include "vplkit/sampling/rng.glsl"
#include "vplkit/visibility/bvh_layout.glsl"
#include "vplkit/vpl/direct_light.glsl"
#include "vplkit/vpl/dprsm_view.glsl"

// estimate.comp's vr_surfel and vr_state (xyz used).
struct vr_surfel {
  vec4 position;
  vec4 normal;
  vec4 albedo;
};
struct vr_state {
  vec4 sum;
  vec4 comp;  // unused here
  uvec4 rng;  // key, counter
};

layout(std430, binding = 0) readonly buffer VrGbuffer { vr_surfel vr_gbuffer[]; };
layout(std430, binding = 1) readonly buffer VrDprsm { vr_surfel vr_dprsm[]; };  // the direct light's shadow test
layout(std430, binding = 5) buffer VrState { vr_state vr_states[]; };
layout(std430, binding = 6) writeonly buffer VrOut { vec4 vr_out[]; };
layout(std430, binding = 8) readonly buffer VrBvhNodes { vplkit_bvh_node vr_bvh_nodes[]; };
layout(std430, binding = 9) readonly buffer VrBvhTriangles { vplkit_bvh_triangle vr_bvh_triangles[]; };
layout(std430, binding = 10) readonly buffer VrTriangleShading { vr_triangle_shading vr_triangle_shadings[]; };
layout(std430, binding = 11) readonly buffer VrShadingPool { uint vr_shading_pool[]; };

uniform int u_width;
uniform int u_height;
uniform int u_dprsm_res;
uniform vec3 u_light_pos;
uniform vec3 u_light_int;
uniform vec3 u_frame_pos;
uniform vec3 u_axis_x;
uniform vec3 u_axis_y;
uniform vec3 u_axis_z;
uniform uint u_seed;
uniform int u_begin;       // this pass's range of directions
uniform int u_end;
uniform int u_first_pass;  // 1: start the pixel's state
uniform int u_last_pass;   // 1: write the estimate
uniform int u_n_dirs;
uniform int u_direct;      // 1: add the direct light (--direct) in the last pass
uniform uint u_bvh_node_count;
uniform float u_surface_offset;  // ray_scene::surface_offset()
uniform float u_scene_size;      // ray_scene::size()
uniform vec3 u_eye;              // the camera's eye

vplkit_gather_point vplkit_load_gather_point(int pixel) {
  return vplkit_unpack_gather_point(vr_gbuffer[pixel].position, vr_gbuffer[pixel].normal, vr_gbuffer[pixel].albedo);
}
vec3 vplkit_load_dprsm_position(int texel) { return vr_dprsm[texel].position.xyz; }
vec3 vplkit_load_dprsm_normal(int texel) { return vr_dprsm[texel].normal.xyz; }
vec3 vplkit_load_dprsm_albedo(int texel) { return vr_dprsm[texel].albedo.xyz; }
uint vplkit_load_voxel_word(uint word_index) { return 0u; }  // no voxel kind is used
vplkit_bvh_node vplkit_load_bvh_node(uint index) { return vr_bvh_nodes[index]; }
vplkit_bvh_triangle vplkit_load_bvh_triangle(uint slot) { return vr_bvh_triangles[slot]; }
vr_triangle_shading vr_load_triangle_shading(uint triangle) { return vr_triangle_shadings[triangle]; }
uint vr_load_shading_word(uint index) { return vr_shading_pool[index]; }

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
  vplkit_dprsm_view view = vplkit_dprsm_view(
      u_dprsm_res, vplkit_point_light(u_light_pos, u_light_int,
                                      vplkit_light_frame(u_frame_pos, u_axis_x, u_axis_y, u_axis_z)));
  vr_exact_scene rs = vr_exact_scene(vplkit_bvh(u_bvh_node_count), u_surface_offset, u_scene_size, u_eye);
  bool valid = vplkit_gather_point_valid(gp);
  if (valid)
    vr_estimate_exact_range(rs, view.light, gp, vr_gather_point_geometric_normal(rs, gp), est, u_begin, u_end);
  st.sum = vec4(est.sum, 0.0);
  st.rng = uvec4(est.rng.key, est.rng.counter, 0u, 0u);
  vr_states[p] = st;
  if (u_last_pass != 0) {
    vec3 e = vec3(0.0);
    if (valid) {
      e = vr_estimate_exact_finish(est, u_n_dirs);
      if (u_direct != 0) e += vplkit_direct_light(gp, view);
    }
    vr_out[p] = vec4(e, 1.0);
  }
}
