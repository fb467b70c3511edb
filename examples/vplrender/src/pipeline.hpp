#pragma once
// vplrender's pipeline, stage by stage (docs/renderer.md): headless GL context -> G-buffer and
// DPRSM rasterised on the GPU and read back -> voxel grid -> the estimator of --method.
#include "cpu_backend.hpp"
#include "image.hpp"
#include "options.hpp"
#include "report.hpp"
#include "scene_setup.hpp"
#include "stage_timer.hpp"

#include <headless_gl/context.hpp>

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

// Throws input_error for inputs the pipeline refuses, vplkit::gl::gl_error when no GL context can
// be made (the message lists every path tried).
pipeline_result run_pipeline(const options& o, const prepared_scene& p, stage_timer& timer,
                             const progress_fn& progress = {});

}  // namespace vplrender
