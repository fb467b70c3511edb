// SPDX-License-Identifier: MIT
#pragma once
// The GPU backend's builders and CDFs, the counterpart of render/cpu/cpu_builders.hpp, on the
// frame's GPU scene buffers:
//  - global (BRSM) weights and local per-region weights: the pack's builders/gather_subset.comp
//    (the stratified subsets, pixel for pixel the C++ stratified_gather_subset /
//    local_gather_subsets with the CPU builder's seeds) and builders/global_weights.comp (per
//    (texel, region) the float mean of luminance(contribution) in the subset's order, as
//    vplkit::global_weight_texel);
//  - GBG weights: builders/gbg_accumulate.comp + gbg_finish.comp (fixed point, hole fill);
//  - the defensive mixtures over them: gpu_cdf.hpp.
// The weights stay on the GPU and go straight into build_mixtures_gpu: nothing but a few counts
// comes back to the host.
#include "raster/gpu_scene_buffers.hpp"
#include "render/frame_buffers.hpp"
#include "render/gpu/gpu_cdf.hpp"
#include "render/settings.hpp"
#include "render/stage_timer.hpp"

#include <headless_gl/compute.hpp>
#include <vplkit/builders/gather_subset.hpp>

#include <nlohmann/json.hpp>

#include <cstdint>
#include <vector>

namespace vplrender {

// The frame's scene buffers on the GPU; throws vplkit::invalid_input naming `who` when the frame was
// prepared for the CPU backend (b.gpu is null).
const gpu_scene_buffers& scene_on_gpu(const frame_buffers& b, const char* who);

// The frame's DPRSM with its arrays, for a host-side consumer (--sampler alias, --face-selection
// roulette): b.dprsm when the frame has host copies, else read back from the GPU.
dprsm_data host_dprsm(const frame_buffers& b);

// The stratified gather subsets of `rects` on the GPU (the pack's builders/gather_subset.comp):
// rectangle i's count strata at pixels[i count ..) (-1 for a stratum that dropped), seed `seed`,
// stream offset i count, pixel for pixel the C++ local_gather_subsets (stratified_gather_subset for
// one rectangle); offsets[i] = i count (rects + 1 of them). `params` keeps the dispatches' blocks
// alive until the work is done.
struct gpu_gather_subsets {
  vplkit::gl::buffer pixels, offsets;
  std::vector<vplkit::gl::buffer> params;
};
gpu_gather_subsets build_gather_subsets_gpu(const gpu_scene_buffers& scene, const vplkit::gbuffer_view<float>& g,
                                            const std::vector<vplkit::pixel_rect>& rects, int count,
                                            std::uint32_t seed);
// |S_i|: the strata of each rectangle that kept a pixel (read back; a few hundred ints).
std::vector<int> gather_subset_sizes(const gpu_gather_subsets& s, int rects, int count);

// BRSM weights on the GPU: N = 1 (global: whole image, s.global_subset strata, seed
// builder_seed(s.seed, 0)) or N = regions (local: s.regions_x x s.regions_y regions,
// s.local_subset strata each, seed builder_seed(s.seed, 1), stream offset i * count).
// `weights` holds (N + 1) 2 R^2 floats, region-major; the last array is left for the CDF build's
// fallback. used[i]: valid gather points of subset i (the CPU builder's |S_i|). Stage
// "<global|local> weights (gpu)" goes to `timer`.
struct gpu_weights {
  vplkit::gl::buffer weights;
  int regions = 1;
  std::vector<int> used;
};
gpu_weights build_brsm_weights_gpu(const frame_buffers& b, const render_settings& s, bool local, stage_timer& timer);

// The GBG weights on the GPU: gbg_accumulate.comp over the valid pixels with the CPU builder's
// parameters (n_dirs = s.dirs, s.dmin, gathering_depth_tolerance(grid), seed
// builder_seed(s.seed, 2), s.gbg_accumulator), then gbg_finish.comp with the hole fill. Equal to
// build_distributions_cpu's within the fixed-point bound of docs/glsl/builders.md. Facts (as the
// CPU's "gbg" key plus scale, max_units, saturated) go to `det`, the GPU time to `timer` ("gbg
// weights + hole fill (gpu)"). read_back = false leaves `weights` empty (the weights stay in
// `buffer`).
struct gbg_gpu_weights {
  std::vector<float> weights;
  double scale = 0.0;   // fixed-point units per unit of weight sum (a power of two)
  long long lit_hits = 0;
  int gather_points = 0;
  vplkit::gl::buffer buffer;  // the filled weights on the GPU (2 R^2 floats)
};
gbg_gpu_weights build_gbg_weights_gpu(const frame_buffers& b, const render_settings& s, stage_timer& timer,
                                      nlohmann::json& det, bool read_back = true);

// Every builder and CDF of s.meth on the GPU (has_distribution(s.meth) must hold): the mixtures
// the estimate kernels sample, builder facts in `det` under the CPU builder's keys (global_subset;
// local_subsets, local_rounds, local_combination; gbg) plus "builders": "gpu".
gpu_mixtures build_distributions_gpu(const frame_buffers& b, const render_settings& s, stage_timer& timer,
                                     nlohmann::json& det);

}  // namespace vplrender
