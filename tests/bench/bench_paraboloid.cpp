// SPDX-License-Identifier: MIT
// Per-value cost of the dual paraboloid mapping (include/vplkit/paraboloid): direction -> (face,
// uv) -> texel, texel centre -> direction, texel solid angle, and the light-frame rotation.
// T = float; inputs precomputed (kBatch = 4096 per iteration); resolutions stated in the names.
#include "bench_common.hpp"

#include <vplkit/paraboloid/light_frame.hpp>
#include <vplkit/paraboloid/paraboloid.hpp>
#include <vplkit/paraboloid/texel_grid.hpp>

namespace {

using namespace vplkit_bench;

void BM_paraboloid_from_direction(benchmark::State& state) {
  const std::vector<v3f> d = unit_directions(kBatch, 21u);
  run_batch(state, [&](std::size_t i) {
    const auto p = vplkit::paraboloid_from_direction(d[i]);
    return p.uv.x + float(p.face);
  });
}

// World direction -> light space -> face/uv -> flat texel index (dprsm_view::texel_of_direction).
void BM_direction_to_texel(benchmark::State& state) {
  const int R = int(state.range(0));
  const std::vector<v3f> d = unit_directions(kBatch, 22u);
  const vplkit::light_frame<float> frame(v3f(0.3f, 2.6f, 0.2f), v3f(0, -1, 0));
  run_batch<int>(state, [&](std::size_t i) {
    const auto p = vplkit::paraboloid_from_direction(frame.to_light(d[i]));
    const vplkit::ivec2 xy = vplkit::texel_from_uv(p.uv, R);
    return vplkit::texel_index(p.face, xy.x, xy.y, R);
  });
}

// Flat texel index -> centre uv -> light-space direction -> world (render_dprsm's per-texel ray).
void BM_texel_to_direction(benchmark::State& state) {
  const int R = int(state.range(0));
  const int n = vplkit::texel_count(R);
  const vplkit::light_frame<float> frame(v3f(0.3f, 2.6f, 0.2f), v3f(0, -1, 0));
  std::vector<int> idx(kBatch);
  std::mt19937 g(23u);
  for (int& t : idx) t = int(g() % std::uint32_t(n));
  run_batch(state, [&](std::size_t i) {
    const int t = idx[i];
    const vplkit::ivec2 xy = vplkit::texel_coords(t, R);
    const v3f d = vplkit::paraboloid_to_direction(vplkit::texel_face(t, R), vplkit::texel_center_uv<float>(xy.x, xy.y, R));
    return frame.to_world(d).y;
  });
}

// Solid angle of every texel of one face, row by row (the validity test included).
void BM_texel_solid_angle(benchmark::State& state) {
  const int R = int(state.range(0));
  float acc = 0;
  for (auto _ : state) {
    for (int y = 0; y < R; ++y)
      for (int x = 0; x < R; ++x) acc += vplkit::texel_solid_angle<float>(x, y, R);
    benchmark::DoNotOptimize(acc);
  }
  state.SetItemsProcessed(std::int64_t(state.iterations()) * R * R);
}

void BM_texel_is_valid(benchmark::State& state) {
  const int R = int(state.range(0));
  int acc = 0;
  for (auto _ : state) {
    for (int y = 0; y < R; ++y)
      for (int x = 0; x < R; ++x) acc += vplkit::texel_is_valid(x, y, R) ? 1 : 0;
    benchmark::DoNotOptimize(acc);
  }
  state.SetItemsProcessed(std::int64_t(state.iterations()) * R * R);
}

}  // namespace

BENCHMARK(BM_paraboloid_from_direction)->Apply(vplkit_bench::standard);
BENCHMARK(BM_direction_to_texel)->Arg(256)->Apply(vplkit_bench::standard);
BENCHMARK(BM_texel_to_direction)->Arg(256)->Apply(vplkit_bench::standard);
BENCHMARK(BM_texel_solid_angle)->Arg(64)->Arg(512)->Apply(vplkit_bench::standard);
BENCHMARK(BM_texel_is_valid)->Arg(512)->Apply(vplkit_bench::standard);

VPLKIT_BENCH_MAIN()
