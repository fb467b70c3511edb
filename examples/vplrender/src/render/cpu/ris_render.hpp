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
// (docs/math.md, "RIS with gathering"); unclamped, so without compensation; with --spatial K > 0
// in rounds of the same two passes (vplkit::ris_mis_spatial_reuse, render_ris_mis_cpu's comment).
#include "render/cpu/cpu_frame.hpp"
#include "render/cpu/parallel.hpp"
#include "render/ris_spatial.hpp"
#include "render/settings.hpp"
#include "render/stage_timer.hpp"

#include <vplkit/builders/local_weights.hpp>
#include <vplkit/estimators/ris_candidate_pool.hpp>
#include <vplkit/estimators/ris_estimator.hpp>
#include <vplkit/estimators/ris_mis_estimator.hpp>
#include <vplkit/estimators/ris_mis_spatial_reuse.hpp>
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

// Does each image region (local) or tile (tiles) draw from a distribution of its own?
inline bool ris_source_per_region(const render_settings& s) {
  return s.ris_source == ris_source_choice::local || s.ris_source == ris_source_choice::tiles;
}

// The candidate source's distribution of pixel p: the pixel's region's for --candidate-source
// local (one distribution per region of s.regions_x x s.regions_y) and its tile's for tiles (of
// s.tiles_x x s.tiles_y), else dists[0].
template <class Dist>
struct ris_candidate_source {
  const Dist* dists;
  bool per_region;
  int width;
  vplkit::image_regions regions;
  ris_candidate_source(const Dist* d, int n_dists, const render_settings& s, int W, int H)
      : dists(d), per_region(ris_source_per_region(s) && n_dists > 1), width(W),
        regions(W, H, s.ris_source == ris_source_choice::tiles ? s.tiles_x : s.regions_x,
                s.ris_source == ris_source_choice::tiles ? s.tiles_y : s.regions_y) {}
  int index(int p) const { return per_region ? regions.region_of_pixel(p % width, p / width) : 0; }
  const Dist& operator()(int p) const { return dists[index(p)]; }
};

// --candidate-pool P > 0: P presampled candidates per candidate distribution (vplkit
// ris_candidate_pool.hpp), distribution d's in entries [d P, (d + 1) P), entry i drawn from the
// stream (ris_pool_seed(seed), i), filled once per frame before the estimate. The GPU backend fills
// the same entries.
struct ris_candidate_pool {
  std::vector<vplkit::ris_pool_entry<float>> entries;
  std::uint32_t size = 0;  // per distribution
  const vplkit::ris_pool_entry<float>* of(int d) const { return entries.data() + std::size_t(d) * size; }
};

template <class Dist>
ris_candidate_pool fill_ris_candidate_pool(const cpu_frame& f, const render_settings& s, const Dist* dists,
                                           int n_dists, float depth_tol, vplkit::vpl_mode vmode) {
  ris_candidate_pool pool;
  pool.size = static_cast<std::uint32_t>(std::max(0, s.ris_pool));
  const int n = ris_source_per_region(s) ? n_dists : 1;
  const std::size_t total = std::size_t(pool.size) * std::size_t(n);
  pool.entries.resize(total);
  const std::uint32_t seed = ris_pool_seed(s.seed);
  constexpr std::size_t chunk = 4096;
  parallel_items(static_cast<int>((total + chunk - 1) / chunk), f.threads, "", {}, [&](int c, int) {
    const std::size_t end = std::min(total, (std::size_t(c) + 1) * chunk);
    for (std::size_t i = std::size_t(c) * chunk; i < end; ++i)
      pool.entries[i] = vplkit::ris_pool_draw_entry(f.view, dists[i / pool.size], seed, static_cast<std::uint32_t>(i),
                                                     vmode, depth_tol);
  });
  return pool;
}

// What the rounds of spatial reuse keep per pixel: its random stream (it runs on from round to
// round), its reservoir record (rewritten by every candidate pass) and its running sum.
struct ris_reuse_rounds {
  std::vector<vplkit::counter_rng> rng;
  std::vector<vplkit::gpu::ris_reservoir_record> records;
  std::vector<vplkit::vec3<float>> sum;
  ris_reuse_rounds(int n_pixels, std::uint32_t seed)
      : rng(static_cast<std::size_t>(n_pixels)),
        records(static_cast<std::size_t>(n_pixels),
                vplkit::gpu::make_ris_reservoir_record(vplkit::ris_reservoir<float>{})),
        sum(static_cast<std::size_t>(n_pixels), vplkit::vec3<float>(0.0f)) {
    for (int p = 0; p < n_pixels; ++p) rng[std::size_t(p)] = vplkit::make_counter_rng(seed, static_cast<std::uint32_t>(p));
  }
  // What pixel q offers its neighbours: its gather point and this round's reservoir.
  vplkit::ris_neighbour<float> neighbour(const vplkit::gbuffer_view<float>& g, int q) const {
    return vplkit::ris_neighbour<float>{g.at(q), vplkit::gpu::ris_reservoir_from_record(records[std::size_t(q)])};
  }
};

