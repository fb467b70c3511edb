// SPDX-License-Identifier: MIT
// Voxel visibility (include/vplkit/visibility), T = float:
//  - triangle_box_overlap (the SAT of the voxeliser), random small triangles against unit boxes;
//  - voxelize: the dense mesh of bench_common.hpp (the room tessellated + block + 2 spheres,
//    5388 triangles) into a fresh grid at 64^3 and 128^3, per triangle;
//  - dda_first_hit per ray in the synthetic room's grid (24 triangles voxelised, mostly empty):
//    "short" rays stop after 4 voxel lengths, "long" rays run until they hit a wall;
//  - voxel_visible (one-sided, the paper's) and voxel_visible_two_sided per query between a gather
//    point of a 64 x 64 G-buffer and a VPL of the R = 64 DPRSM;
//  - the triangle voxel grid: voxelize_triangles of the dense mesh (counters: entries, bytes of
//    the whole grid and of the occupancy alone), triangle_voxel_visible on the same queries as the
//    two-sided test, triangle_voxel_first_hit on the same rays as dda_first_hit ("long"), each
//    with the brick level (bricks:1, empty 4^3 bricks jumped) and without it (bricks:0).
#include "bench_common.hpp"

#include <vplkit/visibility/dda.hpp>
#include <vplkit/visibility/triangle_box_overlap.hpp>
#include <vplkit/visibility/voxel_grid.hpp>
#include <vplkit/visibility/voxel_visible.hpp>
#include <vplkit/visibility/triangle_voxel_query.hpp>
#include <vplkit/visibility/voxelize.hpp>
#include <vplkit/visibility/voxelize_triangles.hpp>
#include <vplkit/vpl/dprsm_view.hpp>

namespace {

using namespace vplkit_bench;

void BM_triangle_box_overlap(benchmark::State& state) {
  const std::vector<float> u = uniforms(9 * kBatch, 51u);
  std::vector<v3f> a(kBatch), b(kBatch), c(kBatch);
  for (std::size_t i = 0; i < kBatch; ++i) {
    // Triangles of size ~1 around points within 1.5 of the box: about half overlap.
    const v3f o(3 * u[9 * i] - 1.5f, 3 * u[9 * i + 1] - 1.5f, 3 * u[9 * i + 2] - 1.5f);
    a[i] = o;
    b[i] = o + v3f(u[9 * i + 3], u[9 * i + 4], u[9 * i + 5]) - 0.5f;
    c[i] = o + v3f(u[9 * i + 6], u[9 * i + 7], u[9 * i + 8]) - 0.5f;
  }
  run_batch<int>(state, [&](std::size_t i) { return vplkit::triangle_box_overlap(v3f(0), v3f(0.5f), a[i], b[i], c[i]) ? 1 : 0; });
}

const mesh& dense() {
  static const mesh* m = new mesh(dense_mesh());
  return *m;
}

void BM_voxelize_dense_mesh(benchmark::State& state) {
  const int res = int(state.range(0));
  const mesh& m = dense();
  const auto bounds = vplkit::fit_voxel_bounds(m.positions.data(), m.positions.size());
  vplkit::voxel_grid<float> grid(bounds.min, bounds.max, vplkit::ivec3(res));
  for (auto _ : state) {
    grid.clear_all();
    vplkit::voxelize(grid, m.positions.data(), m.positions.size(), m.indices.data(), m.indices.size());
    benchmark::DoNotOptimize(grid.words().data());
    benchmark::ClobberMemory();
  }
  state.counters["triangles"] = double(m.triangle_count());
  state.counters["occupied"] = double(grid.count());
  state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(m.triangle_count()));
}

// Rays from random points inside the room (away from the walls and the block's shell) in random
// directions.
struct rays_t {
  std::vector<v3f> o, d;
  explicit rays_t(const vplkit::voxel_grid<float>& g) {
    const std::vector<v3f> dirs = unit_directions(kBatch, 52u);
    std::mt19937 gen(53u);
    std::uniform_real_distribution<float> ux(-1.8f, 1.8f), uy(0.2f, 2.8f);
    const auto view = g.view();
    while (o.size() < kBatch) {
      const v3f p(ux(gen), uy(gen), ux(gen));
      if (vplkit::voxel_test(view, vplkit::world_to_voxel(view, p))) continue;
      o.push_back(p);
      d.push_back(dirs[o.size() - 1]);
    }
  }
};

void BM_dda_first_hit(benchmark::State& state) {
  const int res = int(state.range(0));
  const bool is_short = state.range(1) != 0;
  const auto& grid = room_grid(res);
  const auto view = grid.view();
  const rays_t rays(grid);
  const float t_max = is_short ? 4.0f * grid.voxel_length() : std::numeric_limits<float>::infinity();
  int hits = 0;
  float acc = 0;
  for (auto _ : state) {
    for (std::size_t i = 0; i < kBatch; ++i) {
      const auto h = vplkit::dda_first_hit(view, rays.o[i], rays.d[i], t_max);
      hits += h.hit ? 1 : 0;
      acc += h.t;
    }
    benchmark::DoNotOptimize(acc);
  }
  state.counters["hit_fraction"] = double(hits) / double(std::int64_t(state.iterations()) * std::int64_t(kBatch));
  state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(kBatch));
}

const vpl_pairs& queries() {
  static const vpl_pairs* q = new vpl_pairs(54u);
  return *q;
}

