#pragma once
// The builders of the GPU backend on the GPU: the global (BRSM) weights and the local per-region
// weights from the pack's builders/gather_subset.comp (the stratified subsets, pixel for pixel the
// C++ stratified_gather_subset / local_gather_subsets with the CPU builder's seeds) and
// builders/global_weights.comp (per (texel, region) the float mean of luminance(contribution) in
// the subset's order, as vplkit::global_weight_texel); the GBG weights from build_gbg_weights_gpu
// (gpu_backend.cpp). The weights stay on the GPU and go straight into build_mixtures_gpu
// (gpu_cdf.hpp): nothing but a few counts comes back to the host.
#include "render/cpu/cpu_backend.hpp"
#include "render/gpu/gpu_cdf.hpp"

#include <headless_gl/compute.hpp>
#include <vplkit/visibility/voxel_grid.hpp>

#include <vector>

namespace vplrender {

// BRSM weights on the GPU: N = 1 (global: whole image, es.global_subset strata, seed
// builder_seed(es.seed, 0)) or N = regions (local: es.regions_x x es.regions_y regions,
// es.local_subset strata each, seed builder_seed(es.seed, 1), stream offset i * count).
// `weights` holds (N + 1) 2 R^2 floats, region-major; the last array is left for the CDF build's
// fallback. used[i]: valid gather points of subset i (the CPU builder's |S_i|). Stage
// "<global|local> weights (gpu)" goes to `timer`.
struct gpu_weights {
  vplkit::gl::buffer weights;
  int regions = 1;
  std::vector<int> used;
};
gpu_weights build_brsm_weights_gpu(const gbuffer_data& g, const dprsm_data& d, const estimator_settings& es, bool local,
                                   stage_timer& timer);

// DPRSM / G-buffer surfels as the pack's kernels and estimate.comp read them (3 vec4 per entry).
vplkit::gl::buffer dprsm_surfel_buffer(const dprsm_data& d);

// Every builder and CDF of es.meth on the GPU (gpu_builder_available(es.meth) must hold): the
// mixtures estimate.comp samples, builder facts in `det` under the CPU builder's keys
// (global_subset; local_subsets, local_rounds, local_combination; gbg) plus "builders": "gpu".
gpu_mixtures build_distributions_gpu(const gbuffer_data& g, const dprsm_data& d,
                                     const vplkit::voxel_grid_view<float>& grid, const estimator_settings& es,
                                     stage_timer& timer, nlohmann::json& det);

}  // namespace vplrender
