// SPDX-License-Identifier: MIT
// What the clamp compensation's near-surface test costs per gather point (include/vplkit/
// visibility/triangle_voxel_near.hpp): triangle_voxel_surface_within on every gather point of a
// vplrender frame (`--backend cpu`, 64 x 64 pixels, 64^3 voxels, the default dmin and the
// compensation's plane tolerance, as vplkit::clamp_compensation_may_add asks it), against
//  - scan: triangle_voxel_surface_within_scan, the same answers with every voxel of the box looked
//    up on its own and every listed triangle's plane asked (what the test was before);
//  - lookups: the scan's occupancy lookups alone (voxel_occupied_index on every voxel of the box),
//    what the scan spends before any plane.
// Items = gather points. Counters, per point: voxels in the box, occupied ones, the triangles
// they list (what the scan asks at most), those of the occupied voxels whose triangles share one
// plane (one question each now), and the share of points answered true (the pixels the
// compensation traces). Run with --benchmark_repetitions=N for the `min` aggregate (the least
// disturbed on a shared machine).
// Scenes: cornell and open (built in); Sponza when VPLKIT_BENCH_SPONZA names its OBJ file (the
// camera and light of docs/results.md). The G-buffer is rasterised once per scene (headless GL).
#include <cli/options.hpp>
#include <cli/render_options.hpp>
#include <cli/scene_setup.hpp>
#include <render/frame_buffers.hpp>
#include <render/pipeline.hpp>

#include <headless_gl/context.hpp>

#include <vplkit/core/gather_point.hpp>
#include <vplkit/visibility/triangle_voxel_near.hpp>
#include <vplkit/vpl/vpl.hpp>

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <iostream>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace {

using vec3 = vplkit::vec3<float>;

struct near_queries {
  vplrender::frame_buffers buffers;
  std::vector<vec3> x;  // the valid gather points' positions
  float reach = 0.0f;   // |dmin|
};

std::vector<std::string> scene_args(const std::string& name) {
  if (name != "sponza") return {"bench", "--scene", name};
  const char* path = std::getenv("VPLKIT_BENCH_SPONZA");
  return {"bench", "--scene", path != nullptr ? path : "", "--light", "0,11.5,0", "--camera",
          "-15,2.5,0,5,4.5,0,0,1,0,60"};
}

const near_queries& queries(const std::string& name) {
  static auto* cache = new std::map<std::string, std::unique_ptr<near_queries>>();
  auto& q = (*cache)[name];
  if (!q) {
    std::vector<std::string> args = scene_args(name);
    args.insert(args.end(), {"--method", "global", "--size", "64x64", "--vpls", "16", "--dprsm", "128", "--voxels",
                             "64", "--backend", "cpu"});
    const vplrender::parse_result parsed = vplrender::parse_command_line(args);
    const vplrender::prepared_scene sc = vplrender::prepare_scene(parsed.opts);
    const vplrender::frame_settings f = vplrender::make_frame_settings(parsed.opts);
    const vplrender::render_settings s = vplrender::make_render_settings(parsed.opts, sc.s);
    vplrender::stage_timer timer;
    nlohmann::json details;
    q.reset(new near_queries{vplrender::prepare_buffers(sc.s, f, timer, details), {}, std::abs(s.dmin)});
    const vplkit::gbuffer_view<float> g = q->buffers.gbuf.view();
    for (int p = 0; p < g.width * g.height; ++p) {
      const vplkit::gather_point<float> gp = g.at(p);
      if (vplkit::gather_point_valid(gp)) q->x.push_back(gp.position);
    }
    if (q->x.empty()) throw std::runtime_error("bench_triangle_voxel_near: no gather point in " + name);
  }
  return *q;
}

double min_of(const std::vector<double>& v) { return v.empty() ? 0.0 : *std::min_element(v.begin(), v.end()); }

float tolerance(vec3 x) { return vplkit::vpl_coincidence_tolerance(x, x) / 4.0f; }

// The box's occupancy lookups alone (the loop of triangle_voxel_surface_within without the planes).
int occupied_in_box(const vplkit::triangle_voxel_view<float>& g, vec3 x, float reach, int* voxels,
                    double* stats = nullptr) {
  const float slack = 1e-3f;
  const vec3 c = vplkit::world_to_voxel_coord(g.grid, x);
  const vec3 r = vec3(reach / vplkit::voxel_size(g.grid));
  const vec3 lo = c - r - vec3(slack), hi = c + r + vec3(slack);
  const glm::ivec3 a(vplkit::voxel_floor_to_int(lo.x), vplkit::voxel_floor_to_int(lo.y), vplkit::voxel_floor_to_int(lo.z));
  const glm::ivec3 b(vplkit::voxel_floor_to_int(hi.x), vplkit::voxel_floor_to_int(hi.y), vplkit::voxel_floor_to_int(hi.z));
  int n = 0;
  *voxels = (b.x - a.x + 1) * (b.y - a.y + 1) * (b.z - a.z + 1);
  for (int z = a.z; z <= b.z; ++z)
    for (int y = a.y; y <= b.y; ++y)
      for (int xi = a.x; xi <= b.x; ++xi) {
        const std::int64_t o = vplkit::voxel_occupied_index(g.grid, g.rank, glm::ivec3(xi, y, z));
        if (o < 0) continue;
        ++n;
        if (stats) {
          stats[0] += g.offsets[o + 1] - g.offsets[o];
          stats[1] += vplkit::voxel_plane_is_several(g.planes[o]) ? 0 : 1;
        }
      }
  return n;
}

template <class Test>
void run(benchmark::State& state, const std::string& name, Test&& test) {
  const near_queries& q = queries(name);
  const vplkit::triangle_voxel_view<float> g = q.buffers.grid.view();
  std::int64_t trues = 0;
  for (auto _ : state) {
    std::int64_t t = 0;
    for (const vec3& x : q.x) t += test(g, x, q.reach) ? 1 : 0;
    benchmark::DoNotOptimize(t);
    trues = t;
  }
  state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(q.x.size()));
  state.counters["true_share"] = double(trues) / double(q.x.size());
  // What one pass over the points visits (outside the timed loop).
  double voxels = 0, occupied = 0, stats[2] = {0, 0};
  for (const vec3& x : q.x) {
    int v = 0;
    occupied += occupied_in_box(g, x, q.reach, &v, stats);
    voxels += v;
  }
  state.counters["listed"] = stats[0] / double(q.x.size());
  state.counters["one_plane"] = stats[1] / double(q.x.size());
  state.counters["voxels"] = voxels / double(q.x.size());
  state.counters["occupied"] = occupied / double(q.x.size());
  state.counters["points"] = double(q.x.size());
}