// Renders --method ris-mis into `image` (as render_ris_cpu, without compensation: its estimand is
// the unclamped integral). `tracer` traces its gathering directions (render_cpu's, with the run's
// --lit-test). Without reuse, per pixel vplkit::estimate_ris_mis. With --spatial K > 0 the steps
// j < max(--dirs, --vpls) of estimate_ris_mis become rounds over the image: a candidate pass (if
// j < N = --vpls: each pixel's reservoir of its own M candidates from its own distribution,
// ris_mis_resample, into a ris_params.h record), then a reuse pass (if j < N: the pixel's
// reservoir combined with K neighbours', vplkit::ris_mis_spatial_reuse, pairwise MIS, the target
// with each pixel's own pmf, and shaded with the receiver's distribution, h V W / N; then, if
// j < n1, one gathering direction weighed against n2 as in estimate_ris_mis). The weights' n2 is
// estimate_ris_mis's, vplkit::ris_mis_vpl_samples(N, M).
// Random numbers, per pixel one stream (seed, pixel), per round in this order: the M candidates
// (ris_mis_resample's layout), the reuse's 1 + 3K (ris_spatial_reuse.hpp), the direction's u0, u1;
// each part only in the rounds where it runs. The GPU backend follows the same layout.
template <class Dist, class Tracer, class Visibility>
void render_ris_mis_cpu(const cpu_frame& f, const render_settings& s, const Dist* dists, int n_dists,
                        const Tracer& tracer, const Visibility& visibility, float depth_tol, vplkit::vpl_mode vmode,
                        float* image, stage_timer& timer, const progress_fn& progress, nlohmann::json& det) {
  const vplkit::gbuffer_view<float>& g = f.g;
  const vplkit::dprsm_view<float>& view = f.view;
  const int W = f.W, H = f.H;
  const ris_candidate_source<Dist> dist_of(dists, n_dists, s, W, H);
  const vplkit::ris_spatial_settings<float> spatial = ris_spatial_settings_for(W, H, s.ris_spatial);
  det["ris"] = {{"candidates", s.ris_candidates}, {"candidate_source", to_string(s.ris_source)},
                {"spatial", s.ris_spatial}, {"dirs", s.dirs}, {"mis", "balance"}};
  if (s.ris_spatial > 0)
    det["ris"].update({{"radius", spatial.radius}, {"min_normal_cos", spatial.min_normal_cos},
                       {"max_plane_slope", spatial.max_plane_slope}, {"reuse_mis", "pairwise"}});
  const auto finish = [&](int p, vplkit::vec3<float> c) {
    const vplkit::gather_point<float> gp = g.at(p);
    if (vplkit::gather_point_valid(gp)) {
      if (s.direct) c += vplkit::direct_light(gp, view);
      c = vplkit::estimator_finite_or_zero(glm::max(c, vplkit::vec3<float>(0.0f)));
    } else {
      c = vplkit::vec3<float>(0.0f);
    }
    for (int k = 0; k < 3; ++k) image[3 * std::size_t(p) + std::size_t(k)] = c[k];
  };
  auto t = timer.scoped("estimate (cpu)");
  // Filled inside the estimate's time: it is part of every frame's cost.
  const ris_candidate_pool pool = fill_ris_candidate_pool(f, s, dists, n_dists, depth_tol, vmode);
  if (pool.size > 0) det["ris"]["pool"] = pool.size;
  if (s.ris_spatial <= 0) {
    parallel_items(H, f.threads, "render", progress, [&](int y, int) {
      for (int p = y * W; p < (y + 1) * W; ++p) {
        const vplkit::gather_point<float> gp = g.at(p);
        vplkit::vec3<float> c(0.0f);
        if (vplkit::gather_point_valid(gp)) {
          vplkit::counter_rng rng = vplkit::make_counter_rng(s.seed, static_cast<std::uint32_t>(p));
          if (pool.size > 0)
            c = vplkit::estimate_ris_mis_pooled(gp, view, dist_of(p), pool.of(dist_of.index(p)), pool.size, rng,
                                                s.dirs, s.vpls, s.ris_candidates, tracer, visibility, depth_tol,
                                                vmode);
          else
            c = vplkit::estimate_ris_mis(gp, view, dist_of(p), rng, s.dirs, s.vpls, s.ris_candidates, tracer,
                                         visibility, depth_tol, vmode);
        }
        finish(p, c);
      }
    });
    return;
  }
  const int M = s.ris_candidates;
  const int n_dirs = std::max(0, s.dirs), n_ris = M > 0 ? std::max(0, s.vpls) : 0;
  const float n1 = float(n_dirs), n2 = vplkit::ris_mis_vpl_samples<float>(n_ris, M);
  const int rounds = std::max(n_dirs, n_ris);
  const int n_pixels = W * H;
  ris_reuse_rounds state(n_pixels, s.seed);
  std::vector<vplkit::counter_rng>& rng = state.rng;
  std::vector<vplkit::gpu::ris_reservoir_record>& records = state.records;
  std::vector<vplkit::vec3<float>>& sum = state.sum;
  const auto load = [&](int q) { return state.neighbour(g, q); };
  for (int round = 0; round < rounds; ++round) {
    if (progress) progress("render", static_cast<std::uint64_t>(round), static_cast<std::uint64_t>(rounds));
    const bool ris_round = round < n_ris, dir_round = round < n_dirs;
    if (ris_round)
      parallel_items(H, f.threads, "", {}, [&](int y, int) {
        for (int p = y * W; p < (y + 1) * W; ++p) {
          const vplkit::gather_point<float> gp = g.at(p);
          if (!vplkit::gather_point_valid(gp)) continue;
          vplkit::ris_mis_kept<float> kept;
          records[std::size_t(p)] = vplkit::gpu::make_ris_reservoir_record(
              pool.size > 0 ? vplkit::ris_mis_resample_pooled(gp, pool.of(dist_of.index(p)), pool.size,
                                                              rng[std::size_t(p)], M, n1, n2, kept)
                            : vplkit::ris_mis_resample(gp, view, dist_of(p), rng[std::size_t(p)], M, n1, n2, vmode,
                                                       depth_tol));
        }
      });
    parallel_items(H, f.threads, "", {}, [&](int y, int) {
      for (int p = y * W; p < (y + 1) * W; ++p) {
        const vplkit::gather_point<float> gp = g.at(p);
        if (!vplkit::gather_point_valid(gp)) continue;
        vplkit::counter_rng& r = rng[std::size_t(p)];
        if (ris_round) {
          const vplkit::ris_reservoir<float> reused = vplkit::ris_mis_spatial_reuse(
              gp, p, W, H, view, vplkit::gpu::ris_reservoir_from_record(records[std::size_t(p)]), load, spatial, r,
              dist_of, n1, n2, vmode, depth_tol);
          sum[std::size_t(p)] += vplkit::ris_mis_shade(gp, view, dist_of(p), reused, visibility, n1, n2, vmode,
                                                       depth_tol) / float(n_ris);
        }
        if (dir_round) {
          const float u0 = vplkit::rng_next_unit<float>(r);
          const float u1 = vplkit::rng_next_unit<float>(r);
          const vplkit::orthonormal_basis<float> frame =
              vplkit::make_orthonormal_basis(vplkit::gather_point_shading_normal(gp));
          sum[std::size_t(p)] += vplkit::mis_gathering_sample(
              gp, view, dist_of(p), frame, vplkit::sample_cosine_hemisphere(vplkit::vec2<float>(u0, u1)), tracer,
              depth_tol, n1, n2, vplkit::mis_mode::solid_angle, vmode);
        }
      }
    });
  }
  if (progress) progress("render", static_cast<std::uint64_t>(rounds), static_cast<std::uint64_t>(rounds));
  parallel_items(H, f.threads, "", {}, [&](int y, int) {
    for (int p = y * W; p < (y + 1) * W; ++p) finish(p, sum[std::size_t(p)]);
  });
}

// Renders --method ris into `image` (pixels row-major, background left 0): `dists` the candidate
// source's distributions (one, or one per region of s.regions_x x s.regions_y for local);
// `compensation(gp, p)` what the clamp removed at pixel p (vec3 0 when off; docs/math.md, "The
// clamp's compensation"): RIS's target and shading use the clamped contribution, so its estimand is
// the clamped VPL sum as for the other VPL methods.
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
  ris_reuse_rounds state(n_pixels, s.seed);
  std::vector<vplkit::counter_rng>& rng = state.rng;
  std::vector<vplkit::gpu::ris_reservoir_record>& records = state.records;
  std::vector<vplkit::vec3<float>>& sum = state.sum;
  const auto load = [&](int q) { return state.neighbour(g, q); };
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
