// SPDX-License-Identifier: MIT
// The C++ BVH (include/vplkit/visibility/bvh_*.hpp) against Embree 3 (libembree-dev) on one
// procedural scene of ~100k triangles: a rolling terrain (150 x 150 quads), 64 UV spheres
// (20 x 20 quads each) standing on it and a closed box around everything, 97k triangles in all.
//  - build: vplkit::build_bvh (single-threaded binned SAH) against rtcCommitScene with
//    "threads=1" and with Embree's default thread pool (all cores), medium quality, both
//    including the copy of the vertices;
//  - closest hit: rays from random points inside the box in random directions,
//    bvh_closest_hit against rtcIntersect1 (robust and default scene flags), one thread;
//  - occlusion: segments between two random points inside the box (shadow rays),
//    bvh_occluded(o, q - o, 0, 1) against rtcOccluded1, one thread.
// Items per second = rays per second. Compare vplkit against Embree within one run of this
// program (docs/api/bvh.md has a table). Counters: nodes and depth of vplkit's tree, and the mean
// nodes visited and triangles tested per query.
#include "bench_common.hpp"

#include <bvh_test_scenes.hpp>
#include <embree_scene.hpp>

#include <vplkit/visibility/bvh_build.hpp>
#include <vplkit/visibility/bvh_traverse.hpp>

namespace {

using namespace vplkit_bench;
using vplkit_test::tri_mesh;
using vplkit_test::v3d;

constexpr std::size_t kRays = 1 << 14;

const tri_mesh& scene() {
  static const tri_mesh* m = [] {
    auto* s = new tri_mesh;
    const int n = 150;  // terrain: n x n quads over [-10, 10]^2, heights up to 0.8
    const auto base = std::uint32_t(s->positions.size());
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) {
        const double x = -10.0 + 20.0 * i / n, z = -10.0 + 20.0 * j / n;
        s->positions.push_back(v3f(v3d(x, 0.4 * std::sin(0.7 * x) * std::cos(0.5 * z) + 0.1 * std::sin(3.1 * x + 2.3 * z), z)));
      }
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const std::uint32_t a = base + std::uint32_t(j * (n + 1) + i), b = a + 1, c = a + std::uint32_t(n + 2), d = c - 1;
        s->indices.insert(s->indices.end(), {a, b, c, a, c, d});
      }
    std::mt19937 g(91u);
    std::uniform_real_distribution<double> u(-9.0, 9.0), r(0.2, 0.9);
    for (int k = 0; k < 64; ++k) {  // UV spheres: 20 x 20 quads, shared vertices
      const v3d c(u(g), 0.0, u(g));
      const double radius = r(g);
      const auto sb = std::uint32_t(s->positions.size());
      const int m = 20;
      for (int j = 0; j <= m; ++j)
        for (int i = 0; i <= m; ++i) {
          const double th = 3.141592653589793 * j / m, ph = 6.283185307179586 * i / m;
          s->positions.push_back(
              v3f(c + v3d(0.0, radius + 0.3, 0.0) + radius * v3d(std::sin(th) * std::cos(ph), std::cos(th), std::sin(th) * std::sin(ph))));
        }
      for (int j = 0; j < m; ++j)
        for (int i = 0; i < m; ++i) {
          const std::uint32_t a = sb + std::uint32_t(j * (m + 1) + i), b = a + 1, cc = a + std::uint32_t(m + 2), d = cc - 1;
          s->indices.insert(s->indices.end(), {a, b, cc, a, cc, d});
        }
    }
    s->box(v3d(0.0, 3.0, 0.0), v3d(10.5, 4.0, 10.5), glm::dmat3(1.0), 8, true);
    return s;
  }();
  return *m;
}

const vplkit::bvh<float>& vplkit_bvh() {
  static const auto* b = new vplkit::bvh<float>(
      vplkit::build_bvh(scene().positions.data(), scene().positions.size(), scene().indices.data(), scene().indices.size()));
  return *b;
}

const vplkit_test::embree_device& single_thread_device() {
  static const auto* d = new vplkit_test::embree_device("threads=1");
  return *d;
}

const vplkit_test::embree_scene& embree(bool robust) {
  static const auto* a = new vplkit_test::embree_scene(single_thread_device(), scene().positions.data(), scene().positions.size(),
                                                       scene().indices.data(), scene().indices.size(), false);
  static const auto* b = new vplkit_test::embree_scene(single_thread_device(), scene().positions.data(), scene().positions.size(),
                                                       scene().indices.data(), scene().indices.size(), true);
  return robust ? *b : *a;
}

