// SPDX-License-Identifier: MIT
#pragma once
// Shared by the bench_<area>.cpp programs (not a program itself: only *.cpp files are globbed).
//
//  - VPLKIT_BENCH_MAIN(): Google Benchmark's main with --benchmark_min_time=0.05 as the default
//    (anything on the command line still overrides it: flags are read in order, last wins), so a
//    whole program runs in seconds on two cores.
//  - standard(b): every benchmark also reports a `min` aggregate over its repetitions (next to
//    the built-in mean / median / stddev / cv) when run with --benchmark_repetitions=N.
//  - Fixed inputs: uniform numbers on the library's 2^-24 grid from a fixed-seed std::mt19937,
//    unit directions, and the scenes: the synthetic room of tests/support/synthetic_scene.hpp
//    (24 triangles, exact brute-force ray casting), its DPRSMs, G-buffers and voxel grids, and a
//    denser mesh (the room tessellated plus spheres, ~5k triangles) for voxelisation; (gather
//    point, VPL) pairs of the room and paraboloid-map weights with holes.
// Everything is T = float: the type a renderer stores and the GPU mirror computes in.
#include <synthetic_scene.hpp>

#include <vplkit/core/gather_point.hpp>
#include <vplkit/core/vector.hpp>
#include <vplkit/paraboloid/texel_grid.hpp>
#include <vplkit/sampling/rng.hpp>
#include <vplkit/visibility/voxel_grid.hpp>
#include <vplkit/visibility/voxelize.hpp>
#include <vplkit/vpl/dprsm_view.hpp>
#include <vplkit/vpl/vpl.hpp>

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <random>
#include <utility>
#include <vector>

namespace vplkit_bench {

using v2f = vplkit::vec2<float>;
using v3f = vplkit::vec3<float>;
using scene_t = vplkit_test::synthetic_scene<float>;

// Batch of precomputed inputs per iteration for functions that take a few ns: the loop overhead
// of the benchmark itself (~1 ns) would otherwise dominate. Items processed = batch * iterations.
constexpr std::size_t kBatch = 4096;  // power of two

inline double min_of(const std::vector<double>& v) {
  return v.empty() ? 0.0 : *std::min_element(v.begin(), v.end());
}

inline void standard(benchmark::internal::Benchmark* b) { b->ComputeStatistics("min", &min_of); }

// The timed loop of a per-value benchmark: `value(i)` for the n precomputed inputs of every
// iteration, summed into an accumulator the optimiser must keep (DoNotOptimize once per batch, so
// the barrier costs nothing per value). `value` is a lambda, inlined: the loop is what a hand-
// written one would be. Items processed = n * iterations. Returns the sum of every value.
template <class Acc = float, class Value>
Acc run_items(benchmark::State& state, std::size_t n, Value&& value) {
  Acc acc = 0;
  for (auto _ : state) {
    for (std::size_t i = 0; i < n; ++i) acc += value(i);
    benchmark::DoNotOptimize(acc);
  }
  state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(n));
  return acc;
}

template <class Acc = float, class Value>
Acc run_batch(benchmark::State& state, Value&& value) {
  return run_items<Acc>(state, kBatch, std::forward<Value>(value));
}

// The timed loop of a per-gather-point benchmark: `estimate(gp, rng)` on `per_iteration` of the
// points per iteration (cycled), each with its own stream of seed 99. Items processed =
// per_iteration * items_per_point * iterations.
template <class Estimate>
void run_gather_points(benchmark::State& state, const std::vector<vplkit::gather_point<float>>& pts,
                       int per_iteration, std::int64_t items_per_point, Estimate&& estimate) {
  std::size_t next = 0;
  std::uint32_t stream = 0;
  float acc = 0;
  for (auto _ : state) {
    for (int k = 0; k < per_iteration; ++k) {
      vplkit::counter_rng rng = vplkit::make_counter_rng(99u, stream++);
      acc += estimate(pts[next], rng).y;
      next = next + 1 == pts.size() ? 0 : next + 1;
    }
    benchmark::DoNotOptimize(acc);
  }
  state.SetItemsProcessed(std::int64_t(state.iterations()) * per_iteration * items_per_point);
}

