#pragma once
// vplrender's pipeline, stage by stage (docs/renderer.md): headless GL context -> G-buffer and
// DPRSM rasterised on the GPU and read back -> voxel grid -> the estimator of --method.
#include "app/options.hpp"
#include "app/report.hpp"
#include "app/scene_setup.hpp"
#include "io/image.hpp"
#include "render/cpu/cpu_backend.hpp"
#include "render/stage_timer.hpp"

#include <headless_gl/context.hpp>

#include <vplkit/visibility/voxel_grid.hpp>

#include <nlohmann/json.hpp>

namespace vplrender {

struct pipeline_result {
  image_rgb image;
  std::string gl_renderer;      // headless context description
  nlohmann::json details;       // per-stage facts for the report ("pipeline" key)
};

// The process's headless GL context (created on first call; the pipeline and the tests share it).
// Throws vplkit::gl::gl_error listing every path tried when none works.
vplkit::gl::headless_context& pipeline_gl_context();

// "Prepare once, estimate many" (examples/speed_vs_error): the method-independent stages (GL
// context, G-buffer, DPRSM, voxel grid) and the estimator of o.meth on top of them. run_pipeline is
// exactly prepare_buffers followed by run_estimator.
struct pipeline_buffers {
  std::string gl_renderer;
  gbuffer_data gbuf;
  dprsm_data dprsm;
  vplkit::voxel_grid<float> grid;
};

// Stages go to `timer`, facts to `det` (keys gbuffer, dprsm, voxels). Depends on o's scene, size,
// dprsm, voxels and backend only. Throws vplkit::gl::gl_error when no GL context can be made.
pipeline_buffers prepare_buffers(const options& o, const prepared_scene& p, stage_timer& timer, nlohmann::json& det);

// The estimator of o.meth (its builders, CDFs and estimate stages go to `timer`; facts to `det`:
// keys estimator, estimator_backend, builders_backend). `b` must come from prepare_buffers with
// the same scene, size, dprsm, voxels and backend. Throws input_error for inputs it refuses.
cpu_render_result run_estimator(const options& o, const prepared_scene& p, const pipeline_buffers& b,
                                stage_timer& timer, const progress_fn& progress, nlohmann::json& det);

// Throws input_error for inputs the pipeline refuses, vplkit::gl::gl_error when no GL context can
// be made (the message lists every path tried).
pipeline_result run_pipeline(const options& o, const prepared_scene& p, stage_timer& timer,
                             const progress_fn& progress = {});

}  // namespace vplrender
