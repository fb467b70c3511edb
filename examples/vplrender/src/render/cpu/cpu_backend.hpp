#pragma once
// The CPU backend: every method of vplrender on the read-back G-buffer, DPRSM and voxel grid,
// through vplkit's builders and estimators (C++ templates, T = float), parallel over image rows.
#include "app/options.hpp"
#include "io/image.hpp"
#include "raster/render_data.hpp"
#include "render/stage_timer.hpp"

#include <vplkit/distribution/defensive_mixture.hpp>
#include <vplkit/visibility/voxel_grid.hpp>

#include <nlohmann/json.hpp>

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace vplrender {

// Everything the estimators need besides the buffers (derived from options; docs/renderer.md).
struct estimator_settings {
  method meth = method::mis;
  int vpls = 64;              // VPL samples per gather point
  int dirs = 16;              // gathering directions (gbg NBDIR, gather, mis)
  int regions_x = 2, regions_y = 2;
  float eps = 0.05f;
  local_combination_choice local_combination = local_combination_choice::balance;
  gbg_accumulator_choice gbg_accumulator = gbg_accumulator_choice::gathering;
  cdf_search_choice cdf_search = cdf_search_choice::guide;
  float dmin = 0.0f;          // VPL distance clamp (world units)
  std::uint32_t seed = 1;
  int global_subset = 256;    // |S| of the global CDF
  int local_subset = 256;     // |S_i| per region of the local CDFs
  bool direct = false;
  int threads = 0;            // 0: std::thread::hardware_concurrency()
};

estimator_settings make_estimator_settings(const options& o, const scene& s);

// Seed of builder stage k (0: global subset, 1: local subsets, 2: GBG rays): a hash of --seed
// that differs from the per-pixel estimator streams (make_counter_rng(seed, pixel)).
std::uint32_t builder_seed(std::uint32_t seed, std::uint32_t stage);

// Progress callback: (label, done, total); called from the calling thread only.
using progress_fn = std::function<void(const std::string& label, std::uint64_t done, std::uint64_t total)>;

struct cpu_render_result {
  image_rgb image;              // row 0 = top
  nlohmann::json details;       // builder statistics etc. for the report
};

// Stages are appended to `timer` (clock cpu-wall). Throws vplkit::invalid_input for bad views.
cpu_render_result render_cpu(const gbuffer_data& g, const dprsm_data& d, const vplkit::voxel_grid_view<float>& grid,
                             const estimator_settings& es, stage_timer& timer, const progress_fn& progress = {});

// The builders and CDFs of es.meth on the CPU (shared by both backends): one defensive mixture for
// global, gbg, mis and mis-as-published, one per region for local (region-major), none for
// reference and gather. Stages go to `timer` (cpu-wall), builder facts to `det` (the report's
// pipeline.estimator object). local_rounds: max(1, vpls / regions) for local, else 0.
struct cpu_distributions {
  std::vector<vplkit::defensive_mixture<float>> dists;
  int local_rounds = 0;
};
cpu_distributions build_distributions_cpu(const gbuffer_data& g, const dprsm_data& d,
                                          const vplkit::voxel_grid_view<float>& grid, const estimator_settings& es,
                                          stage_timer& timer, const progress_fn& progress, nlohmann::json& det);

// Depth tolerance of the gathering look-ups (gather, mis; GBG rays): 2 voxel diagonals.
float gathering_depth_tolerance(const vplkit::voxel_grid_view<float>& grid);

// Threads the CPU stages use for es.threads (0: hardware concurrency).
int estimator_threads(int requested);

}  // namespace vplrender
