// SPDX-License-Identifier: MIT
#pragma once
// vplrender's pipeline, stage by stage (docs/renderer.md, docs/architecture.md "Renderer data
// flow"): headless GL context -> voxel grid and (GPU backend) the scene's buffers on the GPU, once
// per scene -> per frame, the G-buffer and the DPRSM rasterised on the GPU (kept there for the GPU
// backend, read back for the CPU backend) -> the estimator of the method, on the backend the
// buffers were prepared for.
#include "render/frame_buffers.hpp"
#include "render/result.hpp"
#include "render/settings.hpp"
#include "render/stage_timer.hpp"
#include "scene/scene.hpp"

#include <headless_gl/context.hpp>

#include <nlohmann/json.hpp>

#include <memory>
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

// The method-independent stages, split into what depends on the scene's geometry only (made once:
// GL context, the rasteriser's programs, mesh and textures, the voxel grid, the exact-ray
// structures, and for the GPU backend the buffers of all of them on the GPU) and what depends on
// the camera and the light (per frame: the G-buffer and the DPRSM). A GPU frame keeps the G-buffer
// and the DPRSM on the GPU: nothing is read back (frame_buffers.hpp). `s` must outlive this.
class frame_pipeline {
public:
  // Stages "gl context", "raster setup (cpu)", "voxelize (gpu|cpu)", (GPU) "scene upload (cpu)",
  // (exact rays) "embree scene (cpu)", "bvh build and upload (cpu)"; facts under det keys voxels,
  // exact_rays. Throws vplkit::gl::gl_error when no GL context can be made.
  frame_pipeline(const scene& s, const frame_settings& f, stage_timer& timer, nlohmann::json& det);
  ~frame_pipeline();
  frame_pipeline(const frame_pipeline&) = delete;
  frame_pipeline& operator=(const frame_pipeline&) = delete;

  // The frame of s's camera and the light `light` (its frame as dprsm_light's: front face down):
  // stages "gbuffer (gpu)", "dprsm tessellation (cpu)", "dprsm (gpu)", (CPU backend) "gbuffer
  // read-back (cpu)", "dprsm read-back (cpu)", and "frame facts (gpu|cpu)"; facts under det keys
  // gbuffer, dprsm, scene_buffers. The buffers are overwritten by the next call.
  const frame_buffers& render(const vplkit::point_light<float>& light, stage_timer& timer, nlohmann::json& det);
  // GPU backend: starts the DPRSM split for the next frame's light on other threads, to run while
  // the GPU renders this frame (the next render() for that light then only waits and uploads; its
  // stage "dprsm tessellation (cpu)" is that wait and the upload, and "dprsm split ahead (cpu,
  // beside the gpu)" the split's own wall time, overlapped). The CPU backend's estimate wants
  // every core itself: there it does nothing.
  void split_ahead(const vplkit::point_light<float>& next_light);
  const frame_buffers& buffers() const;
  // The buffers, moved out (the pipeline is done with them).
  frame_buffers release();

private:
  struct impl;
  std::unique_ptr<impl> impl_;
};

// "Prepare once, estimate many" (examples/speed_vs_error, the window): frame_pipeline's stages for
// s's light, once. Stages go to `timer`, facts to `det` (keys gbuffer, dprsm, voxels,
// scene_buffers). Throws vplkit::gl::gl_error when no GL context can be made.
frame_buffers prepare_buffers(const scene& s, const frame_settings& f, stage_timer& timer, nlohmann::json& det);

// Reads a GPU frame's G-buffer and DPRSM back into b.gbuf and b.dprsm (nothing to do when
// b.has_host_copies()): for a CPU-side consumer of a GPU frame.
void read_back_host_copies(frame_buffers& b);

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
