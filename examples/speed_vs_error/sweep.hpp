// SPDX-License-Identifier: MIT
// The sweep itself: the frame prepared once (G-buffer, DPRSM, voxels, the junction band), the
// references, then every (method, clamp compensation, samples, seed) run on it, timed and compared
// with the references.
#pragma once

#include "reference_cache.hpp"
#include "run_rows.hpp"
#include "sve_options.hpp"

#include "metrics.hpp"

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace speed_vs_error {

// The junction band's width in voxels of the frame's grid (junction_band.hpp).
constexpr float k_band_voxels = 2.0f;

struct sweep_frame {
  vplrender::frame_buffers buffers;
  double prepare_ms = 0.0;          // G-buffer + DPRSM + voxels (not in the runs' totals)
  std::vector<std::uint8_t> band;   // the junction band's mask; empty without exact rays
};

struct sweep_references {
  reference_image vplsum, gather, exact;  // an empty image: skipped (--references)
  // --ref-noise: the second renders of gather and exact, and the noise they measure (metrics.hpp).
  reference_image gather2, exact2;
  std::optional<reference_noise> gather_noise, exact_noise;
};

struct sweep_result {
  std::vector<run_row> rows;
  std::vector<bias_variance_row> bias_variance;  // with 2 or more seeds
  std::vector<std::string> labels;               // the series, in the order they first ran
};

// Prepares the frame every run reuses (with exact rays when a reference or method needs them) and
// prints its line.
sweep_frame prepare_sweep_frame(const sweep_options& so, const vplrender::prepared_scene& p);

// The references --references asks for, from the cache or computed.
sweep_references get_references(const sweep_options& so, const vplrender::prepared_scene& p, const sweep_frame& f);

// Every run of the sweep, printing one line per run.
sweep_result run_sweep(const sweep_options& so, const vplrender::prepared_scene& p, const sweep_frame& f,
                       const sweep_references& refs);

}  // namespace speed_vs_error
