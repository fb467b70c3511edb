// SPDX-License-Identifier: MIT
// CDF weight builders (include/vplkit/builders) on the synthetic room (24 triangles), T = float.
// Time per build; items = the work unit named in each benchmark:
//  - gather subset: stratified_gather_subset of |S| pixels of the 64 x 64 G-buffer (items = picks);
//  - global: build_global_weights, |S| gather points of the 64 x 64 G-buffer against every texel of
//    the 2 x R x R DPRSM (items = |S| x 2R^2 (gather point, texel) pairs; invalid / empty texels
//    are skipped after one vpl_at);
//  - local: build_local_weights, 2 x 2 regions, |S| / 4 gather points per region (items as global);
//  - GBG: build_gbg_weights over all 4096 gather points of the 64 x 64 G-buffer, 16 directions
//    each, both accumulators, hole fill on, with the voxel tracer of the room at 64^3 (what the GPU
//    kernel uses) or the exact brute-force tracer (items = rays = 4096 x 16);
//  - gbg_fill_holes alone, make_vpl_distribution (defensive mixture, eps 0.1) and the 4 local
//    mixtures (items = texels).
#include "bench_common.hpp"

#include <vplkit/builders/gather_subset.hpp>
#include <vplkit/builders/gbg_weights.hpp>
#include <vplkit/builders/global_weights.hpp>
#include <vplkit/builders/local_weights.hpp>
#include <vplkit/builders/vpl_distribution.hpp>
#include <vplkit/visibility/visibility_callables.hpp>

namespace {

using namespace vplkit_bench;

constexpr int kImage = 64;  // G-buffer kImage x kImage
constexpr float kDmin = 0.1f;

void BM_stratified_gather_subset(benchmark::State& state) {
  const auto gb = room_gbuffer(kImage).view();
  const int count = int(state.range(0));
  std::size_t acc = 0;
  for (auto _ : state) {
    const std::vector<int> s = vplkit::stratified_gather_subset(gb, vplkit::full_image_rect(gb), count, 7u);
    acc += s.size();
    benchmark::DoNotOptimize(acc);
  }
  state.SetItemsProcessed(std::int64_t(state.iterations()) * count);
}

void BM_build_global_weights(benchmark::State& state) {
  const int R = int(state.range(0)), S = int(state.range(1));
  const auto gb = room_gbuffer(kImage).view();
  const auto view = room_dprsm(R).view();
  const std::vector<int> subset = vplkit::stratified_gather_subset(gb, vplkit::full_image_rect(gb), S, 7u);
  std::vector<float> w(std::size_t(view.texel_count()));
  for (auto _ : state) {
    vplkit::build_global_weights(gb, subset.data(), subset.size(), view, kDmin, w.data(), w.size());
    benchmark::DoNotOptimize(w.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(subset.size()) * view.texel_count());
}

void BM_build_local_weights_2x2(benchmark::State& state) {
  const int R = int(state.range(0)), S = int(state.range(1));
  const auto gb = room_gbuffer(kImage).view();
  const auto view = room_dprsm(R).view();
  const vplkit::image_regions regions(kImage, kImage, 2, 2);
  for (auto _ : state) {
    const std::vector<float> w = vplkit::build_local_weights(gb, regions, S / 4, 7u, view, kDmin);
    benchmark::DoNotOptimize(w.data());
  }
  state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(S) * view.texel_count());
}

template <class Tracer>
void run_gbg(benchmark::State& state, const Tracer& tracer, float tolerance) {
  const int R = int(state.range(0));
  const auto gb = room_gbuffer(kImage).view();
  const auto view = room_dprsm(R).view();
  vplkit::gbg_params<float> params;
  params.n_dirs = 16;
  params.dmin = kDmin;
  params.depth_tolerance = tolerance;
  params.seed = 21u;
  params.accumulator = state.range(1) != 0 ? vplkit::gbg_accumulator::gathering : vplkit::gbg_accumulator::paper;
  params.fill_holes = true;
  std::vector<float> w(std::size_t(view.texel_count()));
  vplkit::gbg_stats stats;
  for (auto _ : state) {
    stats = vplkit::build_gbg_weights(gb, view, tracer, params, w.data(), w.size());
    benchmark::DoNotOptimize(w.data());
    benchmark::ClobberMemory();
  }
  state.counters["lit_hit_fraction"] = double(stats.lit_hits) / double(stats.rays);
  state.counters["holes"] = double(stats.holes);
  state.SetItemsProcessed(std::int64_t(state.iterations()) * stats.rays);
}

void BM_build_gbg_voxel_tracer64(benchmark::State& state) {
  const auto g = room_grid(64).view();
  run_gbg(state, vplkit::voxel_tracer<float>{g}, vplkit::voxel_tracer_depth_tolerance(g) + 0.05f);
}

void BM_build_gbg_exact_tracer(benchmark::State& state) {
  run_gbg(state, vplkit_test::exact_tracer<float>{&room()}, 0.05f);
}

// GBG-like raw weights with holes: the global weights of 16 gather points, every third texel
// zeroed.
std::vector<float> holey_global_weights(int R) {
  const auto gb = room_gbuffer(kImage).view();
  const auto view = room_dprsm(R).view();
  const std::vector<int> subset = vplkit::stratified_gather_subset(gb, vplkit::full_image_rect(gb), 16, 3u);
  std::vector<float> w = vplkit::build_global_weights(gb, subset, view, kDmin);
  for (std::size_t t = 0; t < w.size(); t += 3) w[t] = 0.0f;
  return w;
}

void BM_gbg_fill_holes(benchmark::State& state) {
  const int R = int(state.range(0));
  const auto view = room_dprsm(R).view();
  const std::vector<float> in = holey_global_weights(R);
  std::vector<float> out(in.size());
  for (auto _ : state) {
    benchmark::DoNotOptimize(vplkit::gbg_fill_holes(in.data(), out.data(), view));
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(in.size()));
}

void BM_make_vpl_distribution_eps01(benchmark::State& state) {
  const int R = int(state.range(0));
  const auto view = room_dprsm(R).view();
  const std::vector<float> w = holey_global_weights(R);
  const vplkit::discrete_cdf<float> fallback = vplkit::make_vpl_fallback(view);
  for (auto _ : state) {
    const auto d = vplkit::make_vpl_distribution(w.data(), w.size(), view, fallback, 0.1f);
    benchmark::DoNotOptimize(&d);
  }
  state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(w.size()));
}

