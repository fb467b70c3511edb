// SPDX-License-Identifier: MIT
// Interface of vplrender's RIS kernels (estimate_ris.comp, estimate_ris_mis.comp beside this file):
// the reservoir buffer's binding, the pass define and the RIS parameters, in the two-language form
// of the pack's <kernel>_params.h (vplkit/core/params.h). The parameters are not a block of their
// own: estimate_params.h nests them as the estimate block's member `ris` (vr_params.ris), so every
// estimate kernel reads exactly one uniform block. On the NVIDIA H200 (driver 580.159.04) a second
// block, VrRisParams at binding 25, read as zeros in estimate_ris_mis.comp (--candidates read 0:
// ris-mis rendered gathering's image) while llvmpipe read it right; the estimate block at binding
// 17 is read right by every kernel on both. tests/renderer/renderer_gpu_ris_params_test.cpp and
// renderer_gpu_ris_mis_params_test.cpp ask the GL driver where every member lies.
//
// Passes (VR_RIS_PASS, a specialisation define; docs/renderer.md, "The estimate kernels"):
//   VR_RIS_PASS_ESTIMATE 0: no spatial reuse; per pixel --vpls samples [begin, end), each a
//     reservoir of M candidates and one visibility query (vplkit_estimate_ris_range). Splits over
//     dispatches like the other estimators (VR_SPLIT). No reservoir buffer.
//   VR_RIS_PASS_CANDIDATES 1: one round's reservoir of M candidates per pixel, written to the
//     reservoir buffer (the only thing a neighbour needs from this pass).
//   VR_RIS_PASS_REUSE 2: the round's reuse: each pixel combines its reservoir with K neighbours'
//     (vplkit_ris_spatial_reuse, pairwise MIS), shades the result with one visibility query and
//     adds it to its sum. Reads the G-buffer and the reservoirs only: no candidate is redrawn.
//   With reuse, each of the --vpls rounds is a candidate dispatch and a reuse dispatch; the
//   pixel's sum and random stream live in the state buffer (VR_SPLIT 1) between them, in the order
//   of render/cpu/ris_render.hpp, so the two backends draw the same numbers.
//   estimate_ris_mis.comp (--method ris-mis) has the same three passes: without reuse (the pass
//   define left out) its steps; with reuse max(--dirs, n2) rounds, the round in begin, the reuse
//   pass also tracing the step's gathering direction (vplkit_ris_mis_spatial_reuse).
//   VR_RIS_PASS_POOL 3 (estimate_ris_mis.comp with VR_RIS_POOL): one invocation per entry of the
//     presampled candidate pool (--candidate-pool; vplkit_ris_pool_draw_entry), once per frame
//     before the passes above, which then (VR_RIS_POOL defined) draw their candidates from it.
#ifndef VPLRENDER_ESTIMATE_RIS_PARAMS_H
#define VPLRENDER_ESTIMATE_RIS_PARAMS_H

#include "vplkit/core/params.h"

// A number above estimate_params.h's (0..19), each resource its own (core/params.h).
#define VR_RIS_BINDING_RESERVOIRS 24  // SSBO: vplkit_ris_reservoir_record reservoirs[W H] (ris_params.h)
#define VR_RIS_BINDING_POOL 26        // SSBO: vplkit_ris_pool_record pool[pools * pool_size] (ris_pool_params.h)
#define VR_RIS_BINDING_TILES 27       // SSBO: uint tiles[] (VR_RIS_TILES: the tiles' block CDFs, guides, shares)

#define VR_RIS_PASS_ESTIMATE 0
#define VR_RIS_PASS_CANDIDATES 1
#define VR_RIS_PASS_REUSE 2
#define VR_RIS_PASS_POOL 3
// VR_RIS_PER_REGION (defined or not): --candidate-source local or tiles, each pixel draws from its
//   region's (tile's) mixture; else every pixel from mixture 0, which then lives in registers
//   (VR_ONE_MIXTURE).
// VR_RIS_TILES (defined or not; with VR_RIS_PER_REGION): --candidate-source tiles, the mixtures'
//   learned parts are the tiles' block CDFs (estimate_tiles.glsl).
#ifndef __cplusplus
#ifndef VR_RIS_PASS
#define VR_RIS_PASS VR_RIS_PASS_ESTIMATE
#endif
#endif

#ifdef __cplusplus
namespace vplrender::gpu {
using vplkit::gpu::uint;
struct ris_params {
#else
struct vr_ris_params {
#endif
  int candidates;         // M per reservoir (--candidates)
  int neighbours;         // K reuse attempts (--spatial)
  int radius;             // the reuse square's half side in pixels (ris_spatial_settings_for)
  int mis;                // vplkit_ris_reuse_pairwise (0) or _balance (1)
  int regions_x;          // VR_RIS_PER_REGION: the image regions of --candidate-source local
  int regions_y;          //   (vplkit_image_regions; region r samples mixture r)
  uint pool_size;         // VR_RIS_POOL: entries per candidate distribution (--candidate-pool)
  uint pool_seed;         //   the pool's stream seed (ris_pool_seed): entry i takes (pool_seed, i)
  float min_normal_cos;   // the reuse's rejection thresholds (ris_spatial_settings)
  float max_plane_slope;
  int tile_block;         // VR_RIS_TILES: B, texels per block side (--tile-block)
  uint tile_guide_base;   //   the tile buffer's guides start here (uints; estimate_tiles.glsl)
  uint tile_share_base;   //   ... and its per-texel shares here
  uint pad1;
  uint pad2;
  uint pad3;
};

#ifdef __cplusplus
static_assert(sizeof(ris_params) == 64);  // 16 scalars: four std140 rows (a struct member of a std140
                                          // block starts on a 16-byte boundary: 64 keeps it whole)
}  // namespace vplrender::gpu
#endif

#endif  // VPLRENDER_ESTIMATE_RIS_PARAMS_H
