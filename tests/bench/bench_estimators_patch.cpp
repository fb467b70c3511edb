// SPDX-License-Identifier: MIT
// Patch-sampled VPLs (vpl_mode::patch, docs/math.md section 11) against point VPLs, per sample,
// T = float, on the synthetic room as in bench_estimators.cpp: DPRSM 2 x 64 x 64, the 4096 gather
// points of the 64 x 64 G-buffer (64 per iteration, cycled), voxel visibility at 64^3 or none,
// voxel tracer at 64^3 for MIS, a defensive mixture (eps 0.1) over global weights of 256 gather
// points, dmin 0 (patch VPLs need no clamp), depth window = the tracer's tolerance.
// Each benchmark runs with Arg 0 (point) and 1 (patch); compare the two rows of one run.
//  - vpl_at / dprsm_patch_vpl: the VPL itself (batches of precomputed texels and jitters).
//  - VPL sampling, local (4 CDFs), MIS (8 + 8): whole estimates, items = samples.
//  - the exhaustive sum: items = gather points (every texel; the patch form with one jittered
//    point per texel).
#include "bench_common.hpp"

#include <vplkit/builders/gather_subset.hpp>
#include <vplkit/builders/global_weights.hpp>
#include <vplkit/builders/local_weights.hpp>
#include <vplkit/builders/vpl_distribution.hpp>
#include <vplkit/estimators/local_estimator.hpp>
#include <vplkit/estimators/mis_estimator.hpp>
#include <vplkit/estimators/vpl_sampling_estimator.hpp>
#include <vplkit/estimators/vpl_sum.hpp>
#include <vplkit/visibility/visibility_callables.hpp>
#include <vplkit/vpl/dprsm_patch.hpp>

namespace {

using namespace vplkit_bench;

constexpr int kImage = 64;
constexpr int kPointsPerIteration = 64;
constexpr int kSamples = 16;

vplkit::vpl_mode mode_of(const benchmark::State& state) {
  return state.range(0) != 0 ? vplkit::vpl_mode::patch : vplkit::vpl_mode::point;
}

const std::vector<vplkit::gather_point<float>>& points() {
  static const auto* p = new std::vector<vplkit::gather_point<float>>(room_gather_points(kImage));
  return *p;
}

float tolerance() { return vplkit::voxel_tracer_depth_tolerance(room_grid(64).view()) + 0.05f; }

struct distributions_t {
  vplkit::defensive_mixture<float> defensive;
  std::vector<vplkit::defensive_mixture<float>> local;
  distributions_t() {
    const auto gb = room_gbuffer(kImage).view();
    const auto view = room_dprsm(64).view();
    const auto subset = vplkit::stratified_gather_subset(gb, vplkit::full_image_rect(gb), 256, 7u);
    defensive = vplkit::make_vpl_distribution(vplkit::build_global_weights(gb, subset, view, 0.1f), view, 0.1f);
    const vplkit::image_regions regions(kImage, kImage, 2, 2);
    local = vplkit::make_local_vpl_distributions(vplkit::build_local_weights(gb, regions, 64, 7u, view, 0.1f), 4,
                                                 view, 0.1f);
  }
};

const distributions_t& dists() {
  static const distributions_t* d = new distributions_t();
  return *d;
}

template <class Estimate>
void run_points(benchmark::State& state, std::int64_t items_per_point, Estimate&& estimate) {
  run_gather_points(state, points(), kPointsPerIteration, items_per_point, estimate);
}

// The VPL alone: vpl_at(t) (point) or dprsm_patch_vpl(t, xi) (patch) over lit texels.
void BM_vpl(benchmark::State& state) {
  const auto view = room_dprsm(64).view();
  std::vector<int> texels;
  for (int t = 0; t < view.texel_count(); ++t)
    if (vplkit::vpl_has_flux(view.vpl_at(t))) texels.push_back(t);
  const std::vector<v2f> xi = uniform_pairs(kBatch, 5u);
  const bool patch = mode_of(state) == vplkit::vpl_mode::patch;
  const float tol = tolerance();
  float acc = 0;
  for (auto _ : state) {
    for (std::size_t k = 0; k < kBatch; ++k) {
      const int t = texels[k % texels.size()];
      acc += patch ? vplkit::dprsm_patch_vpl(view, t, xi[k], tol).point.flux.y : view.vpl_at(t).flux.y;
    }
    benchmark::DoNotOptimize(acc);
  }
  state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(kBatch));
}

