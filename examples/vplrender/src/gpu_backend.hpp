#pragma once
// The GPU backend: vplrender's estimators as compute shaders built from the GLSL pack
// (examples/vplrender/shaders/estimate.comp), one invocation per pixel, the CPU backend's random
// streams (make_counter_rng(seed, pixel)). Builders, hole filling and CDFs still run on the CPU
// (build_distributions_cpu) and are uploaded; the direct light is added on the CPU after read-back.
#include "cpu_backend.hpp"

#include <vplkit/visibility/voxel_grid.hpp>

namespace vplrender {

// True for the methods whose estimator runs on the GPU in this build (the rest fall back to the CPU).
bool gpu_estimator_available(method m);

// Renders on the current GL context; stages go to `timer` ("estimate (gpu)" with a GPU timer
// query, builders cpu-wall). Throws vplkit::invalid_input for bad views, vplkit::gl::gl_error for GL
// failures. Requires gpu_estimator_available(es.meth).
cpu_render_result render_gpu(const gbuffer_data& g, const dprsm_data& d, const vplkit::voxel_grid_view<float>& grid,
                             const estimator_settings& es, stage_timer& timer, const progress_fn& progress = {});

// Loop iterations one dispatch may spend per invocation (llvmpipe stops every loop after 65535 per
// invocation, silently; the host keeps a margin) and the passes a method is split into.
constexpr int gpu_loop_budget = 60000;
int gpu_pass_count(const estimator_settings& es, int dprsm_resolution, const vplkit::ivec3& voxel_resolution,
                   int regions);

}  // namespace vplrender
