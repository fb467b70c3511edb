// SPDX-License-Identifier: MIT
// Build and sampling throughput of the discrete samplers against std::discrete_distribution.
//   bench_distribution --benchmark_repetitions=3 --benchmark_report_aggregates_only=true
// Weights are exponential (not trivially uniform); the u are precomputed (2^20 of them, the
// RNG convention of docs/math.md section 6) so that the timing is the sampler, not the RNG. Every
// sampler sees the same u sequence; std::discrete_distribution gets the same bits through a
// replaying URNG (it turns each 64-bit draw into a double in [0, 1) itself).
#include <vplkit/distribution/alias_table.hpp>
#include <vplkit/distribution/discrete_cdf.hpp>

#include <benchmark/benchmark.h>

#include <cstdint>
#include <random>
#include <vector>

namespace {

constexpr std::size_t kUs = std::size_t(1) << 20;  // buffer of precomputed random numbers

const std::vector<float>& weights(std::size_t n) {
  static std::vector<float> w;
  if (w.size() != n) {
    std::mt19937_64 rng(n);
    std::exponential_distribution<float> ex(1.0f);
    w.resize(n);
    for (auto& x : w) x = ex(rng);
  }
  return w;
}

const std::vector<std::uint32_t>& random_bits() {
  static const std::vector<std::uint32_t> bits = [] {
    std::mt19937 rng(12345);
    std::vector<std::uint32_t> b(kUs);
    for (auto& x : b) x = rng();
    return b;
  }();
  return bits;
}

const std::vector<float>& random_us() {
  static const std::vector<float> us = [] {
    std::vector<float> u(kUs);
    for (std::size_t i = 0; i < kUs; ++i) u[i] = float(random_bits()[i] >> 8) * 0x1p-24f;
    return u;
  }();
  return us;
}

// A URNG that replays the precomputed bits (as 64-bit draws), so std::discrete_distribution
// pays no RNG cost either.
struct replay_urng {
  using result_type = std::uint64_t;
  static constexpr result_type min() { return 0; }
  static constexpr result_type max() { return ~result_type(0); }
  const std::uint32_t* bits;
  std::size_t i = 0;
  result_type operator()() {
    const std::uint64_t hi = bits[i & (kUs - 1)], lo = bits[(i + 1) & (kUs - 1)];
    ++i;
    return (hi << 32) | lo;
  }
};

// The `min` aggregate next to mean / median / stddev / cv under --benchmark_repetitions (as the
// other bench programs report through bench_common.hpp).
double min_of(const std::vector<double>& v) {
  double m = v.empty() ? 0.0 : v[0];
  for (double x : v) m = x < m ? x : m;
  return m;
}

void sizes(benchmark::internal::Benchmark* b) {
  for (int k = 10; k <= 22; k += 2) b->Arg(int64_t(1) << k);
  b->Arg(int64_t(1) << 24);
}

// ---- build ----------------------------------------------------------------------------------

// Building from `w` (a new object each time) or rebuilding into one (discrete_cdf::assign: what a
// renderer does every frame; no allocation, so no page faults on fresh memory).
void build_discrete_cdf(benchmark::State& state, const std::vector<float>& w) {
  for (auto _ : state) {
    vplkit::discrete_cdf<float> d(w);
    benchmark::DoNotOptimize(d.cdf().data());
  }
  state.SetItemsProcessed(state.iterations() * int64_t(w.size()));
}

void rebuild_discrete_cdf(benchmark::State& state, const std::vector<float>& w) {
  vplkit::discrete_cdf<float> d(w);
  for (auto _ : state) {
    d.assign(w);
    benchmark::DoNotOptimize(d.cdf().data());
  }
  state.SetItemsProcessed(state.iterations() * int64_t(w.size()));
}

void BM_build_discrete_cdf(benchmark::State& state) { build_discrete_cdf(state, weights(std::size_t(state.range(0)))); }
void BM_rebuild_discrete_cdf(benchmark::State& state) { rebuild_discrete_cdf(state, weights(std::size_t(state.range(0)))); }
// The target: both paraboloids of a 512 x 512 DPRSM, float weights.
void BM_build_discrete_cdf_2x512x512(benchmark::State& state) { build_discrete_cdf(state, weights(2 * 512 * 512)); }
void BM_rebuild_discrete_cdf_2x512x512(benchmark::State& state) { rebuild_discrete_cdf(state, weights(2 * 512 * 512)); }

void BM_build_alias_table(benchmark::State& state) {
  const auto& w = weights(std::size_t(state.range(0)));
  for (auto _ : state) {
    vplkit::alias_table<float> a(w);
    benchmark::DoNotOptimize(a.bins().data());
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
}

void BM_build_std_discrete_distribution(benchmark::State& state) {
  const auto& w = weights(std::size_t(state.range(0)));
  for (auto _ : state) {
    std::discrete_distribution<std::uint32_t> d(w.begin(), w.end());
    benchmark::DoNotOptimize(&d);
  }
  state.SetItemsProcessed(state.iterations() * state.range(0));
}

// ---- sampling -------------------------------------------------------------------------------

template <class Sample>
void run_sampling(benchmark::State& state, Sample&& sample) {
  const std::vector<float>& us = random_us();
  std::size_t i = 0, acc = 0;
  for (auto _ : state) {
    acc += sample(us[i]);
    i = (i + 1) & (kUs - 1);
  }
  benchmark::DoNotOptimize(acc);
  state.SetItemsProcessed(state.iterations());
}

void BM_sample_discrete_cdf_guided(benchmark::State& state) {
  const vplkit::discrete_cdf<float> d(weights(std::size_t(state.range(0))));
  run_sampling(state, [&](float u) { return d.sample(u).index; });
}

void BM_sample_discrete_cdf_binary_search(benchmark::State& state) {
  const vplkit::discrete_cdf<float> d(weights(std::size_t(state.range(0))));
  run_sampling(state, [&](float u) { return d.sample_binary_search(u).index; });
}

void BM_sample_alias_table_one_u(benchmark::State& state) {
  const vplkit::alias_table<float> a(weights(std::size_t(state.range(0))));
  run_sampling(state, [&](float u) { return a.sample(u).index; });
}

void BM_sample_alias_table_two_u(benchmark::State& state) {
  const vplkit::alias_table<float> a(weights(std::size_t(state.range(0))));
  const std::vector<float>& us = random_us();
  std::size_t i = 0, acc = 0;
  for (auto _ : state) {
    acc += a.sample(us[i], us[(i + 1) & (kUs - 1)]).index;
    i = (i + 2) & (kUs - 1);
  }
  benchmark::DoNotOptimize(acc);
  state.SetItemsProcessed(state.iterations());
}

void BM_sample_std_discrete_distribution(benchmark::State& state) {
  const auto& w = weights(std::size_t(state.range(0)));
  std::discrete_distribution<std::uint32_t> d(w.begin(), w.end());
  replay_urng g{random_bits().data()};
  std::size_t acc = 0;
  for (auto _ : state) acc += d(g);
  benchmark::DoNotOptimize(acc);
  state.SetItemsProcessed(state.iterations());
}

}  // namespace

BENCHMARK(BM_build_discrete_cdf_2x512x512)->Unit(benchmark::kMicrosecond)->ComputeStatistics("min", &min_of);
BENCHMARK(BM_rebuild_discrete_cdf_2x512x512)->Unit(benchmark::kMicrosecond)->ComputeStatistics("min", &min_of);
BENCHMARK(BM_build_discrete_cdf)->Apply(sizes)->Unit(benchmark::kMicrosecond)->ComputeStatistics("min", &min_of);
BENCHMARK(BM_rebuild_discrete_cdf)->Apply(sizes)->Unit(benchmark::kMicrosecond)->ComputeStatistics("min", &min_of);
BENCHMARK(BM_build_alias_table)->Apply(sizes)->Unit(benchmark::kMicrosecond)->ComputeStatistics("min", &min_of);
BENCHMARK(BM_build_std_discrete_distribution)->Apply(sizes)->Unit(benchmark::kMicrosecond)->ComputeStatistics("min", &min_of);
BENCHMARK(BM_sample_discrete_cdf_guided)->Apply(sizes)->ComputeStatistics("min", &min_of);
BENCHMARK(BM_sample_discrete_cdf_binary_search)->Apply(sizes)->ComputeStatistics("min", &min_of);
BENCHMARK(BM_sample_alias_table_one_u)->Apply(sizes)->ComputeStatistics("min", &min_of);
BENCHMARK(BM_sample_alias_table_two_u)->Apply(sizes)->ComputeStatistics("min", &min_of);
BENCHMARK(BM_sample_std_discrete_distribution)->Apply(sizes)->ComputeStatistics("min", &min_of);

BENCHMARK_MAIN();
