// SPDX-License-Identifier: MIT
// Per-value cost of the MIS heuristics and density conversions (include/vplkit/mis). T = float;
// inputs precomputed (kBatch = 4096 per iteration): pdfs in (0, 4), counts 16 and 16.
#include "bench_common.hpp"

#include <vplkit/mis/heuristics.hpp>
#include <vplkit/mis/pdf_conversion.hpp>

namespace {

using namespace vplkit_bench;

struct pdf_inputs {
  std::vector<float> p1, p2, f, d2, area, cos1, cos2;
  pdf_inputs() {
    const std::vector<float> u = uniforms(7 * kBatch, 31u);
    auto take = [&](std::size_t k, float scale, float offset) {
      std::vector<float> v(kBatch);
      for (std::size_t i = 0; i < kBatch; ++i) v[i] = offset + scale * u[k * kBatch + i];
      return v;
    };
    p1 = take(0, 4.0f, 1e-3f);
    p2 = take(1, 4.0f, 1e-3f);
    f = take(2, 2.0f, 0.0f);
    d2 = take(3, 9.0f, 1e-2f);
    area = take(4, 1e-2f, 1e-6f);
    cos1 = take(5, 1.0f, 0.0f);
    cos2 = take(6, 1.0f, 0.0f);
  }
};

const pdf_inputs& in() {
  static const pdf_inputs* p = new pdf_inputs();
  return *p;
}

void BM_balance_heuristic(benchmark::State& state) {
  const auto& x = in();
  run_batch(state, [&](std::size_t i) { return vplkit::balance_heuristic(16.0f, x.p1[i], 16.0f, x.p2[i]); });
}

void BM_power_heuristic(benchmark::State& state) {
  const auto& x = in();
  run_batch(state, [&](std::size_t i) { return vplkit::power_heuristic(16.0f, x.p1[i], 16.0f, x.p2[i]); });
}

// f / (n1 p1 + n2 p2) with its overflow-safe ordering (the MIS estimator's per-sample value).
void BM_balance_combined(benchmark::State& state) {
  const auto& x = in();
  run_batch(state, [&](std::size_t i) { return vplkit::balance_combined(x.f[i], 16.0f, x.p1[i], 16.0f, x.p2[i]); });
}

void BM_cosine_pdf_solid_angle(benchmark::State& state) {
  const auto& x = in();
  run_batch(state, [&](std::size_t i) { return vplkit::cosine_pdf_solid_angle(x.cos2[i]); });
}

// pmf(t) -> solid-angle density at x: pmf d2^2 / (A_t cos theta1).
void BM_vpl_pdf_solid_angle(benchmark::State& state) {
  const auto& x = in();
  run_batch(state, [&](std::size_t i) { return vplkit::vpl_pdf_solid_angle(x.p2[i] * 1e-4f, x.d2[i], x.area[i], x.cos1[i]); });
}

// The paper's mixed-measure weights (eq. 8-11), for comparison.
void BM_mis_weights_as_published(benchmark::State& state) {
  const auto& x = in();
  run_batch(state, [&](std::size_t i) {
    const float c = x.cos2[i];
    const auto w = vplkit::mis_weights_as_published(c, std::sqrt(1.0f - c * c), x.p2[i] * 1e-4f);
    return w.vpl + w.gathering;
  });
}

}  // namespace

BENCHMARK(BM_balance_heuristic)->Apply(vplkit_bench::standard);
BENCHMARK(BM_power_heuristic)->Apply(vplkit_bench::standard);
BENCHMARK(BM_balance_combined)->Apply(vplkit_bench::standard);
BENCHMARK(BM_cosine_pdf_solid_angle)->Apply(vplkit_bench::standard);
BENCHMARK(BM_vpl_pdf_solid_angle)->Apply(vplkit_bench::standard);
BENCHMARK(BM_mis_weights_as_published)->Apply(vplkit_bench::standard);

VPLKIT_BENCH_MAIN()