// Points inside the box (above the floor, below the lid), and random directions.
struct queries {
  std::vector<v3f> o, d, q;
  queries() {
    const std::vector<v3f> dirs = unit_directions(kRays, 93u);
    std::mt19937 g(94u);
    std::uniform_real_distribution<float> ux(-9.5f, 9.5f), uy(0.5f, 6.5f);
    for (std::size_t i = 0; i < kRays; ++i) {
      o.push_back(v3f(ux(g), uy(g), ux(g)));
      d.push_back(dirs[i]);
      q.push_back(v3f(ux(g), uy(g), ux(g)));
    }
  }
};
const queries& rays() {
  static const queries* r = new queries();
  return *r;
}

void BM_build_vplkit(benchmark::State& state) {
  const tri_mesh& m = scene();
  std::size_t nodes = 0;
  int depth = 0;
  for (auto _ : state) {
    const auto b = vplkit::build_bvh(m.positions.data(), m.positions.size(), m.indices.data(), m.indices.size());
    nodes = b.node_count();
    depth = b.depth();
    benchmark::DoNotOptimize(b.nodes().data());
  }
  state.counters["triangles"] = double(m.triangle_count());
  state.counters["nodes"] = double(nodes);
  state.counters["depth"] = double(depth);
  state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(m.triangle_count()));
}

// Arg: Embree's worker threads (1, or 0 for its default: every core).
void BM_build_embree(benchmark::State& state) {
  const tri_mesh& m = scene();
  const vplkit_test::embree_device all_cores;
  const vplkit_test::embree_device& device = state.range(0) == 1 ? single_thread_device() : all_cores;
  for (auto _ : state) {
    const vplkit_test::embree_scene s(device, m.positions.data(), m.positions.size(), m.indices.data(), m.indices.size(), false);
    benchmark::DoNotOptimize(&s);
  }
  state.counters["triangles"] = double(m.triangle_count());
  state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(m.triangle_count()));
}

void BM_closest_hit_vplkit(benchmark::State& state) {
  const auto view = vplkit_bvh().view();
  const queries& r = rays();
  vplkit::bvh_traversal_counts counts;
  for (std::size_t i = 0; i < kRays; ++i) vplkit::bvh_closest_hit(view, r.o[i], r.d[i], 0.0f, INFINITY, &counts);
  run_items<std::uint64_t>(state, kRays, [&](std::size_t i) { return vplkit::bvh_closest_hit(view, r.o[i], r.d[i]).triangle; });
  state.counters["nodes_per_ray"] = double(counts.nodes) / double(kRays);
  state.counters["triangles_per_ray"] = double(counts.triangles) / double(kRays);
}

// Arg: 1 for RTC_SCENE_FLAG_ROBUST (watertight, as vplkit), 0 for Embree's default flags.
void BM_closest_hit_embree(benchmark::State& state) {
  const auto& e = embree(state.range(0) == 1);
  const queries& r = rays();
  run_items<std::uint64_t>(state, kRays, [&](std::size_t i) { return e.intersect(r.o[i], r.d[i]).triangle; });
}

void BM_occluded_vplkit(benchmark::State& state) {
  const auto view = vplkit_bvh().view();
  const queries& r = rays();
  vplkit::bvh_traversal_counts counts;
  for (std::size_t i = 0; i < kRays; ++i) vplkit::bvh_occluded(view, r.o[i], r.q[i] - r.o[i], 0.0f, 1.0f, &counts);
  run_items<std::uint64_t>(state, kRays, [&](std::size_t i) { return vplkit::bvh_occluded(view, r.o[i], r.q[i] - r.o[i], 0.0f, 1.0f); });
  state.counters["nodes_per_ray"] = double(counts.nodes) / double(kRays);
  state.counters["triangles_per_ray"] = double(counts.triangles) / double(kRays);
}

void BM_occluded_embree(benchmark::State& state) {
  const auto& e = embree(state.range(0) == 1);
  const queries& r = rays();
  run_items<std::uint64_t>(state, kRays, [&](std::size_t i) { return e.occluded(r.o[i], r.q[i] - r.o[i], 0.0f, 1.0f); });
}

}  // namespace

BENCHMARK(BM_build_vplkit)->Unit(benchmark::kMillisecond)->Apply(vplkit_bench::standard);
BENCHMARK(BM_build_embree)->ArgName("threads")->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond)->Apply(vplkit_bench::standard);
BENCHMARK(BM_closest_hit_vplkit)->Unit(benchmark::kMillisecond)->Apply(vplkit_bench::standard);
BENCHMARK(BM_closest_hit_embree)->ArgName("robust")->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond)->Apply(vplkit_bench::standard);
BENCHMARK(BM_occluded_vplkit)->Unit(benchmark::kMillisecond)->Apply(vplkit_bench::standard);
BENCHMARK(BM_occluded_embree)->ArgName("robust")->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond)->Apply(vplkit_bench::standard);

VPLKIT_BENCH_MAIN()
