// SPDX-License-Identifier: MIT
#pragma once
// What the method-independent stages (render/pipeline.hpp, prepare_buffers) hand to every estimator
// run: the G-buffer, the DPRSM and the voxel grid of one frame as CPU arrays (the CPU backend, the
// report, the tests) and, when prepared for the GPU backend, the same buffers on the GPU, made once
// (raster/gpu_scene_buffers.hpp). Both backends take this one type.
#include "raster/render_data.hpp"
#include "raster/voxels.hpp"
#include "render/settings.hpp"

#include <memory>
#include <string>

namespace vplrender {

struct gpu_scene_buffers;  // raster/gpu_scene_buffers.hpp (GL types; this header stays GL-free)
class ray_scene;          // render/cpu/ray_scene.hpp (Embree types stay out of this header)

struct frame_buffers {
  backend back = backend::gpu;  // the backend whose estimators these buffers serve
  std::string gl_renderer;      // the headless context's description
  gbuffer_data gbuf;
  dprsm_data dprsm;
  scene_voxels grid;  // the triangle voxel grid; grid.occupancy() is the paper's binary grid
  // The same G-buffer, DPRSM and voxel grid on the GPU; null for the CPU backend.
  std::shared_ptr<const gpu_scene_buffers> gpu;
  // The scene's triangles in Embree (--visibility exact on the CPU, --method exact); null unless
  // the frame was prepared with frame_settings::exact_rays.
  std::shared_ptr<const ray_scene> rays;
};

}  // namespace vplrender
