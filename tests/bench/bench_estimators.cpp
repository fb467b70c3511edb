// SPDX-License-Identifier: MIT
// Estimators (include/vplkit/estimators) per gather point on the synthetic room (24 triangles),
// T = float. Gather points: the 4096 of the 64 x 64 G-buffer, 64 per iteration, cycled.
// Visibility: the two-sided voxel test on the room voxelised at 64^3 (voxel_visibility), or none
// (always_visible); the gathering rays use voxel_tracer at 64^3 (depth tolerance one voxel
// diagonal + 0.05). DPRSM 2 x 64 x 64 unless the name says otherwise; dmin = 0.1.
// Distributions for VPL sampling: from the global weights of 256 gather points (the builders'
// default pattern): discrete_cdf (guided inverse transform), alias_table, defensive_mixture
// (eps = 0.1), face_roulette (the paper's Alg. 1/3); local: 4 mixtures (2 x 2 regions, eps 0.1).
// Items: samples (16 per gather point: N = 16 VPLs, 16 gathering rays, 4 rounds x 4 local CDFs,
// MIS 8 rays + 8 VPLs), or gather points for the exhaustive sum (every texel of the map).
#include "bench_common.hpp"

#include <vplkit/builders/gather_subset.hpp>
#include <vplkit/builders/global_weights.hpp>
#include <vplkit/builders/local_weights.hpp>
#include <vplkit/builders/vpl_distribution.hpp>
#include <vplkit/distribution/alias_table.hpp>
#include <vplkit/distribution/discrete_cdf.hpp>
#include <vplkit/distribution/face_roulette.hpp>
#include <vplkit/estimators/gathering_estimator.hpp>
#include <vplkit/estimators/local_estimator.hpp>
#include <vplkit/estimators/mis_estimator.hpp>
#include <vplkit/estimators/vpl_sampling_estimator.hpp>
#include <vplkit/estimators/vpl_sum.hpp>
#include <vplkit/visibility/visibility_callables.hpp>