inline int run_main(int argc, char** argv) {
  static char default_min_time[] = "--benchmark_min_time=0.05";
  std::vector<char*> args;
  args.push_back(argv[0]);
  args.push_back(default_min_time);
  for (int i = 1; i < argc; ++i) args.push_back(argv[i]);
  args.push_back(nullptr);
  int n = int(args.size()) - 1;
  benchmark::Initialize(&n, args.data());
  if (benchmark::ReportUnrecognizedArguments(n, args.data())) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

#define VPLKIT_BENCH_MAIN() \
  int main(int argc, char** argv) { return vplkit_bench::run_main(argc, argv); }

// ---- fixed random inputs --------------------------------------------------------------------------
// n numbers in [0, 1) on the 2^-24 grid (the RNG convention of docs/math.md section 6).
inline std::vector<float> uniforms(std::size_t n, std::uint32_t seed) {
  std::mt19937 g(seed);
  std::vector<float> u(n);
  for (float& x : u) x = float(g() >> 8) * 0x1p-24f;
  return u;
}

inline std::vector<v2f> uniform_pairs(std::size_t n, std::uint32_t seed) {
  const std::vector<float> u = uniforms(2 * n, seed);
  std::vector<v2f> out(n);
  for (std::size_t i = 0; i < n; ++i) out[i] = v2f(u[2 * i], u[2 * i + 1]);
  return out;
}

// Unit directions uniform on the sphere (normalised Gaussians).
inline std::vector<v3f> unit_directions(std::size_t n, std::uint32_t seed) {
  std::mt19937 g(seed);
  std::normal_distribution<float> nd(0.0f, 1.0f);
  std::vector<v3f> out(n);
  for (v3f& d : out) {
    do d = v3f(nd(g), nd(g), nd(g));
    while (glm::dot(d, d) < 1e-6f);
    d = glm::normalize(d);
  }
  return out;
}

// ---- the synthetic room and what is built from it ------------------------------------------------
inline const scene_t& room() {
  static const scene_t* s = new scene_t();
  return *s;
}

// What make(key) returns, built on the first call with that key and kept for the program's life.
// One cache per call site (Make is that site's lambda).
template <class V, class Make>
const V& built_once(int key, Make make) {
  static auto* cache = new std::map<int, std::unique_ptr<V>>();
  auto& p = (*cache)[key];
  if (!p) p.reset(new V(make(key)));
  return *p;
}

inline const vplkit_test::dprsm_data<float>& room_dprsm(int R) {
  return built_once<vplkit_test::dprsm_data<float>>(R, [](int r) { return room().make_dprsm(r); });
}

// Square W x W G-buffer of the room's camera (every pixel hits a surface).
inline const vplkit_test::gbuffer_data<float>& room_gbuffer(int W) {
  return built_once<vplkit_test::gbuffer_data<float>>(W, [](int w) { return room().make_gbuffer(w, w); });
}

inline const vplkit::voxel_grid<float>& room_grid(int res) {
  return built_once<vplkit::voxel_grid<float>>(res, [](int r) { return room().make_voxel_grid(r); });
}

// The valid gather points of a room G-buffer, in pixel order.
inline std::vector<vplkit::gather_point<float>> room_gather_points(int W) {
  const auto gb = room_gbuffer(W).view();
  std::vector<vplkit::gather_point<float>> out;
  for (int p = 0; p < gb.pixel_count(); ++p)
    if (vplkit::gather_point_valid(gb.at(p))) out.push_back(gb.at(p));
  return out;
}

// kBatch (gather point, VPL) pairs of the room at W = R = 64, drawn with `seed`: gather points
// uniformly, VPLs among the texels that carry flux.
struct vpl_pairs {
  std::vector<vplkit::gather_point<float>> gp;
  std::vector<vplkit::vpl<float>> v;
  explicit vpl_pairs(std::uint32_t seed) {
    const auto view = room_dprsm(64).view();
    const auto points = room_gather_points(64);
    std::vector<vplkit::vpl<float>> vpls;
    for (int t = 0; t < view.texel_count(); ++t) {
      const auto x = view.vpl_at(t);
      if (x.flux.x > 0 || x.flux.y > 0 || x.flux.z > 0) vpls.push_back(x);
    }
    std::mt19937 g(seed);
    for (std::size_t i = 0; i < kBatch; ++i) {
      gp.push_back(points[g() % points.size()]);
      v.push_back(vpls[g() % vpls.size()]);
    }
  }
};

// Weights of a 2 x R x R paraboloid map (exponential, + 1e-3) with `holes_percent` % of the valid
// texels left at 0, fixed seed per (R, holes_percent).
inline std::vector<float> holey_weights(int R, int holes_percent) {
  std::mt19937 g(std::uint32_t(R * 100 + holes_percent));
  std::exponential_distribution<float> ex(1.0f);
  std::uniform_int_distribution<int> pct(0, 99);
  std::vector<float> w(std::size_t(vplkit::texel_count(R)), 0.0f);
  for (int face = 0; face < 2; ++face)
    for (int y = 0; y < R; ++y)
      for (int x = 0; x < R; ++x) {
        const float v = ex(g) + 1e-3f;
        if (!vplkit::texel_is_valid(x, y, R) || pct(g) < holes_percent) continue;
        w[std::size_t(vplkit::texel_index(face, x, y, R))] = v;
      }
  return w;
}

// ---- a denser mesh for voxelisation ---------------------------------------------------------------
struct mesh {
  std::vector<v3f> positions;
  std::vector<std::uint32_t> indices;
  std::size_t triangle_count() const { return indices.size() / 3; }
};

// The room's six walls as n x n grids of quads (2 n^2 triangles each), the floating block of the
// synthetic scene (12 triangles) and two UV spheres of s x s quads: 12 n^2 + 12 + 4 s^2 triangles.
inline mesh dense_mesh(int n = 16, int s = 24) {
  mesh m;
  auto grid = [&](v3f origin, v3f du, v3f dv, int k) {
    const std::uint32_t base = std::uint32_t(m.positions.size());
    for (int j = 0; j <= k; ++j)
      for (int i = 0; i <= k; ++i) m.positions.push_back(origin + du * (float(i) / float(k)) + dv * (float(j) / float(k)));
    for (int j = 0; j < k; ++j)
      for (int i = 0; i < k; ++i) {
        const std::uint32_t a = base + std::uint32_t(j * (k + 1) + i), b = a + 1, c = a + std::uint32_t(k + 1), d = c + 1;
        m.indices.insert(m.indices.end(), {a, b, d, a, d, c});
      }
  };
  const v3f lo = scene_t::room_min(), hi = scene_t::room_max(), e = hi - lo;
  grid(lo, v3f(e.x, 0, 0), v3f(0, 0, e.z), n);                       // floor
  grid(v3f(lo.x, hi.y, lo.z), v3f(e.x, 0, 0), v3f(0, 0, e.z), n);    // ceiling
  grid(lo, v3f(0, e.y, 0), v3f(0, 0, e.z), n);                       // x = min
  grid(v3f(hi.x, lo.y, lo.z), v3f(0, e.y, 0), v3f(0, 0, e.z), n);    // x = max
  grid(lo, v3f(e.x, 0, 0), v3f(0, e.y, 0), n);                       // z = min
  grid(v3f(lo.x, lo.y, hi.z), v3f(e.x, 0, 0), v3f(0, e.y, 0), n);    // z = max
  const scene_t& r = room();
  const std::uint32_t base = std::uint32_t(m.positions.size());
  for (std::size_t i = 0; i < r.indices.size(); ++i)
    if (i >= 36) {  // the block: the scene's triangles 12..23 (the first 12 are the room's walls)
      m.positions.push_back(r.positions[r.indices[i]]);
      m.indices.push_back(base + std::uint32_t(i - 36));
    }
  auto sphere = [&](v3f c, float radius) {
    const std::uint32_t b0 = std::uint32_t(m.positions.size());
    for (int j = 0; j <= s; ++j)
      for (int i = 0; i <= s; ++i) {
        const float th = 3.14159265f * float(j) / float(s), ph = 6.2831853f * float(i) / float(s);
        m.positions.push_back(c + radius * v3f(std::sin(th) * std::cos(ph), std::cos(th), std::sin(th) * std::sin(ph)));
      }
    for (int j = 0; j < s; ++j)
      for (int i = 0; i < s; ++i) {
        const std::uint32_t a = b0 + std::uint32_t(j * (s + 1) + i), b = a + 1, cc = a + std::uint32_t(s + 1), d = cc + 1;
        m.indices.insert(m.indices.end(), {a, b, d, a, d, cc});
      }
  };
  sphere(v3f(1.0f, 0.6f, 1.0f), 0.6f);
  sphere(v3f(-1.2f, 2.0f, 1.2f), 0.5f);
  return m;
}

}  // namespace vplkit_bench
