#pragma once
// The GPU backend: vplrender's estimators as compute shaders built from the GLSL pack
// (examples/vplrender/shaders/estimate.comp), one invocation per pixel, the CPU backend's random
// streams (make_counter_rng(seed, pixel)). Every builder and every CDF runs on the GPU too
// (gpu_builder_available): the GBG weights (gbg, mis, mis-as-published) by the pack's
// gbg_accumulate.comp + gbg_finish.comp (fixed point, hole fill), the global and local weights by
// gather_subset.comp + global_weights.comp (gpu_builders.cpp), the learned CDFs and the shared
// defensive fallback by cdf_build.comp (gpu_cdf.cpp). The weights and CDF arrays never leave the
// GPU; only the CDF totals (16 bytes per distribution) and the subsets' sizes come back, for the
// mixture scalars and the report. The direct light (--direct) is added inside estimate.comp
// (u_direct: vplkit_direct_light, the CPU backend's vplkit::direct_light), so the host only reads the
// finished image back. Stage times (docs/renderer.md): "<builder> (gpu)", "cdf (gpu)",
// "estimate (gpu)", "read-back (cpu)".
#include "render/cpu/cpu_backend.hpp"

#include <headless_gl/compute.hpp>

#include <vplkit/visibility/voxel_grid.hpp>

#include <vector>

namespace vplrender {

// True for the methods whose estimator runs on the GPU in this build (the rest fall back to the CPU).
bool gpu_estimator_available(method m);

// Renders on the current GL context; stages go to `timer` (builders, "cdf (gpu)" and
// "estimate (gpu)" with GPU timer queries, "upload (cpu)" / "read-back (cpu)" cpu-wall). Throws vplkit::invalid_input for bad views, vplkit::gl::gl_error for GL
// failures. Requires gpu_estimator_available(es.meth).
cpu_render_result render_gpu(const gbuffer_data& g, const dprsm_data& d, const vplkit::voxel_grid_view<float>& grid,
                             const estimator_settings& es, stage_timer& timer, const progress_fn& progress = {});

// True for the methods whose builders and CDFs run on the GPU: global, local, gbg, mis,
// mis-as-published (reference and gather have none).
bool gpu_builder_available(method m);

// The GBG weights on the GPU (current GL context): gbg_accumulate.comp over the valid pixels with
// the CPU builder's parameters (n_dirs = es.dirs, es.dmin, gathering_depth_tolerance(grid),
// seed builder_seed(es.seed, 2), gathering accumulator), then gbg_finish.comp with the hole fill.
// Returns the filled weights (2 R^2); equal to build_distributions_cpu's within the fixed-point
// bound of docs/glsl/builders.md. Facts (as the CPU's "gbg" key plus scale, max_units, saturated)
// go to `det`, the GPU time to `timer` ("gbg weights + hole fill (gpu)", GPU timer query).
// read_back = false leaves `weights` empty (the weights stay in `buffer` for build_mixtures_gpu).
struct gbg_gpu_weights {
  std::vector<float> weights;
  double scale = 0.0;   // fixed-point units per unit of weight sum (a power of two)
  long long lit_hits = 0;
  int gather_points = 0;
  vplkit::gl::buffer buffer;  // the filled weights on the GPU (2 R^2 floats)
};
gbg_gpu_weights build_gbg_weights_gpu(const gbuffer_data& g, const dprsm_data& d,
                                      const vplkit::voxel_grid_view<float>& grid, const estimator_settings& es,
                                      stage_timer& timer, nlohmann::json& det, bool read_back = true);

// Loop iterations one dispatch may spend per invocation (llvmpipe stops every loop after 65535 per
// invocation, silently; the host keeps a margin) and the passes a method is split into.
constexpr int gpu_loop_budget = 60000;
int gpu_pass_count(const estimator_settings& es, int dprsm_resolution, const vplkit::ivec3& voxel_resolution,
                   int regions);

}  // namespace vplrender
