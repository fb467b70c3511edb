// SPDX-License-Identifier: MIT
// Per-value cost of the sampling primitives (include/vplkit/sampling): the counter RNG (PCG hash),
// Duff et al.'s orthonormal basis, the concentric cosine-hemisphere map. T = float.
//   bench_sampling --benchmark_repetitions=3 --benchmark_report_aggregates_only=true
// Inputs are precomputed (kBatch = 4096 per iteration) so that the timing is the function.
#include "bench_common.hpp"

#include <vplkit/sampling/cosine_hemisphere.hpp>
#include <vplkit/sampling/orthonormal_basis.hpp>
#include <vplkit/sampling/rng.hpp>

namespace {

using namespace vplkit_bench;

void BM_pcg_hash(benchmark::State& state) {
  std::uint32_t acc = 0;
  std::uint32_t v = 12345u;
  for (auto _ : state) {
    for (std::size_t i = 0; i < kBatch; ++i) acc ^= vplkit::pcg_hash(v + std::uint32_t(i));
    v += std::uint32_t(kBatch);
    benchmark::DoNotOptimize(acc);
  }
  state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(kBatch));
}

// One stream drawing floats in sequence (two hashes per number).
void BM_rng_next_float_one_stream(benchmark::State& state) {
  vplkit::counter_rng r = vplkit::make_counter_rng(7u, 42u);
  run_batch(state, [&](std::size_t) { return vplkit::rng_next_float(r); });
}

// A new stream per value (make_counter_rng + one draw): the per-pixel setup of a shader.
void BM_rng_make_stream_and_draw(benchmark::State& state) {
  std::uint32_t stream = 0;
  run_batch(state, [&](std::size_t) {
    vplkit::counter_rng r = vplkit::make_counter_rng(3u, stream++);
    return vplkit::rng_next_float(r);
  });
}

void BM_make_orthonormal_basis(benchmark::State& state) {
  const std::vector<v3f> n = unit_directions(kBatch, 11u);
  run_batch(state, [&](std::size_t i) {
    const auto f = vplkit::make_orthonormal_basis(n[i]);
    return f.t.x + f.b.y;
  });
}

void BM_orthonormal_basis_to_world(benchmark::State& state) {
  const std::vector<v3f> n = unit_directions(kBatch, 11u);
  const std::vector<v3f> l = unit_directions(kBatch, 12u);
  run_batch(state, [&](std::size_t i) {
    const auto f = vplkit::make_orthonormal_basis(n[i]);
    return vplkit::to_world(f, l[i]).z;
  });
}

void BM_concentric_disk(benchmark::State& state) {
  const std::vector<v2f> u = uniform_pairs(kBatch, 13u);
  run_batch(state, [&](std::size_t i) { return vplkit::concentric_disk(u[i]).x; });
}

void BM_sample_cosine_hemisphere(benchmark::State& state) {
  const std::vector<v2f> u = uniform_pairs(kBatch, 13u);
  run_batch(state, [&](std::size_t i) { return vplkit::sample_cosine_hemisphere(u[i]).z; });
}

// What one gathering / GBG direction costs end to end: two RNG draws, the hemisphere map, the
// basis and the rotation to world space.
void BM_cosine_direction_full(benchmark::State& state) {
  const std::vector<v3f> n = unit_directions(kBatch, 11u);
  vplkit::counter_rng r = vplkit::make_counter_rng(5u, 9u);
  run_batch(state, [&](std::size_t i) {
    const float u0 = vplkit::rng_next_float(r), u1 = vplkit::rng_next_float(r);
    const v3f local = vplkit::sample_cosine_hemisphere(v2f(u0, u1));
    return vplkit::to_world(vplkit::make_orthonormal_basis(n[i]), local).y;
  });
}

}  // namespace

BENCHMARK(BM_pcg_hash)->Apply(vplkit_bench::standard);
BENCHMARK(BM_rng_next_float_one_stream)->Apply(vplkit_bench::standard);
BENCHMARK(BM_rng_make_stream_and_draw)->Apply(vplkit_bench::standard);
BENCHMARK(BM_make_orthonormal_basis)->Apply(vplkit_bench::standard);
BENCHMARK(BM_orthonormal_basis_to_world)->Apply(vplkit_bench::standard);
BENCHMARK(BM_concentric_disk)->Apply(vplkit_bench::standard);
BENCHMARK(BM_sample_cosine_hemisphere)->Apply(vplkit_bench::standard);
BENCHMARK(BM_cosine_direction_full)->Apply(vplkit_bench::standard);

VPLKIT_BENCH_MAIN()
