// SPDX-License-Identifier: MIT
#pragma once
// vplrender's pipeline, stage by stage (docs/renderer.md, docs/architecture.md "Renderer data
// flow"): headless GL context -> G-buffer and DPRSM rasterised on the GPU and read back -> voxel
// grid -> (GPU backend) the scene buffers on the GPU, once -> the estimator of the method, on the
// backend the buffers were prepared for.
#include "render/frame_buffers.hpp"
#include "render/result.hpp"
#include "render/settings.hpp"
#include "render/stage_timer.hpp"
#include "scene/scene.hpp"

#include <headless_gl/context.hpp>

#include <nlohmann/json.hpp>

#include <string>

namespace vplrender {

// The process's headless GL context (created on first call; the pipeline and the tests share it).
// Throws vplkit::gl::gl_error listing every path tried when none works.
vplkit::gl::headless_context& pipeline_gl_context();

// What the method-independent stages depend on.
struct frame_settings {
  int width = 512, height = 512;
  int dprsm = 512;   // paraboloid map resolution per face
  int voxels = 128;  // voxel grid resolution per axis
  backend back = backend::gpu;
  // Also build the exact ray-tracing structures: the scene in Embree (frame_buffers::rays: exact
  // rays on the CPU backend, and the surface offset both backends use) and, for the GPU backend,
  // the scene's BVH and the triangles' shading on the GPU (gpu_scene_buffers::bvh, ::shading).
  // Needed by --visibility exact and --method exact.
  bool exact_rays = false;
};

// "Prepare once, estimate many" (examples/speed_vs_error, the window): the method-independent
// stages (GL context, G-buffer, DPRSM, voxel grid, and for the GPU backend the scene buffers on the
// GPU). Stages go to `timer`, facts to `det` (keys gbuffer, dprsm, voxels, scene_buffers). Throws
// vplkit::gl::gl_error when no GL context can be made.
frame_buffers prepare_buffers(const scene& s, const frame_settings& f, stage_timer& timer, nlohmann::json& det);

// The estimator of s.meth on the backend `b` was prepared for (its builders, CDFs and estimate
// stages go to `timer`; facts to `det`: keys estimator, estimator_backend, builders_backend,
// memory). Throws input_error for inputs it refuses.
render_result run_estimator(const frame_buffers& b, const render_settings& s, stage_timer& timer,
                            const progress_fn& progress, nlohmann::json& det);

struct pipeline_result {
  image_rgb image;
  std::string gl_renderer;  // headless context description
  nlohmann::json details;   // per-stage facts for the report ("pipeline" key)
};

// prepare_buffers followed by run_estimator. Throws input_error for inputs the pipeline refuses,
// vplkit::gl::gl_error when no GL context can be made (the message lists every path tried).
pipeline_result run_pipeline(const scene& sc, const frame_settings& f, const render_settings& s, stage_timer& timer,
                             const progress_fn& progress = {});

}  // namespace vplrender