void BM_voxel_visible_one_sided(benchmark::State& state) {
  const auto view = room_grid(int(state.range(0))).view();
  const auto& q = queries();
  const int visible = run_batch<int>(state, [&](std::size_t i) {
    return vplkit::voxel_visible(view, q.gp[i].position, q.gp[i].normal, q.v[i].position) ? 1 : 0;
  });
  state.counters["visible_fraction"] = double(visible) / double(std::int64_t(state.iterations()) * std::int64_t(kBatch));
}

void BM_voxel_visible_two_sided(benchmark::State& state) {
  const auto view = room_grid(int(state.range(0))).view();
  const auto& q = queries();
  const int visible = run_batch<int>(state, [&](std::size_t i) {
    return vplkit::voxel_visible_two_sided(view, q.gp[i].position, q.gp[i].normal, q.v[i].position, q.v[i].normal) ? 1 : 0;
  });
  state.counters["visible_fraction"] = double(visible) / double(std::int64_t(state.iterations()) * std::int64_t(kBatch));
}

void BM_voxelize_triangles_dense_mesh(benchmark::State& state) {
  const int res = int(state.range(0));
  const mesh& m = dense();
  const auto bounds = vplkit::fit_voxel_bounds(m.positions.data(), m.positions.size());
  std::size_t entries = 0, bytes = 0, occupancy_bytes = 0;
  for (auto _ : state) {
    const auto g = vplkit::voxelize_triangles(bounds.min, bounds.max, vplkit::ivec3(res), m.positions.data(),
                                              m.positions.size(), m.indices.data(), m.indices.size());
    entries = g.entries().size();
    bytes = g.memory_bytes();
    occupancy_bytes = 4 * g.occupancy().word_count();
    benchmark::DoNotOptimize(g.entries().data());
  }
  state.counters["triangles"] = double(m.triangle_count());
  state.counters["entries"] = double(entries);
  state.counters["bytes"] = double(bytes);
  state.counters["occupancy_bytes"] = double(occupancy_bytes);
  state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(m.triangle_count()));
}

// The synthetic room's triangle voxel grid, over the bounds of room_grid (the same occupancy).
const vplkit::triangle_voxel_grid<float>& room_triangle_grid(int res) {
  static auto* cache = new std::map<int, std::unique_ptr<vplkit::triangle_voxel_grid<float>>>();
  auto& p = (*cache)[res];
  if (!p) {
    const auto& s = room();
    const auto& occ = room_grid(res);
    p.reset(new vplkit::triangle_voxel_grid<float>(vplkit::voxelize_triangles(
        occ.bounds_min(), occ.bounds_max(), occ.resolution(), s.positions.data(), s.positions.size(),
        s.indices.data(), s.indices.size())));
  }
  return *p;
}

// range(1) = 0: without the brick level (every brick stepped through), 1: jumping empty bricks.
void BM_triangle_voxel_visible(benchmark::State& state) {
  const auto& grid = room_triangle_grid(int(state.range(0)));
  auto view = grid.view();
  if (state.range(1) == 0) view.bricks = nullptr;
  const auto& q = queries();
  int acc = 0;
  for (auto _ : state) {
    for (std::size_t i = 0; i < kBatch; ++i) acc += vplkit::triangle_voxel_visible(view, q.gp[i].position, q.v[i].position) ? 1 : 0;
    benchmark::DoNotOptimize(acc);
  }
  state.counters["visible_fraction"] = double(acc) / double(std::int64_t(state.iterations()) * std::int64_t(kBatch));
  state.counters["bytes"] = double(grid.memory_bytes());
  state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(kBatch));
}

void BM_triangle_voxel_first_hit(benchmark::State& state) {
  const int res = int(state.range(0));
  auto view = room_triangle_grid(res).view();
  if (state.range(1) == 0) view.bricks = nullptr;
  const rays_t rays(room_grid(res));
  int hits = 0;
  float acc = 0;
  for (auto _ : state) {
    for (std::size_t i = 0; i < kBatch; ++i) {
      const auto h = vplkit::triangle_voxel_first_hit(view, rays.o[i], rays.d[i]);
      hits += h.hit ? 1 : 0;
      acc += h.t;
    }
    benchmark::DoNotOptimize(acc);
  }
  state.counters["hit_fraction"] = double(hits) / double(std::int64_t(state.iterations()) * std::int64_t(kBatch));
  state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(kBatch));
}

}  // namespace

BENCHMARK(BM_triangle_box_overlap)->Apply(vplkit_bench::standard);
BENCHMARK(BM_voxelize_dense_mesh)->Arg(64)->Arg(128)->Unit(benchmark::kMillisecond)->Apply(vplkit_bench::standard);
BENCHMARK(BM_dda_first_hit)->ArgNames({"res", "short"})->Args({64, 1})->Args({64, 0})->Args({128, 1})->Args({128, 0})->Apply(vplkit_bench::standard);
BENCHMARK(BM_voxel_visible_one_sided)->ArgName("res")->Arg(64)->Arg(128)->Apply(vplkit_bench::standard);
BENCHMARK(BM_voxel_visible_two_sided)->ArgName("res")->Arg(64)->Arg(128)->Apply(vplkit_bench::standard);
BENCHMARK(BM_voxelize_triangles_dense_mesh)->Arg(64)->Arg(128)->Unit(benchmark::kMillisecond)->Apply(vplkit_bench::standard);
BENCHMARK(BM_triangle_voxel_visible)->ArgNames({"res", "bricks"})->ArgsProduct({{64, 128}, {0, 1}})->Apply(vplkit_bench::standard);
BENCHMARK(BM_triangle_voxel_first_hit)->ArgNames({"res", "bricks"})->ArgsProduct({{64, 128}, {0, 1}})->Apply(vplkit_bench::standard);

VPLKIT_BENCH_MAIN()
