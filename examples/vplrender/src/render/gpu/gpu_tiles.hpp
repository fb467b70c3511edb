// SPDX-License-Identifier: MIT
#pragma once
// --candidate-source tiles on the GPU backend (ris-mis): render/cpu/tiled_candidates.hpp's
// distributions, built on the GPU from the frame's DPRSM and G-buffer where they lie.
//  - the pack's builders/tile_blocks.comp: per block of B x B texels its texels' flux shares and
//    its proxy VPL;
//  - the tiles' gather points: builders/gather_subset.comp over the s.tiles_x x s.tiles_y tiles,
//    s.tile_points strata each, seed builder_seed(s.seed, 3) (the CPU's local_gather_subsets);
//  - the pack's builders/tile_weights.comp: per (block, tile) the proxy's mean unshadowed
//    contribution's luminance;
//  - one CDF over the blocks per tile (build_cdf_set_gpu).
// Mixture d of the estimate kernels (VR_RIS_TILES, estimate_tiles.glsl) is then tile d's: its
// learned part the block CDF (id VR_TILE_SLOT + d), its fallback the flux build's, mixed by the
// C++ mixture_split of --eps. Nothing but the totals and the points' counts comes back.
#include "render/frame_buffers.hpp"
#include "render/gpu/gpu_cdf.hpp"
#include "render/settings.hpp"
#include "render/stage_timer.hpp"

#include "estimate_params.h"

#include <headless_gl/compute.hpp>

#include <nlohmann/json.hpp>

#include <cstdint>
#include <vector>

namespace vplrender {

struct gpu_tiles {
  vplkit::gl::buffer data;  // VR_RIS_BINDING_TILES: the block CDFs, their guides, the shares
  std::uint32_t guide_base = 0, share_base = 0;  // where the guides and shares start in data (uints)
  int count = 0;   // tiles
  int blocks = 0;  // Nb = 2 ceil(R / B)^2
  std::vector<float> totals;  // per tile: its block weights' total (0: the fallback alone)
};

// `flux`: the flux build's mixtures (build_distributions_gpu with the flux builder); its fallback is
// every tile's. The stage "tiles (gpu)" goes to `timer`, the facts to det["tiles"] (as the CPU
// backend's: tiles, grid, points, block, blocks, and empty: the tiles whose blocks all weigh 0,
// which draw from the fallback alone). Throws vplkit::invalid_input when the tiles'
// CDFs would not fit the kernels' 32-bit word addressing.
gpu_tiles build_tiles_gpu(const frame_buffers& b, const render_settings& s, stage_timer& timer, nlohmann::json& det);

// Mixture record d for tile d: learned (VR_TILE_SLOT + d, Nb, guide size, total), the fallback of
// `flux_record` (a record of the flux build's mixture), and the split of eps on the two totals.
std::vector<gpu::mixture_record> tile_mixture_records(const gpu_tiles& t, const gpu::mixture_record& flux_record,
                                                      float eps);

}  // namespace vplrender
