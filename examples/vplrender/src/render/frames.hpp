// SPDX-License-Identifier: MIT
#pragma once
// `vplrender --frames N` without a window (docs/renderer.md, "Frames"): N frames in one process,
// the light moving along light_path, everything that depends only on the geometry made once
// (render/pipeline.hpp, frame_pipeline) and per frame the G-buffer, the DPRSM, the builders, the
// CDFs and the estimate, with nothing read back but the image on the GPU backend. One untimed
// warm-up frame (the path's frame 0) comes first, so that every kernel variant is compiled before
// the timed frames. Both backends.
#include "io/image.hpp"
#include "render/light_path.hpp"
#include "render/pipeline.hpp"

#include <nlohmann/json.hpp>

#include <functional>
#include <string>
#include <vector>

namespace vplrender {

struct frames_run {
  std::vector<double> frame_ms;                 // per timed frame: wall time from its G-buffer to its image on the host
  std::vector<std::vector<stage_time>> stages;  // per timed frame: its stages
  image_rgb last_image;                         // the last frame's image
  nlohmann::json last_details;                  // the last frame's facts (as pipeline_result::details)
  std::string gl_renderer;
};

// Called with each timed frame's index and image (tests compare them with single renders).
using frame_image_fn = std::function<void(int frame, const image_rgb& image)>;

// The geometry-only stages and the warm-up frame ("warm-up frame", cpu-wall) go to `setup`.
// Throws as run_pipeline.
frames_run run_frames(const scene& s, const frame_settings& f, const render_settings& rs, const light_path& path,
                      stage_timer& setup, const frame_image_fn& each_frame = {});

// The "frames" object of the JSON report: count, median_ms (and min, max, fps), the per-stage
// medians over the timed frames (stages: name, median_ms, clock, in the order of the first frame),
// the warm-up frames, the light path and which frame's image was written.
nlohmann::json frames_report(const frames_run& r, const light_path& path);

}  // namespace vplrender
