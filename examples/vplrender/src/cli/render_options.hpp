// SPDX-License-Identifier: MIT
#pragma once
// The command line's options turned into the pipeline's settings, and the pipeline driven by them:
// what vplrender, the window, examples/speed_vs_error and the tests run.
#include "cli/options.hpp"
#include "cli/scene_setup.hpp"
#include "render/pipeline.hpp"

namespace vplrender {

frame_settings make_frame_settings(const options& o);

// dmin = 1% of the scene diagonal (docs/math.md section 2); the rest is o's.
render_settings make_render_settings(const options& o, const scene& s);

// The pipeline's stages for o (render/pipeline.hpp). run_estimator runs o's method and switches
// on the backend `b` was prepared for; b must come from prepare_buffers with o's scene, size,
// dprsm, voxels and backend.
frame_buffers prepare_buffers(const options& o, const prepared_scene& p, stage_timer& timer, nlohmann::json& det);
render_result run_estimator(const options& o, const prepared_scene& p, const frame_buffers& b, stage_timer& timer,
                            const progress_fn& progress, nlohmann::json& det);
pipeline_result run_pipeline(const options& o, const prepared_scene& p, stage_timer& timer,
                             const progress_fn& progress = {});

}  // namespace vplrender
