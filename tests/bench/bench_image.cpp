// SPDX-License-Identifier: MIT
// Hole-aware 3x3 median fill (include/vplkit/image/median_fill.hpp) of a DPRSM weight array of
// 2 x R x R floats: median_fill_dprsm (validation, the finiteness scan and the fill of both faces).
// Holes: each texel is set to 0 with probability holes% (fixed seed), the rest are exponential
// weights; texels outside the paraboloid disk are 0 as in a real weight array.
//   BM_median_fill_dprsm/<R>/<holes %>: items = texels (2 R^2), bytes = texels read + written.
#include "bench_common.hpp"

#include <vplkit/image/median_fill.hpp>
#include <vplkit/paraboloid/texel_grid.hpp>

namespace {

using namespace vplkit_bench;

void BM_median_fill_dprsm(benchmark::State& state) {
  const int R = int(state.range(0));
  const std::vector<float> in = holey_weights(R, int(state.range(1)));
  std::vector<float> out(in.size(), 0.0f);
  for (auto _ : state) {
    vplkit::median_fill_dprsm(in.data(), out.data(), R);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(in.size()));
  state.SetBytesProcessed(std::int64_t(state.iterations()) * std::int64_t(2 * in.size() * sizeof(float)));
}

// The per-texel function alone on hole texels (9 reads, the insertion sort), no validation.
void BM_median_fill_texel_holes_only(benchmark::State& state) {
  const int R = 512;
  const std::vector<float> in = holey_weights(R, int(state.range(0)));
  std::vector<std::pair<int, int>> holes;
  for (int y = 1; y < R - 1 && holes.size() < kBatch; ++y)
    for (int x = 1; x < R - 1 && holes.size() < kBatch; ++x)
      if (in[std::size_t(y * R + x)] == 0.0f && vplkit::texel_is_valid(x, y, R)) holes.emplace_back(x, y);
  auto always = [](int, int) { return true; };
  float acc = 0;
  for (auto _ : state) {
    for (const auto& h : holes) acc += vplkit::median_fill_texel(in.data(), R, R, h.first, h.second, always);
    benchmark::DoNotOptimize(acc);
  }
  state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(holes.size()));
}

}  // namespace

BENCHMARK(BM_median_fill_dprsm)->Args({512, 10})->Args({512, 90})->Args({256, 10})->Unit(benchmark::kMillisecond)->Apply(vplkit_bench::standard);
BENCHMARK(BM_median_fill_texel_holes_only)->Arg(10)->Arg(90)->Apply(vplkit_bench::standard);

VPLKIT_BENCH_MAIN()
