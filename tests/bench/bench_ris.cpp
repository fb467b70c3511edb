// SPDX-License-Identifier: MIT
// The resampled estimator (estimators/ris_estimator.hpp) and its spatial reuse
// (estimators/ris_spatial_reuse.hpp) per gather point on the synthetic room, T = float, next to
// what they replace: a VPL sample with its visibility query. Gather points: the 4096 of the
// 64 x 64 G-buffer, 64 per iteration, cycled; DPRSM 2 x 64 x 64; visibility: the two-sided voxel
// test at 64^3; dmin 0.1; candidates from the defensive mixture (eps 0.1) of the global weights of
// 256 gather points (as bench_estimators.cpp).
// Items: candidates for the candidate pass (M = 32 per reservoir; point and patch VPLs); samples
// for estimate_ris (16 samples of M = 8 or 32 candidates each); pixels for the reuse (K = 4 or 8,
// the neighbours' reservoirs precomputed, pairwise or balance MIS), whose cost is target
// evaluations only; VPL samples for the reference row (a draw, a contribution and a query).
#include "bench_common.hpp"

#include <vplkit/builders/gather_subset.hpp>
#include <vplkit/builders/global_weights.hpp>
#include <vplkit/builders/vpl_distribution.hpp>
#include <vplkit/estimators/mis_estimator.hpp>
#include <vplkit/estimators/ris_candidate_pool.hpp>
#include <vplkit/estimators/ris_estimator.hpp>
#include <vplkit/estimators/ris_mis_estimator.hpp>
#include <vplkit/estimators/ris_spatial_reuse.hpp>
#include <vplkit/estimators/vpl_sampling_estimator.hpp>
#include <vplkit/visibility/visibility_callables.hpp>

