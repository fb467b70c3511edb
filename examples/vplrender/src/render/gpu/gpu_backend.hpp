// SPDX-License-Identifier: MIT
#pragma once
// The GPU backend: every method of vplrender as a compute shader built from the GLSL pack, one
// kernel per estimator (render/gpu/estimate_kernels.hpp: examples/vplrender/shaders/
// estimate_<estimator>.comp; --method exact: exact.comp, which shades its hits as the CPU's
// ray_scene does), specialised per render by compile-time defines (estimate_params.h), one
// invocation per pixel, on the frame's GPU scene buffers, with the CPU backend's random streams
// (make_counter_rng(seed, pixel)). Every builder and CDF runs on the GPU too (gpu_builders.hpp);
// the weights and CDF arrays never leave the GPU, only the CDF totals and the subsets' sizes come
// back, for the mixture scalars and the report. The direct light (--direct) is added inside the
// estimate kernel (vplkit_direct_light, the CPU backend's vplkit::direct_light), so the host only
// reads the finished image back. The CPU backend's counterpart is render/cpu/cpu_backend.hpp
// (same entry point, same result). Stage times (docs/renderer.md): "<builder> (gpu)", "cdf (gpu)",
// "estimate (gpu)", "read-back (cpu)".
#include "render/frame_buffers.hpp"
#include "render/result.hpp"
#include "render/settings.hpp"
#include "render/stage_timer.hpp"

#include <vplkit/core/vector.hpp>

namespace vplrender {

// On the current GL context; b must have been prepared for the GPU backend (b.gpu set). Throws
// vplkit::invalid_input for bad views, vplkit::gl::gl_error for GL failures.
render_result render_gpu(const frame_buffers& b, const render_settings& s, stage_timer& timer,
                         const progress_fn& progress = {});

// The passes (dispatches) a method's samples are split into where the loop budget applies
// (loop_budget.hpp: llvmpipe, or render_settings::loop_budget always) for a DPRSM of 2 R^2 texels,
// a voxel grid and `regions` local CDFs; elsewhere every stage is one dispatch.
int gpu_pass_count(const render_settings& s, int dprsm_resolution, const vplkit::ivec3& voxel_resolution, int regions);

}  // namespace vplrender
