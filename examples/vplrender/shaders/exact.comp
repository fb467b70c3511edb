// SPDX-License-Identifier: MIT
// vplrender's --method exact kernel (--backend gpu): one invocation per pixel, the CPU backend's
// estimate_exact (render/cpu/exact_estimator.cpp) through exact_estimator.glsl, on the frame's BVH
// and shading buffers (raster/gpu_bvh.hpp, raster/gpu_scene_shading.hpp). The host puts
// "#version 430" first and the variant's defines (estimate_params.h: VR_SPLIT, VR_DIRECT) in the
// preamble; parameters, bindings and the pass glue are the estimate kernels' (estimate_io.glsl).
//
// The hemisphere is the G-buffer's geometric normal's (as on the CPU). The offset that moves ray
// origins off their surfaces is the host ray scene's, so both backends move the same points by the
// same amounts. Random numbers: per direction u0 then u1 (the CPU's).
#include "estimate_io.glsl"
#include "exact_estimator.glsl"
#include "vplkit/visibility/bvh_layout.glsl"

layout(std430, binding = VR_ESTIMATE_BINDING_BVH_NODES) restrict readonly buffer VrBvhNodes { vplkit_bvh_node vr_bvh_nodes[]; };
layout(std430, binding = VR_ESTIMATE_BINDING_BVH_TRIANGLES) restrict readonly buffer VrBvhTriangles {
  vplkit_bvh_triangle vr_bvh_triangles[];
};
layout(std430, binding = VR_ESTIMATE_BINDING_TRIANGLE_SHADING) restrict readonly buffer VrTriangleShading {
  vr_triangle_shading vr_triangle_shadings[];
};
layout(std430, binding = VR_ESTIMATE_BINDING_SHADING_POOL) restrict readonly buffer VrShadingPool { uint vr_shading_pool[]; };

uint vplkit_load_voxel_word(uint word_index) { return 0u; }  // no voxel kind is used
vplkit_bvh_node vplkit_load_bvh_node(uint index) { return vr_bvh_nodes[index]; }
vplkit_bvh_triangle vplkit_load_bvh_triangle(uint slot) { return vr_bvh_triangles[slot]; }
vr_triangle_shading vr_load_triangle_shading(uint triangle) { return vr_triangle_shadings[triangle]; }
uint vr_load_shading_word(uint index) { return vr_shading_pool[index]; }

void main() {
  uint p = vr_pixel();
  if (!vr_in_image(p)) return;
  vplkit_gather_point gp = vplkit_load_gather_point(int(p));
  bool valid = vplkit_gather_point_valid(gp);
  vplkit_estimator_state est = vr_begin_estimate(p);
  if (valid) {
    vr_exact_scene rs = vr_exact_scene(vplkit_bvh(vr_params.bvh_node_count), vr_params.surface_offset);
    vr_estimate_exact_range(rs, vr_view().light, gp, est, vr_begin(), vr_end());
  }
  vr_keep_estimate(p, est);
  if (vr_last_pass()) vr_write_estimate(p, gp, valid, vr_estimate_exact_finish(est, vr_params.n_dirs));
}
