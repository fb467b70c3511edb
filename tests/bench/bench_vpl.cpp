// SPDX-License-Identifier: MIT
// The VPL model (include/vplkit/vpl) on the synthetic room (tests/support/synthetic_scene.hpp,
// 24 triangles, light at (0.3, 2.6, 0.2) looking down), T = float:
//  - vpl_at: the VPL (flux, position, normal) of a DPRSM texel, over every texel of a 2 x R x R map;
//  - vpl_contribution: L_t(x) of one VPL at one gather point (gather points of a 64 x 64 G-buffer,
//    VPLs of the DPRSM at R = 64, no visibility);
//  - reflected_radiance, dprsm_lookup (projection into the DPRSM and the depth test);
//  - render_dprsm: the CPU DPRSM ray caster with the scene's brute-force tracer (24 triangles),
//    per texel of the 2 x R x R map (invalid corner texels cost no ray).
#include "bench_common.hpp"

#include <vplkit/vpl/dprsm_lookup.hpp>
#include <vplkit/vpl/dprsm_raycast.hpp>
#include <vplkit/vpl/dprsm_view.hpp>
#include <vplkit/vpl/vpl.hpp>

namespace {

using namespace vplkit_bench;

void BM_vpl_at_all_texels(benchmark::State& state) {
  const int R = int(state.range(0));
  const auto view = room_dprsm(R).view();
  const int n = view.texel_count();
  float acc = 0;
  for (auto _ : state) {
    for (int t = 0; t < n; ++t) acc += view.vpl_at(t).flux.x;
    benchmark::DoNotOptimize(acc);
  }
  state.SetItemsProcessed(std::int64_t(state.iterations()) * n);
}

const vpl_pairs& pairs() {
  static const vpl_pairs* p = new vpl_pairs(41u);
  return *p;
}

void BM_vpl_contribution(benchmark::State& state) {
  const auto& p = pairs();
  const float dmin = 0.1f;
  run_batch(state, [&](std::size_t i) { return vplkit::vpl_contribution(p.gp[i].position, p.gp[i].normal, p.gp[i].albedo, p.v[i], dmin).y; });
}

void BM_reflected_radiance(benchmark::State& state) {
  const auto& p = pairs();
  const auto& light = room().light;
  run_batch(state, [&](std::size_t i) { return vplkit::reflected_radiance(light.position, light.intensity, p.v[i].position, p.v[i].normal, v3f(0.5f)).x; });
}

// Surface points of the room (the G-buffer's), projected into the DPRSM at R.
void BM_dprsm_lookup(benchmark::State& state) {
  const int R = int(state.range(0));
  const auto view = room_dprsm(R).view();
  const auto& p = pairs();
  run_batch<int>(state, [&](std::size_t i) {
    const auto r = vplkit::dprsm_lookup(view, p.gp[i].position, 0.05f);
    return r.texel + (r.lit ? 1 : 0);
  });
}

void BM_render_dprsm_raycast(benchmark::State& state) {
  const int R = int(state.range(0));
  const scene_t& s = room();
  std::vector<v3f> pos, nrm, alb;
  for (auto _ : state) {
    const auto view = vplkit::render_dprsm(
        s.light, R, [&s](v3f o, v3f d) { return s.trace_from_light(o, d); }, pos, nrm, alb);
    benchmark::DoNotOptimize(view.position);
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(std::int64_t(state.iterations()) * vplkit::texel_count(R));
}

}  // namespace

BENCHMARK(BM_vpl_at_all_texels)->Arg(64)->Arg(256)->Apply(vplkit_bench::standard);
BENCHMARK(BM_vpl_contribution)->Apply(vplkit_bench::standard);
BENCHMARK(BM_reflected_radiance)->Apply(vplkit_bench::standard);
BENCHMARK(BM_dprsm_lookup)->Arg(64)->Arg(256)->Apply(vplkit_bench::standard);
BENCHMARK(BM_render_dprsm_raycast)->Arg(64)->Arg(256)->Unit(benchmark::kMillisecond)->Apply(vplkit_bench::standard);

VPLKIT_BENCH_MAIN()
