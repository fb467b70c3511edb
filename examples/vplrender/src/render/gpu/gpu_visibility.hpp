// SPDX-License-Identifier: MIT
#pragma once
// The GPU backend's visibility, chosen by render_settings::visibility: the one place that maps a
// visibility_choice to what the kernels need: the define that selects the kernel's visibility
// (the estimate kernels' VR_VISIBILITY, estimate_visibility.glsl; gbg_accumulate.comp's VPLKIT_GBG_TRIANGLE_VOXELS or
// VPLKIT_GBG_TRACER_BVH), the buffers to bind and the loop iterations one query costs under
// llvmpipe's budget. A new kind adds a case to each function here and a branch to those define
// blocks.
#include "raster/gpu_scene_buffers.hpp"
#include "render/frame_buffers.hpp"
#include "render/settings.hpp"

#include <vplkit/core/error.hpp>

#include <string>

namespace vplrender {

// The frame's BVH on the GPU, or invalid_input naming `who` when the frame was prepared without
// exact rays (frame_settings::exact_rays).
inline const gpu_bvh& gpu_frame_bvh(const gpu_scene_buffers& scene, const char* who) {
  if (scene.bvh.nodes.size_bytes() == 0)  // upload_scene_bvh leaves at least one node, even when empty
    throw vplkit::invalid_input(std::string(who) +
                                ": exact visibility needs a frame prepared with exact rays (frame_settings::exact_rays)");
  return scene.bvh;
}

// The estimate kernels' VR_VISIBILITY (estimate_params.h: 0 paper voxels, 1 exact, 2 triangle voxels).
inline std::string estimate_visibility_define(visibility_choice v) {
  switch (v) {
    case visibility_choice::paper_voxels: return "#define VR_VISIBILITY 0\n";
    case visibility_choice::exact: return "#define VR_VISIBILITY 1\n";
    case visibility_choice::voxels: break;
  }
  return "#define VR_VISIBILITY 2\n";
}

// gbg_accumulate.comp's tracer define (none: the paper's voxel tracer).
inline std::string gbg_tracer_define(visibility_choice v) {
  switch (v) {
    case visibility_choice::exact: return "#define VPLKIT_GBG_TRACER_BVH\n";
    case visibility_choice::paper_voxels: return "";
    case visibility_choice::voxels: break;
  }
  return "#define VPLKIT_GBG_TRIANGLE_VOXELS\n";
}

// Loop iterations one visibility query or traced ray may spend: a voxel march crosses at most
// rx + ry + rz voxels, and with the triangle voxels tests at most march_triangle_tests triangles
// in them (without the scene's buffers: a bound of 2 per voxel crossed); a BVH query visits at
// most gpu_bvh::query_cost nodes and triangles.
inline long long gpu_query_cost(const gpu_scene_buffers* scene, visibility_choice v, const vplkit::ivec3& voxels) {
  const long long march = static_cast<long long>(voxels.x) + voxels.y + voxels.z;
  switch (v) {
    case visibility_choice::exact: return scene != nullptr ? scene->bvh.query_cost : 1024;
    case visibility_choice::paper_voxels: return march;
    case visibility_choice::voxels: break;
  }
  return march + (scene != nullptr ? scene->voxel_triangles.march_tests : 2 * march);
}

// The bindings of the buffers a kind reads beyond the G-buffer, DPRSM and occupancy words.
// voxel_bricks: the brick level of the voxels' marches (VPLKIT_VOXEL_BRICKS in the kernel);
// no_binding for a kernel that steps through empty space voxel by voxel.
constexpr unsigned no_binding = ~0u;
struct visibility_bindings {
  unsigned bvh_nodes, bvh_triangles;                                         // exact
  unsigned voxel_rank, voxel_offsets, voxel_entries, voxel_triangles;        // voxels
  unsigned voxel_bricks = no_binding;                                        // voxels
};

// Binds the buffers the kind reads beyond the G-buffer, DPRSM and occupancy words (exact: the
// BVH's nodes and triangles; voxels: the triangle voxel grid's four arrays and, when bound, its
// brick level); returns the BVH's node count for the kernel (0 for the voxel kinds).
inline std::uint32_t bind_visibility_buffers(const gpu_scene_buffers& scene, visibility_choice v,
                                             const visibility_bindings& at) {
  switch (v) {
    case visibility_choice::exact: {
      const gpu_bvh& b = gpu_frame_bvh(scene, "gpu visibility");
      b.nodes.bind(at.bvh_nodes);
      b.triangles.bind(at.bvh_triangles);
      return b.node_count;
    }
    case visibility_choice::paper_voxels: break;
    case visibility_choice::voxels: {
      const gpu_triangle_voxels& t = scene.voxel_triangles;
      t.rank.bind(at.voxel_rank);
      t.offsets.bind(at.voxel_offsets);
      t.entries.bind(at.voxel_entries);
      t.triangles.bind(at.voxel_triangles);
      if (at.voxel_bricks != no_binding) t.bricks.bind(at.voxel_bricks);
      break;
    }
  }
  return 0u;
}

}  // namespace vplrender