namespace {

using namespace vplkit_bench;

constexpr int kImage = 64;
constexpr int kPointsPerIteration = 64;
constexpr float kDmin = 0.1f;

const std::vector<vplkit::gather_point<float>>& points() {
  static const auto* p = new std::vector<vplkit::gather_point<float>>(room_gather_points(kImage));
  return *p;
}

vplkit::voxel_visibility<float> visibility() { return vplkit::voxel_visibility<float>{room_grid(64).view()}; }

const vplkit::defensive_mixture<float>& mixture() {
  static const auto* d = [] {
    const auto gb = room_gbuffer(kImage).view();
    const auto view = room_dprsm(64).view();
    const auto subset = vplkit::stratified_gather_subset(gb, vplkit::full_image_rect(gb), 256, 7u);
    return new vplkit::defensive_mixture<float>(
        vplkit::make_vpl_distribution(vplkit::build_global_weights(gb, subset, view, kDmin), view, 0.1f));
  }();
  return *d;
}

template <class Estimate>
void run_points(benchmark::State& state, std::int64_t items_per_point, Estimate&& estimate) {
  run_gather_points(state, points(), kPointsPerIteration, items_per_point, estimate);
}

// The candidate pass alone: one reservoir of 32 candidates (no visibility).
void BM_ris_candidates(benchmark::State& state) {
  const auto view = room_dprsm(64).view();
  const auto mode = state.range(0) != 0 ? vplkit::vpl_mode::patch : vplkit::vpl_mode::point;
  const float tol = std::numeric_limits<float>::infinity();
  run_points(state, 32, [&](const vplkit::gather_point<float>& gp, vplkit::counter_rng& rng) {
    const auto r = vplkit::ris_resample(gp, view, mixture(), rng, 32, kDmin, mode, tol);
    return vplkit::vec3<float>(r.weight_sum);
  });
}

// ris-mis's candidate pass from a pool (ris_candidate_pool.hpp): one reservoir of 32 candidates
// drawn from 16384 presampled patch points (the renderer's --candidate-pool default), weighed
// with n1 = 8, n2 = 8 max(1, 32/2) (no visibility). Items: candidates.
void BM_ris_mis_pooled_candidates(benchmark::State& state) {
  const auto view = room_dprsm(64).view();
  const float tol = std::numeric_limits<float>::infinity();
  static const auto* pool = [&] {
    auto* p = new std::vector<vplkit::ris_pool_entry<float>>(16384);
    for (std::uint32_t i = 0; i < p->size(); ++i)
      (*p)[i] = vplkit::ris_pool_draw_entry(view, mixture(), 3u, i, vplkit::vpl_mode::patch, tol);
    return p;
  }();
  const float n1 = 8.0f, n2 = vplkit::ris_mis_vpl_samples<float>(8, 32);
  run_points(state, 32, [&](const vplkit::gather_point<float>& gp, vplkit::counter_rng& rng) {
    vplkit::ris_mis_kept<float> kept;
    const auto r = vplkit::ris_mis_resample_pooled(gp, pool->data(), std::uint32_t(pool->size()), rng, 32, n1, n2,
                                                   kept);
    return vplkit::vec3<float>(r.weight_sum) + kept.h;
  });
}

// 16 samples, each a reservoir of M candidates and one query.
void BM_ris_estimate(benchmark::State& state) {
  const auto view = room_dprsm(64).view();
  const auto vis = visibility();
  const int m = int(state.range(0));
  run_points(state, 16, [&](const vplkit::gather_point<float>& gp, vplkit::counter_rng& rng) {
    return vplkit::estimate_ris(gp, view, mixture(), rng, 16, m, vis, kDmin);
  });
}

// What a candidate is measured against: a VPL sample with its query (16 per gather point).
void BM_vpl_sample_with_query(benchmark::State& state) {
  const auto view = room_dprsm(64).view();
  const auto vis = visibility();
  run_points(state, 16, [&](const vplkit::gather_point<float>& gp, vplkit::counter_rng& rng) {
    return vplkit::estimate_vpl_sampling(gp, view, mixture(), rng, 16, vis, kDmin);
  });
}

// The reuse pass per pixel: K neighbours of the 64 x 64 G-buffer, their reservoirs (8 candidates)
// computed beforehand; no ray is traced (the shade is not included).
void BM_ris_spatial_reuse(benchmark::State& state) {
  const auto view = room_dprsm(64).view();
  const auto g = room_gbuffer(kImage).view();
  static std::vector<vplkit::ris_reservoir<float>>* res = [&] {
    auto* r = new std::vector<vplkit::ris_reservoir<float>>(std::size_t(g.pixel_count()));
    for (int p = 0; p < g.pixel_count(); ++p) {
      vplkit::counter_rng rng = vplkit::make_counter_rng(5u, std::uint32_t(p));
      (*r)[std::size_t(p)] = vplkit::ris_resample(g.at(p), view, mixture(), rng, 8, kDmin);
    }
    return r;
  }();
  vplkit::ris_spatial_settings<float> s;
  s.neighbours = int(state.range(0));
  s.radius = 4;
  s.mis = state.range(1) != 0 ? vplkit::ris_reuse_mis::balance : vplkit::ris_reuse_mis::pairwise;
  const auto load = [&](int q) { return vplkit::ris_neighbour<float>{g.at(q), (*res)[std::size_t(q)]}; };
  int pixel = 0;
  float acc = 0.0f;
  for (auto _ : state) {
    for (int k = 0; k < kPointsPerIteration; ++k) {
      vplkit::counter_rng rng = vplkit::make_counter_rng(6u, std::uint32_t(pixel));
      acc += vplkit::ris_spatial_reuse(g.at(pixel), pixel, g.width, g.height, view, (*res)[std::size_t(pixel)], load, s,
                                       rng, kDmin)
                 .weight_sum;
      pixel = pixel + 1 == g.pixel_count() ? 0 : pixel + 1;
    }
    benchmark::DoNotOptimize(acc);
  }
  state.SetItemsProcessed(std::int64_t(state.iterations()) * kPointsPerIteration);
}

vplkit::voxel_tracer<float> tracer() { return vplkit::voxel_tracer<float>{room_grid(64).view()}; }
float tolerance() { return vplkit::voxel_tracer_depth_tolerance(room_grid(64).view()) + 0.05f; }

// 8 steps of estimate_ris_mis: a direction and a RIS sample of M candidates each (M = 0: estimate_mis's
// 8 + 8, a direction and a VPL sample each).
void BM_ris_mis_steps(benchmark::State& state) {
  const auto view = room_dprsm(64).view();
  const auto vis = visibility();
  const auto tr = tracer();
  const float tol = tolerance();
  const int m = int(state.range(0));
  run_points(state, 8, [&](const vplkit::gather_point<float>& gp, vplkit::counter_rng& rng) {
    if (m == 0)
      return vplkit::estimate_mis(gp, view, mixture(), rng, 8, 8, tr, vis, tol, vplkit::mis_mode::solid_angle,
                                  vplkit::vpl_mode::patch);
    return vplkit::estimate_ris_mis(gp, view, mixture(), rng, 8, 8, m, tr, vis, tol, vplkit::vpl_mode::patch);
  });
}

}  // namespace

BENCHMARK(BM_ris_candidates)->ArgName("patch")->Arg(0)->Arg(1)->Apply(vplkit_bench::standard);
BENCHMARK(BM_ris_mis_pooled_candidates)->Apply(vplkit_bench::standard);
BENCHMARK(BM_ris_estimate)->ArgName("M")->Arg(8)->Arg(32)->Apply(vplkit_bench::standard);
BENCHMARK(BM_vpl_sample_with_query)->Apply(vplkit_bench::standard);
BENCHMARK(BM_ris_spatial_reuse)->ArgNames({"K", "balance"})->Args({4, 0})->Args({4, 1})->Args({8, 0})->Args({8, 1})
    ->Apply(vplkit_bench::standard);
BENCHMARK(BM_ris_mis_steps)->ArgName("M")->Arg(0)->Arg(8)->Arg(32)->Apply(vplkit_bench::standard);

VPLKIT_BENCH_MAIN()
