// SPDX-License-Identifier: MIT
#pragma once
// --method ris and ris-mis on the CPU backend (docs/math.md section 13, docs/renderer.md). ris: per pixel --vpls
// samples, each from its own reservoir of --candidates candidates drawn from the candidate source
// (one distribution, or with --candidate-source local the pixel's region's), one visibility query
// each. With --spatial K > 0 every sample is a round of two passes over the image: the candidate
// pass stores each pixel's reservoir in a ris_params.h record, the reuse pass combines it with K
// neighbours' (vplkit::ris_spatial_reuse, pairwise MIS: unbiased) and shades the result. One
// record per pixel whatever the sample count: the rounds reuse it. ris-mis: per pixel
// vplkit::estimate_ris_mis, --vpls RIS samples balanced against --dirs gathering directions
// (docs/math.md, "RIS with gathering"); unclamped, so without compensation, and without reuse.
#include "render/cpu/cpu_frame.hpp"
#include "render/cpu/parallel.hpp"
#include "render/ris_spatial.hpp"
#include "render/settings.hpp"
#include "render/stage_timer.hpp"

#include <vplkit/builders/local_weights.hpp>
#include <vplkit/estimators/ris_estimator.hpp>
#include <vplkit/estimators/ris_mis_estimator.hpp>
#include <vplkit/estimators/ris_params.h>
#include <vplkit/estimators/ris_spatial_reuse.hpp>
#include <vplkit/estimators/vpl_sum.hpp>
#include <vplkit/sampling/rng.hpp>
#include <vplkit/vpl/direct_light.hpp>

#include <glm/common.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <string>
#include <cstdint>
#include <vector>