template <class Visibility>
void run_vpl_sampling(benchmark::State& state, const Visibility& vis) {
  const auto view = room_dprsm(64).view();
  const auto& d = dists().defensive;
  const auto mode = mode_of(state);
  const float tol = tolerance();
  run_points(state, kSamples, [&](const vplkit::gather_point<float>& gp, vplkit::counter_rng& rng) {
    return vplkit::estimate_vpl_sampling(gp, view, d, rng, kSamples, vis, 0.0f, mode, tol);
  });
}

void BM_vpl_sampling_voxel64(benchmark::State& state) {
  run_vpl_sampling(state, vplkit::voxel_visibility<float>{room_grid(64).view()});
}
void BM_vpl_sampling_no_visibility(benchmark::State& state) { run_vpl_sampling(state, vplkit::always_visible{}); }

void BM_local_4cdfs_balance(benchmark::State& state) {
  const auto view = room_dprsm(64).view();
  const vplkit::voxel_visibility<float> vis{room_grid(64).view()};
  const auto& local = dists().local;
  const auto mode = mode_of(state);
  const float tol = tolerance();
  run_points(state, kSamples, [&](const vplkit::gather_point<float>& gp, vplkit::counter_rng& rng) {
    return vplkit::estimate_local(gp, view, local.data(), int(local.size()), rng, kSamples / 4, vis, 0.0f,
                                  vplkit::local_combination::balance, mode, tol);
  });
}

void BM_mis_8dirs_8vpls(benchmark::State& state) {
  const auto view = room_dprsm(64).view();
  const vplkit::voxel_visibility<float> vis{room_grid(64).view()};
  const vplkit::voxel_tracer<float> tr{room_grid(64).view()};
  const auto& d = dists().defensive;
  const auto mode = mode_of(state);
  const float tol = tolerance();
  run_points(state, kSamples, [&](const vplkit::gather_point<float>& gp, vplkit::counter_rng& rng) {
    return vplkit::estimate_mis(gp, view, d, rng, kSamples / 2, kSamples / 2, tr, vis, tol,
                                vplkit::mis_mode::solid_angle, mode);
  });
}

void BM_exhaustive_sum_no_visibility(benchmark::State& state) {
  const auto view = room_dprsm(64).view();
  const bool patch = mode_of(state) == vplkit::vpl_mode::patch;
  const float tol = tolerance();
  run_points(state, 1, [&](const vplkit::gather_point<float>& gp, vplkit::counter_rng& rng) {
    return patch ? vplkit::exhaustive_vpl_patch_sum(gp, view, rng, 1, vplkit::always_visible{}, 0.0f, tol)
                 : vplkit::exhaustive_vpl_sum(gp, view, vplkit::always_visible{}, 0.0f);
  });
}

}  // namespace

BENCHMARK(BM_vpl)->ArgName("patch")->Arg(0)->Arg(1)->Apply(vplkit_bench::standard);
BENCHMARK(BM_vpl_sampling_voxel64)->ArgName("patch")->Arg(0)->Arg(1)->Apply(vplkit_bench::standard);
BENCHMARK(BM_vpl_sampling_no_visibility)->ArgName("patch")->Arg(0)->Arg(1)->Apply(vplkit_bench::standard);
BENCHMARK(BM_local_4cdfs_balance)->ArgName("patch")->Arg(0)->Arg(1)->Apply(vplkit_bench::standard);
BENCHMARK(BM_mis_8dirs_8vpls)->ArgName("patch")->Arg(0)->Arg(1)->Apply(vplkit_bench::standard);
BENCHMARK(BM_exhaustive_sum_no_visibility)->ArgName("patch")->Arg(0)->Arg(1)->Apply(vplkit_bench::standard);

VPLKIT_BENCH_MAIN()