void BM_near(benchmark::State& state, const std::string& name) {
  run(state, name, [](const vplkit::triangle_voxel_view<float>& g, vec3 x, float reach) {
    return vplkit::triangle_voxel_surface_within(g, x, reach, tolerance(x));
  });
}

void BM_near_scan(benchmark::State& state, const std::string& name) {
  run(state, name, [](const vplkit::triangle_voxel_view<float>& g, vec3 x, float reach) {
    return vplkit::triangle_voxel_surface_within_scan(g, x, reach, tolerance(x));
  });
}

void BM_near_lookups(benchmark::State& state, const std::string& name) {
  run(state, name, [](const vplkit::triangle_voxel_view<float>& g, vec3 x, float reach) {
    int v = 0;
    return occupied_in_box(g, x, reach, &v) > 0;
  });
}

}  // namespace

int main(int argc, char** argv) {
  try {
    benchmark::AddCustomContext("gl", vplrender::pipeline_gl_context().describe());
  } catch (const std::exception& e) {
    std::cerr << "bench_triangle_voxel_near: no GL context: " << e.what() << "\n";
    return 1;
  }
  std::vector<std::string> scenes = {"cornell", "open"};
  if (std::getenv("VPLKIT_BENCH_SPONZA") != nullptr) scenes.push_back("sponza");
  for (const std::string& s : scenes) {
    benchmark::RegisterBenchmark(("BM_near/" + s).c_str(), [s](benchmark::State& st) { BM_near(st, s); })
        ->ComputeStatistics("min", &min_of);
    benchmark::RegisterBenchmark(("BM_near_scan/" + s).c_str(), [s](benchmark::State& st) { BM_near_scan(st, s); })
        ->ComputeStatistics("min", &min_of);
    benchmark::RegisterBenchmark(("BM_near_lookups/" + s).c_str(), [s](benchmark::State& st) { BM_near_lookups(st, s); })
        ->ComputeStatistics("min", &min_of);
  }
  static char default_min_time[] = "--benchmark_min_time=0.05";
  std::vector<char*> args{argv[0], default_min_time};
  for (int i = 1; i < argc; ++i) args.push_back(argv[i]);
  args.push_back(nullptr);
  int n = int(args.size()) - 1;
  benchmark::Initialize(&n, args.data());
  if (benchmark::ReportUnrecognizedArguments(n, args.data())) return 1;
  try {
    benchmark::RunSpecifiedBenchmarks();
  } catch (const std::exception& e) {
    std::cerr << "bench_triangle_voxel_near: " << e.what() << "\n";
    return 1;
  }
  benchmark::Shutdown();
  return 0;
}