namespace vplrender {

// Renders --method ris into `image` (pixels row-major, background left 0): `dists` the candidate
// source's distributions (one, or one per region of s.regions_x x s.regions_y for local);
// `compensation(gp, p)` what the clamp removed at pixel p (vec3 0 when off; docs/math.md, "The
// clamp's compensation"): RIS's target and shading use the clamped contribution, so its estimand is
// the clamped VPL sum as for the other VPL methods.
// The candidate source's distribution of pixel p: the pixel's region's for --candidate-source
// local (one distribution per region of s.regions_x x s.regions_y), else dists[0].
template <class Dist>
struct ris_candidate_source {
  const Dist* dists;
  bool per_region;
  int width;
  vplkit::image_regions regions;
  ris_candidate_source(const Dist* d, int n_dists, const render_settings& s, int W, int H)
      : dists(d), per_region(s.ris_source == ris_source_choice::local && n_dists > 1), width(W),
        regions(W, H, s.regions_x, s.regions_y) {}
  const Dist& operator()(int p) const {
    return per_region ? dists[regions.region_of_pixel(p % width, p / width)] : dists[0];
  }
};

// Renders --method ris-mis into `image` (as render_ris_cpu, without compensation or reuse: its
// estimand is the unclamped integral, and spatial reuse of its MIS-weighted target is not built).
// `tracer` traces its gathering directions (render_cpu's, with the run's --lit-test).
template <class Dist, class Tracer, class Visibility>
void render_ris_mis_cpu(const cpu_frame& f, const render_settings& s, const Dist* dists, int n_dists,
                        const Tracer& tracer, const Visibility& visibility, float depth_tol, vplkit::vpl_mode vmode,
                        float* image, stage_timer& timer, const progress_fn& progress, nlohmann::json& det) {
  if (s.ris_spatial > 0)
    throw vplkit::invalid_input("--method ris-mis: --spatial " + std::to_string(s.ris_spatial) +
                                " is not supported (spatial reuse is built for --method ris only; use --spatial 0)");
  const vplkit::gbuffer_view<float>& g = f.g;
  const vplkit::dprsm_view<float>& view = f.view;
  const int W = f.W, H = f.H;
  const ris_candidate_source<Dist> dist_of(dists, n_dists, s, W, H);
  det["ris"] = {{"candidates", s.ris_candidates}, {"candidate_source", to_string(s.ris_source)},
                {"spatial", 0}, {"dirs", s.dirs}, {"mis", "balance"}};
  auto t = timer.scoped("estimate (cpu)");
  parallel_items(H, f.threads, "render", progress, [&](int y, int) {
    for (int p = y * W; p < (y + 1) * W; ++p) {
      const vplkit::gather_point<float> gp = g.at(p);
      vplkit::vec3<float> c(0.0f);
      if (vplkit::gather_point_valid(gp)) {
        vplkit::counter_rng rng = vplkit::make_counter_rng(s.seed, static_cast<std::uint32_t>(p));
        c = vplkit::estimate_ris_mis(gp, view, dist_of(p), rng, s.dirs, s.vpls, s.ris_candidates, tracer, visibility,
                                     depth_tol, vmode);
        if (s.direct) c += vplkit::direct_light(gp, view);
        c = vplkit::estimator_finite_or_zero(glm::max(c, vplkit::vec3<float>(0.0f)));
      }
      for (int k = 0; k < 3; ++k) image[3 * std::size_t(p) + std::size_t(k)] = c[k];
    }
  });
}

template <class Dist, class Visibility, class Compensation>
void render_ris_cpu(const cpu_frame& f, const render_settings& s, const Dist* dists, int n_dists,
                    const Visibility& visibility, float depth_tol, vplkit::vpl_mode vmode,
                    const Compensation& compensation, float* image,
                    stage_timer& timer, const progress_fn& progress, nlohmann::json& det) {
  const vplkit::gbuffer_view<float>& g = f.g;
  const vplkit::dprsm_view<float>& view = f.view;
  const int W = f.W, H = f.H, M = s.ris_candidates, N = s.vpls;
  const ris_candidate_source<Dist> dist_of(dists, n_dists, s, W, H);
  const vplkit::ris_spatial_settings<float> spatial = ris_spatial_settings_for(W, H, s.ris_spatial);
  det["ris"] = {{"candidates", M}, {"candidate_source", to_string(s.ris_source)}, {"spatial", s.ris_spatial}};
  if (s.ris_spatial > 0)
    det["ris"].update({{"radius", spatial.radius}, {"min_normal_cos", spatial.min_normal_cos},
                       {"max_plane_slope", spatial.max_plane_slope}, {"mis", "pairwise"}});
  // The pixel's value as every method finishes it (render_cpu's render_pixels).
  const auto finish = [&](int p, vplkit::vec3<float> c) {
    const vplkit::gather_point<float> gp = g.at(p);
    c += compensation(gp, p);
    if (s.direct) c += vplkit::direct_light(gp, view);
    c = vplkit::estimator_finite_or_zero(glm::max(c, vplkit::vec3<float>(0.0f)));
    for (int k = 0; k < 3; ++k) image[3 * std::size_t(p) + std::size_t(k)] = c[k];
  };
  auto t = timer.scoped("estimate (cpu)");
  if (s.ris_spatial <= 0) {
    parallel_items(H, f.threads, "render", progress, [&](int y, int) {
      for (int p = y * W; p < (y + 1) * W; ++p) {
        const vplkit::gather_point<float> gp = g.at(p);
        if (!vplkit::gather_point_valid(gp)) continue;
        vplkit::counter_rng rng = vplkit::make_counter_rng(s.seed, static_cast<std::uint32_t>(p));
        finish(p, vplkit::estimate_ris(gp, view, dist_of(p), rng, N, M, visibility, s.dmin, vmode, depth_tol));
      }
    });
    return;
  }
  const int n_pixels = W * H;
  std::vector<vplkit::counter_rng> rng(static_cast<std::size_t>(n_pixels));
  for (int p = 0; p < n_pixels; ++p) rng[std::size_t(p)] = vplkit::make_counter_rng(s.seed, static_cast<std::uint32_t>(p));
  std::vector<vplkit::gpu::ris_reservoir_record> records(
      static_cast<std::size_t>(n_pixels), vplkit::gpu::make_ris_reservoir_record(vplkit::ris_reservoir<float>{}));
  std::vector<vplkit::vec3<float>> sum(static_cast<std::size_t>(n_pixels), vplkit::vec3<float>(0.0f));
  const auto load = [&](int q) {
    return vplkit::ris_neighbour<float>{g.at(q), vplkit::gpu::ris_reservoir_from_record(records[std::size_t(q)])};
  };
  for (int round = 0; round < N; ++round) {
    if (progress) progress("render", static_cast<std::uint64_t>(round), static_cast<std::uint64_t>(N));
    // Candidates: each pixel's reservoir of its own M candidates.
    parallel_items(H, f.threads, "", {}, [&](int y, int) {
      for (int p = y * W; p < (y + 1) * W; ++p) {
        const vplkit::gather_point<float> gp = g.at(p);
        if (!vplkit::gather_point_valid(gp)) continue;
        records[std::size_t(p)] = vplkit::gpu::make_ris_reservoir_record(
            vplkit::ris_resample(gp, view, dist_of(p), rng[std::size_t(p)], M, s.dmin, vmode, depth_tol));
      }
    });
    // Reuse: each pixel combines its reservoir with its neighbours' and shades the result.
    parallel_items(H, f.threads, "", {}, [&](int y, int) {
      for (int p = y * W; p < (y + 1) * W; ++p) {
        const vplkit::gather_point<float> gp = g.at(p);
        if (!vplkit::gather_point_valid(gp)) continue;
        const vplkit::ris_reservoir<float> r = vplkit::ris_spatial_reuse(
            gp, p, W, H, view, vplkit::gpu::ris_reservoir_from_record(records[std::size_t(p)]), load, spatial,
            rng[std::size_t(p)], s.dmin, vmode, depth_tol);
        sum[std::size_t(p)] += vplkit::ris_shade(gp, view, r, visibility, s.dmin, vmode, depth_tol);
      }
    });
  }
  if (progress) progress("render", static_cast<std::uint64_t>(N), static_cast<std::uint64_t>(N));
  parallel_items(H, f.threads, "", {}, [&](int y, int) {
    for (int p = y * W; p < (y + 1) * W; ++p)
      if (vplkit::gather_point_valid(g.at(p))) finish(p, sum[std::size_t(p)] / float(N));
  });
}

}  // namespace vplrender
