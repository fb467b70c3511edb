// SPDX-License-Identifier: MIT
#pragma once
// The CPU backend's visibility and tracer, the callables vplkit's estimators and builders take
// (include/vplkit/visibility/visibility_callables.hpp), chosen by render_settings::visibility:
// voxels (the triangles the frame's voxel grid lists: triangle_voxel_visibility,
// triangle_voxel_tracer), paper_voxels (its occupancy: voxel_visibility, voxel_tracer) or exact
// (the scene's triangles in Embree, render/cpu/ray_scene.hpp). This is the one place that maps a visibility_choice to
// code on the CPU; a new kind adds a member and a case to both structs. The kind is a run-time
// branch per query, the same every time, so it costs nothing measurable next to the query.
#include "render/cpu/ray_scene.hpp"
#include "render/frame_buffers.hpp"
#include "render/settings.hpp"

#include <vplkit/core/error.hpp>
#include <vplkit/visibility/visibility_callables.hpp>

#include <limits>

namespace vplrender {

struct cpu_visibility {
  visibility_choice kind = visibility_choice::voxels;
  vplkit::triangle_voxel_visibility<float> voxels;
  vplkit::voxel_visibility<float> paper_voxels;
  const ray_scene* exact = nullptr;
  bool operator()(vec3 x, vec3 n_x, vec3 y, vec3 n_y) const {
    switch (kind) {
      case visibility_choice::exact: return exact->visible(x, n_x, y, n_y);
      case visibility_choice::paper_voxels: return paper_voxels(x, n_x, y, n_y);
      case visibility_choice::voxels: break;
    }
    return voxels(x, n_x, y, n_y);
  }
};

struct cpu_tracer {
  visibility_choice kind = visibility_choice::voxels;
  vplkit::triangle_voxel_tracer<float> voxels;
  vplkit::voxel_tracer<float> paper_voxels;
  const ray_scene* exact = nullptr;
  vplkit::ray_hit<float> operator()(vec3 x, vec3 n_x, vec3 dir) const {
    return trace_within(x, n_x, dir, std::numeric_limits<float>::infinity());
  }
  // Is a surface other than x's own plane within reach (vplkit's surface_within protocol: the
  // clamp compensation traces nothing where none is)? The triangle voxels list the same triangles
  // as the exact rays see; the paper's voxel-entry points lie up to a voxel diagonal off their
  // surfaces, so that kind cannot say.
  bool surface_within(vec3 x, vec3 n_x, float reach, float plane_tolerance) const {
    if (kind == visibility_choice::paper_voxels) return true;
    return voxels.surface_within(x, n_x, reach, plane_tolerance);
  }
  // The first hit when it lies within reach of x (vplkit's trace_within protocol: the clamp
  // compensation's short rays); every kind stops its ray about there.
  vplkit::ray_hit<float> trace_within(vec3 x, vec3 n_x, vec3 dir, float reach) const {
    switch (kind) {
      case visibility_choice::exact: {
        vplkit::ray_hit<float> h = exact->trace(x, n_x, dir, reach);
        if (!shading_normals) h.shading_normal = vec3(0.0f);
        return h;
      }
      case visibility_choice::paper_voxels: return paper_voxels.trace_within(x, n_x, dir, reach);
      case visibility_choice::voxels: break;
    }
    vplkit::ray_hit<float> h = voxels.trace_within(x, n_x, dir, reach);
    if (!shading_normals) h.shading_normal = vec3(0.0f);
    return h;
  }
  // Gathering's lit test (vplkit/visibility/light_visibility.hpp): a shadow ray through Embree
  // (lit_test_choice::shadow_ray with exact visibility) or the voxel march under the exact
  // contract, else the DPRSM's shadow map.
  bool shadow_ray = false;
  // Exact hits carry their shading normal; the GBG builder's tracer drops it, as the GPU's GBG
  // kernel (the pack's BVH tracer) has none, so that both backends build the same weights.
  bool shading_normals = true;
  // The voxel march answers it under the exact contract (--voxel-contract exact): the same segment
  // from y moved off its surface to the light.
  bool answers_light_visibility() const {
    return shadow_ray && (kind == visibility_choice::exact ? exact != nullptr
                                                           : kind == visibility_choice::voxels &&
                                                                 voxels.ends == vplkit::triangle_voxel_ends::offset);
  }
  bool light_visible(vec3 y, vec3 n_y, vec3 c) const {
    if (kind == visibility_choice::exact) return exact->visible(y, n_y, c, vec3(0.0f));
    return vplkit::triangle_voxel_visible_offset(voxels.grid, y, n_y, c, vec3(0.0f), voxels.offset);
  }
};

// The frame's ray scene, or invalid_input naming `who` when the frame was prepared without one
// (frame_settings::exact_rays).
inline const ray_scene& frame_ray_scene(const frame_buffers& b, const char* who) {
  if (!b.rays)
    throw vplkit::invalid_input(std::string(who) +
                                ": exact visibility needs a frame prepared with exact rays (frame_settings::exact_rays)");
  return *b.rays;
}

// The triangle voxels' contract (--voxel-contract): exact moves the ends by the exact rays'
// offset when the frame has them, else by the grid's own (vplkit::triangle_voxel_surface_offset),
// and shades the tracer's hits with the scene's corner normals.
template <class Query>
inline void set_voxel_contract(const frame_buffers& b, voxel_contract_choice e, Query& q) {
  if (e != voxel_contract_choice::exact) return;
  q.ends = vplkit::triangle_voxel_ends::offset;
  q.offset = b.rays ? b.ray_frame.surface_offset : vplkit::triangle_voxel_surface_offset(b.grid.view().grid);
}

inline cpu_visibility make_cpu_visibility(const frame_buffers& b, visibility_choice v,
                                          voxel_contract_choice contract = voxel_contract_choice::plane_rule) {
  cpu_visibility c;
  c.kind = v;
  c.voxels = vplkit::triangle_voxel_visibility<float>{b.grid.view()};
  set_voxel_contract(b, contract, c.voxels);
  c.paper_voxels = vplkit::voxel_visibility<float>{b.grid.occupancy().view()};
  if (v == visibility_choice::exact) c.exact = &frame_ray_scene(b, "cpu visibility");
  return c;
}

inline cpu_tracer make_cpu_tracer(const frame_buffers& b, visibility_choice v,
                                  lit_test_choice lit = lit_test_choice::shadow_map,
                                  voxel_contract_choice contract = voxel_contract_choice::plane_rule) {
  cpu_tracer c;
  c.kind = v;
  c.shadow_ray = lit == lit_test_choice::shadow_ray;  // answered only with exact rays (answers_light_visibility)
  c.voxels = vplkit::triangle_voxel_tracer<float>{b.grid.view()};
  set_voxel_contract(b, contract, c.voxels);
  if (contract == voxel_contract_choice::exact) {
    if (!b.corners)
      throw vplkit::invalid_input("cpu tracer: --voxel-contract exact needs the frame's voxel corners (a CPU-backend frame)");
    c.voxels.corners = b.corners->view();
  }
  c.paper_voxels = vplkit::voxel_tracer<float>{b.grid.occupancy().view()};
  if (v == visibility_choice::exact) c.exact = &frame_ray_scene(b, "cpu tracer");
  return c;
}

}  // namespace vplrender
