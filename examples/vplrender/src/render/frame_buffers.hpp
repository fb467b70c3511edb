// SPDX-License-Identifier: MIT
#pragma once
// What the method-independent stages (render/pipeline.hpp) hand to every estimator run: the
// G-buffer, the DPRSM and the voxel grid of one frame. Both backends take this one type.
//  - CPU backend: the G-buffer and the DPRSM as CPU arrays (read back from the rasteriser).
//  - GPU backend: the same data on the GPU only (raster/gpu_scene_buffers.hpp, written there by the
//    rasteriser): `gbuf` and `dprsm` then carry their sizes and the light but no arrays, and
//    nothing is read back but the image. read_back_host_copies (render/pipeline.hpp) fills the
//    arrays for a CPU-side consumer that needs them (a test, --sampler alias's host tables).
// The voxel grid (geometry only) is on the host for both, and also on the GPU for the GPU backend.
#include "raster/render_data.hpp"
#include "raster/voxels.hpp"
#include "render/settings.hpp"

#include <cstddef>
#include <limits>
#include <memory>
#include <string>

namespace vplrender {

struct gpu_scene_buffers;  // raster/gpu_scene_buffers.hpp (GL types; this header stays GL-free)
class ray_scene;          // render/cpu/ray_scene.hpp (Embree types stay out of this header)

// What the host needs to know about a frame's G-buffer and DPRSM as numbers: the report's and the
// lighting warnings' pixel counts and the GBG builder's fixed-point bound. Counted on the GPU for a
// GPU frame (shaders/frame_facts.comp), from the arrays otherwise (host_frame_facts).
struct frame_facts {
  bool known = false;                   // false: not counted yet (host_frame_facts on the arrays)
  std::size_t valid_pixels = 0;         // pixels that show a surface (gbuffer_data::valid_count)
  std::size_t gather_points = 0;        // ... that are gather points (vplkit::gather_point_valid)
  std::size_t directly_lit_pixels = 0;  // ... that the light reaches (vplkit::direct_light > 0)
  // The smallest distance from the light to a DPRSM texel that saw a surface (albedo != 0);
  // +infinity when none did.
  float nearest_lit_distance = std::numeric_limits<float>::infinity();
};

// The number both backends' exact rays share (render/cpu/ray_scene.hpp computes it): how far a
// ray's ends move off their surfaces, so the GPU's exact kernels move the same points by the same
// amounts as Embree's rays without including the CPU backend.
struct exact_ray_frame {
  float surface_offset = 0.0f;
};

struct frame_buffers {
  backend back = backend::gpu;  // the backend whose estimators these buffers serve
  std::string gl_renderer;      // the headless context's description
  gbuffer_data gbuf;            // GPU backend: sizes only, unless has_host_copies()
  dprsm_data dprsm;             // GPU backend: resolution and light only, unless has_host_copies()
  scene_voxels grid;  // the triangle voxel grid; grid.occupancy() is the paper's binary grid
  // The same G-buffer, DPRSM and voxel grid on the GPU; null for the CPU backend.
  std::shared_ptr<const gpu_scene_buffers> gpu;
  // The scene's triangles in Embree (--visibility exact on the CPU, --method exact); null unless
  // the frame was prepared with frame_settings::exact_rays.
  std::shared_ptr<const ray_scene> rays;
  exact_ray_frame ray_frame;  // rays' numbers; meaningful when rays is set
  frame_facts facts;  // set by the pipeline; a frame made from arrays leaves it to host_frame_facts
  // The scene's corners in the grid's triangle order, for the CPU voxel tracer's shading normals
  // (--voxel-contract exact); the pipeline sets it for the CPU backend, null otherwise.
  std::shared_ptr<const voxel_corners> corners;

  // The G-buffer and the DPRSM are on the host as arrays.
  bool has_host_copies() const {
    return gbuf.position.size() == static_cast<std::size_t>(gbuf.width) * static_cast<std::size_t>(gbuf.height) &&
           dprsm.position.size() == 2 * static_cast<std::size_t>(dprsm.resolution) * static_cast<std::size_t>(dprsm.resolution);
  }
};

// The facts counted from the arrays (as frame_facts.comp counts them on the GPU).
frame_facts host_frame_facts(const gbuffer_data& g, const dprsm_data& d);

// b.facts when known, else host_frame_facts of b's arrays (a frame made from arrays by hand);
// throws vplkit::invalid_input when it has neither.
frame_facts facts_of(const frame_buffers& b);

// b.ray_frame; throws vplkit::invalid_input naming `who` when the frame was prepared without exact
// rays (frame_settings::exact_rays).
const exact_ray_frame& frame_exact_rays(const frame_buffers& b, const char* who);

}  // namespace vplrender
