// SPDX-License-Identifier: MIT
#pragma once
// The CPU backend's builders and CDFs (vplkit's builders, T = float, parallel over rows or texel
// blocks): the distributions the estimators of render_cpu sample. The GPU backend's counterpart is
// render/gpu/gpu_builders.hpp.
#include "render/frame_buffers.hpp"
#include "render/settings.hpp"
#include "render/stage_timer.hpp"

#include <vplkit/distribution/defensive_mixture.hpp>

#include <nlohmann/json.hpp>

#include <vector>

namespace vplrender {

// One defensive mixture for global, gbg, mis and mis-as-published, one per region for local
// (region-major), none for reference and gather; for ris those of its --candidate-source (flux: the
// flux CDF, with --eps). local_rounds: max(1, vpls / regions) for local,
// else 0.
struct cpu_distributions {
  std::vector<vplkit::defensive_mixture<float>> dists;
  std::vector<float> weights;  // the builders' weights behind `dists` (region-major, 2 R^2 each)
  int local_rounds = 0;
};

// The GBG weights (gbg, mis, mis-as-published): vplkit's GBG builder over the image rows, each
// worker accumulating into its own gbg_partial (gbg_accumulate_pixels), merged in worker order
// (gbg_merge), normalised, counted and hole-filled (gbg_finish, gbg_count_and_fill). Stages "gbg
// weights (cpu)" and "gbg hole fill (cpu)", facts under det["gbg"]. The GPU backend's counterpart
// is build_gbg_weights_gpu.
std::vector<float> build_gbg_weights_cpu(const frame_buffers& b, const render_settings& s, stage_timer& timer,
                                         const progress_fn& progress, nlohmann::json& det);

// Stages go to `timer` (cpu-wall), builder facts to `det` (the report's pipeline.estimator
// object: global_subset; local_subsets, local_rounds, local_combination; gbg). Throws
// vplkit::invalid_input for bad views.
cpu_distributions build_distributions_cpu(const frame_buffers& b, const render_settings& s, stage_timer& timer,
                                          const progress_fn& progress, nlohmann::json& det);

}  // namespace vplrender