void BM_make_local_vpl_distributions_4_eps01(benchmark::State& state) {
  const int R = int(state.range(0));
  const auto view = room_dprsm(R).view();
  const std::vector<float> one = holey_global_weights(R);
  std::vector<float> flat;
  for (int i = 0; i < 4; ++i) flat.insert(flat.end(), one.begin(), one.end());
  for (auto _ : state) {
    const auto d = vplkit::make_local_vpl_distributions(flat, 4, view, 0.1f);
    benchmark::DoNotOptimize(d.data());
  }
  state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(flat.size()));
}

}  // namespace

BENCHMARK(BM_stratified_gather_subset)->Arg(256)->Arg(4096)->Apply(vplkit_bench::standard);
BENCHMARK(BM_build_global_weights)->ArgNames({"R", "S"})->Args({64, 256})->Args({256, 64})->Unit(benchmark::kMillisecond)->Apply(vplkit_bench::standard);
BENCHMARK(BM_build_local_weights_2x2)->ArgNames({"R", "S"})->Args({64, 256})->Args({256, 64})->Unit(benchmark::kMillisecond)->Apply(vplkit_bench::standard);
BENCHMARK(BM_build_gbg_voxel_tracer64)->ArgNames({"R", "gathering"})->Args({64, 1})->Args({64, 0})->Args({256, 1})->Args({256, 0})->Unit(benchmark::kMillisecond)->Apply(vplkit_bench::standard);
BENCHMARK(BM_build_gbg_exact_tracer)->ArgNames({"R", "gathering"})->Args({64, 1})->Args({256, 1})->Unit(benchmark::kMillisecond)->Apply(vplkit_bench::standard);
BENCHMARK(BM_gbg_fill_holes)->ArgName("R")->Arg(64)->Arg(256)->Unit(benchmark::kMillisecond)->Apply(vplkit_bench::standard);
BENCHMARK(BM_make_vpl_distribution_eps01)->ArgName("R")->Arg(64)->Arg(256)->Unit(benchmark::kMillisecond)->Apply(vplkit_bench::standard);
BENCHMARK(BM_make_local_vpl_distributions_4_eps01)->ArgName("R")->Arg(256)->Unit(benchmark::kMillisecond)->Apply(vplkit_bench::standard);

VPLKIT_BENCH_MAIN()