namespace {

using namespace vplkit_bench;

constexpr int kImage = 64;
constexpr int kPointsPerIteration = 64;
constexpr int kSamples = 16;
constexpr float kDmin = 0.1f;

const std::vector<vplkit::gather_point<float>>& points() {
  static const auto* p = new std::vector<vplkit::gather_point<float>>(room_gather_points(kImage));
  return *p;
}

vplkit::voxel_visibility<float> visibility() { return vplkit::voxel_visibility<float>{room_grid(64).view()}; }
vplkit::voxel_tracer<float> tracer() { return vplkit::voxel_tracer<float>{room_grid(64).view()}; }
float tolerance() { return vplkit::voxel_tracer_depth_tolerance(room_grid(64).view()) + 0.05f; }

struct distributions_t {
  std::vector<float> weights;
  vplkit::discrete_cdf<float> cdf;
  vplkit::alias_table<float> alias;
  vplkit::defensive_mixture<float> defensive;
  vplkit::face_roulette<float> roulette;
  std::vector<vplkit::defensive_mixture<float>> local;
  explicit distributions_t(int R) {
    const auto gb = room_gbuffer(kImage).view();
    const auto view = room_dprsm(R).view();
    const auto subset = vplkit::stratified_gather_subset(gb, vplkit::full_image_rect(gb), 256, 7u);
    weights = vplkit::build_global_weights(gb, subset, view, kDmin);
    cdf = vplkit::discrete_cdf<float>(weights);
    alias = vplkit::alias_table<float>(weights);
    defensive = vplkit::make_vpl_distribution(weights, view, 0.1f);
    const std::size_t face = std::size_t(R) * std::size_t(R);
    roulette = vplkit::face_roulette<float>(vplkit::discrete_cdf<float>(weights.data(), face),
                                            vplkit::discrete_cdf<float>(weights.data() + face, face));
    const vplkit::image_regions regions(kImage, kImage, 2, 2);
    local = vplkit::make_local_vpl_distributions(vplkit::build_local_weights(gb, regions, 64, 7u, view, kDmin), 4,
                                                 view, 0.1f);
  }
};

const distributions_t& dists() {
  static const distributions_t* d = new distributions_t(64);
  return *d;
}

// Runs `estimate(gp, rng)` on kPointsPerIteration gather points per iteration.
template <class Estimate>
void run_points(benchmark::State& state, std::int64_t items_per_point, Estimate&& estimate) {
  run_gather_points(state, points(), kPointsPerIteration, items_per_point, estimate);
}

void BM_exhaustive_vpl_sum_no_visibility(benchmark::State& state) {
  const auto view = room_dprsm(int(state.range(0))).view();
  run_points(state, 1, [&](const vplkit::gather_point<float>& gp, vplkit::counter_rng&) {
    return vplkit::exhaustive_vpl_sum(gp, view, vplkit::always_visible{}, kDmin);
  });
}

void BM_exhaustive_vpl_sum_voxel64(benchmark::State& state) {
  const auto view = room_dprsm(int(state.range(0))).view();
  const auto vis = visibility();
  run_points(state, 1, [&](const vplkit::gather_point<float>& gp, vplkit::counter_rng&) {
    return vplkit::exhaustive_vpl_sum(gp, view, vis, kDmin);
  });
}

template <class Distribution>
void run_vpl_sampling(benchmark::State& state, const Distribution& d) {
  const auto view = room_dprsm(64).view();
  const auto vis = visibility();
  run_points(state, kSamples, [&](const vplkit::gather_point<float>& gp, vplkit::counter_rng& rng) {
    return vplkit::estimate_vpl_sampling(gp, view, d, rng, kSamples, vis, kDmin);
  });
}

void BM_vpl_sampling_cdf(benchmark::State& state) { run_vpl_sampling(state, dists().cdf); }
void BM_vpl_sampling_alias(benchmark::State& state) { run_vpl_sampling(state, dists().alias); }
void BM_vpl_sampling_defensive(benchmark::State& state) { run_vpl_sampling(state, dists().defensive); }
void BM_vpl_sampling_face_roulette(benchmark::State& state) { run_vpl_sampling(state, dists().roulette); }

// The distribution alone, no visibility (what sampling costs before any ray).
void BM_vpl_sampling_defensive_no_visibility(benchmark::State& state) {
  const auto view = room_dprsm(64).view();
  const auto& d = dists().defensive;
  run_points(state, kSamples, [&](const vplkit::gather_point<float>& gp, vplkit::counter_rng& rng) {
    return vplkit::estimate_vpl_sampling(gp, view, d, rng, kSamples, vplkit::always_visible{}, kDmin);
  });
}

void BM_local_4cdfs(benchmark::State& state) {
  const auto view = room_dprsm(64).view();
  const auto vis = visibility();
  const auto& local = dists().local;
  const auto combination = state.range(0) != 0 ? vplkit::local_combination::balance : vplkit::local_combination::average;
  run_points(state, kSamples, [&](const vplkit::gather_point<float>& gp, vplkit::counter_rng& rng) {
    return vplkit::estimate_local(gp, view, local.data(), int(local.size()), rng, kSamples / 4, vis, kDmin, combination);
  });
}

void BM_gathering(benchmark::State& state) {
  const auto view = room_dprsm(64).view();
  const auto tr = tracer();
  const float tol = tolerance();
  run_points(state, kSamples, [&](const vplkit::gather_point<float>& gp, vplkit::counter_rng& rng) {
    return vplkit::estimate_gathering(gp, view, rng, kSamples, tr, tol);
  });
}

void BM_mis_8dirs_8vpls(benchmark::State& state) {
  const auto view = room_dprsm(64).view();
  const auto vis = visibility();
  const auto tr = tracer();
  const float tol = tolerance();
  const auto& d = dists().defensive;
  const auto mode = state.range(0) != 0 ? vplkit::mis_mode::solid_angle : vplkit::mis_mode::as_published;
  run_points(state, kSamples, [&](const vplkit::gather_point<float>& gp, vplkit::counter_rng& rng) {
    return vplkit::estimate_mis(gp, view, d, rng, kSamples / 2, kSamples / 2, tr, vis, tol, mode);
  });
}

}  // namespace

BENCHMARK(BM_exhaustive_vpl_sum_no_visibility)->ArgName("R")->Arg(16)->Arg(64)->Apply(vplkit_bench::standard);
BENCHMARK(BM_exhaustive_vpl_sum_voxel64)->ArgName("R")->Arg(16)->Arg(32)->Apply(vplkit_bench::standard);
BENCHMARK(BM_vpl_sampling_cdf)->Apply(vplkit_bench::standard);
BENCHMARK(BM_vpl_sampling_alias)->Apply(vplkit_bench::standard);
BENCHMARK(BM_vpl_sampling_defensive)->Apply(vplkit_bench::standard);
BENCHMARK(BM_vpl_sampling_face_roulette)->Apply(vplkit_bench::standard);
BENCHMARK(BM_vpl_sampling_defensive_no_visibility)->Apply(vplkit_bench::standard);
BENCHMARK(BM_local_4cdfs)->ArgName("balance")->Arg(1)->Arg(0)->Apply(vplkit_bench::standard);
BENCHMARK(BM_gathering)->Apply(vplkit_bench::standard);
BENCHMARK(BM_mis_8dirs_8vpls)->ArgName("solid_angle")->Arg(1)->Arg(0)->Apply(vplkit_bench::standard);

VPLKIT_BENCH_MAIN()
