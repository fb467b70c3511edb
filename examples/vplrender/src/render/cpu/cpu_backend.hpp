// SPDX-License-Identifier: MIT
#pragma once
// The CPU backend: every method of vplrender on the frame's CPU buffers (G-buffer, DPRSM, voxel
// grid) through vplkit's builders and estimators (C++ templates, T = float), parallel over image
// rows. The GPU backend's counterpart is render/gpu/gpu_backend.hpp (same entry point, same result).
#include "render/frame_buffers.hpp"
#include "render/result.hpp"
#include "render/settings.hpp"
#include "render/stage_timer.hpp"

namespace vplrender {

// The clamp compensation's stage (--clamp-compensation on): an "estimate" stage, so that
// speed_vs_error counts it in the estimate; the estimate itself is "estimate (cpu)".
constexpr const char* clamp_compensation_stage_cpu = "estimate: clamp compensation (cpu)";

// Stages are appended to `timer` (clock cpu-wall). Throws vplkit::invalid_input for bad views.
render_result render_cpu(const frame_buffers& b, const render_settings& s, stage_timer& timer,
                         const progress_fn& progress = {});

}  // namespace vplrender
