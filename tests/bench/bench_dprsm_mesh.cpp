// SPDX-License-Identifier: MIT
// What the DPRSM's mesh costs the host on every frame whose light moves: the split of the scene's
// triangles for the paraboloid projection (tessellate_on_all_cores, raster/tessellate.hpp) and the
// vertex array the DPRSM pass draws (gl_mesh::upload: material order, per-corner vertices with
// their triangle's plane, the buffer upload). BM_dprsm_mesh_frame is the two as a frame runs them
// (raster/dprsm_mesh.hpp: split and vertices on all cores, buffers kept from frame to frame), the
// light alternating between two positions so that every iteration rebuilds the mesh. vplrender's JSON reports the two together as the
// stage "dprsm tessellation (cpu)"; on an NVIDIA H200 (16 cores) it was 6.75 ms for cornell and
// 155 ms for the Sponza OBJ at R = 512, beside GPU stages of a few milliseconds.
//
// Scenes (argument `scene`): 0 = cornell (36 triangles, 22,742 after the split at R = 512);
// 1 = dense: cornell with its floor replaced by a grid of 2 x 182 x 182 triangles (66,248 in all,
// the Sponza OBJ's count: a mesh of small triangles, most of which need no split). The light is the
// scene's. `R` is the DPRSM resolution (the split angle sqrt(2 / R)).
#include "bench_common.hpp"

#include <raster/dprsm_mesh.hpp>
#include <raster/gl_mesh.hpp>
#include <raster/tessellate.hpp>
#include <render/pipeline.hpp>
#include <scene/builtin_scenes.hpp>

#include <benchmark/benchmark.h>

#include <cstdint>
#include <iostream>
#include <vector>

namespace {

using namespace vplrender;

// cornell with its floor (the two triangles at y = the room's floor, facing +y) replaced by an
// n x n grid of quads over the same rectangle, with the floor's material and normal.
scene dense_cornell(int n) {
  scene s = make_cornell_scene();
  std::vector<triangle> kept;
  const triangle* floor = nullptr;
  float y0 = 1e30f;
  for (const triangle& t : s.triangles)
    if (t.n[0].y > 0.99f && t.p[0].y < y0) y0 = t.p[0].y;
  for (const triangle& t : s.triangles) {
    const bool is_floor = t.n[0].y > 0.99f && t.p[0].y == y0 && t.p[1].y == y0 && t.p[2].y == y0;
    if (is_floor && !floor) floor = &t;
    if (!is_floor) kept.push_back(t);
  }
  const aabb b = bounds(s.triangles);
  std::vector<triangle> grid;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      auto at = [&](int a, int c) {
        return vec3(b.lo.x + (b.hi.x - b.lo.x) * float(a) / float(n), y0, b.lo.z + (b.hi.z - b.lo.z) * float(c) / float(n));
      };
      triangle t;
      t.material = floor ? floor->material : 0;
      t.n = {vec3(0, 1, 0), vec3(0, 1, 0), vec3(0, 1, 0)};
      t.p = {at(i, j), at(i, j + 1), at(i + 1, j + 1)};
      grid.push_back(t);
      t.p = {at(i, j), at(i + 1, j + 1), at(i + 1, j)};
      grid.push_back(t);
    }
  s.triangles = grid;
  s.triangles.insert(s.triangles.end(), kept.begin(), kept.end());
  return s;
}

const scene& scene_for(int which) {
  static const scene cornell = make_cornell_scene();
  static const scene dense = dense_cornell(182);
  return which == 0 ? cornell : dense;
}

tessellation_params params_for(int R) {
  tessellation_params p;
  p.max_angle = tessellation_angle_for_resolution(R);
  return p;
}

void BM_dprsm_tessellation(benchmark::State& state) {
  const scene& s = scene_for(int(state.range(0)));
  const tessellation_params p = params_for(int(state.range(1)));
  tessellation_stats st;
  for (auto _ : state) {
    std::vector<triangle> out = tessellate_on_all_cores(s.triangles, s.light.position, p, &st);
    benchmark::DoNotOptimize(out.data());
  }
  state.counters["triangles_in"] = double(st.input);
  state.counters["triangles_out"] = double(st.output);
  state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(st.output));
}

// The mesh of one light uploaded again and again (the tessellation done once, outside the loop).
void BM_dprsm_mesh_upload(benchmark::State& state) {
  const scene& s = scene_for(int(state.range(0)));
  const std::vector<triangle> tris = tessellate_on_all_cores(s.triangles, s.light.position, params_for(int(state.range(1))));
  pipeline_gl_context().make_current();
  gl_mesh mesh;
  for (auto _ : state) {
    mesh.upload(tris);
    benchmark::DoNotOptimize(mesh.ranges().data());
  }
  state.counters["triangles"] = double(tris.size());
  state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(tris.size()));
}

void BM_dprsm_mesh_frame(benchmark::State& state) {
  const scene& s = scene_for(int(state.range(0)));
  const tessellation_params p = params_for(int(state.range(1)));
  pipeline_gl_context().make_current();
  dprsm_mesh mesh(s.triangles);
  const vec3 lights[2] = {s.light.position, s.light.position + vec3(0.01f, -0.02f, 0.015f)};
  tessellation_stats st;
  std::int64_t k = 0;
  for (auto _ : state) {
    mesh.build(lights[k++ & 1], p, &st);
    benchmark::DoNotOptimize(mesh.mesh().ranges().data());
  }
  state.counters["triangles_out"] = double(st.output);
  state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(st.output));
}

}  // namespace

BENCHMARK(BM_dprsm_mesh_frame)->ArgNames({"scene", "R"})->Args({0, 512})->Args({1, 512})->Args({0, 64})
    ->Unit(benchmark::kMillisecond)->Apply(vplkit_bench::standard);
BENCHMARK(BM_dprsm_tessellation)->ArgNames({"scene", "R"})->Args({0, 512})->Args({1, 512})->Args({0, 64})
    ->Unit(benchmark::kMillisecond)->Apply(vplkit_bench::standard);
BENCHMARK(BM_dprsm_mesh_upload)->ArgNames({"scene", "R"})->Args({0, 512})->Args({1, 512})->Args({0, 64})
    ->Unit(benchmark::kMillisecond)->Apply(vplkit_bench::standard);

int main(int argc, char** argv) {
  try {
    benchmark::AddCustomContext("gl", pipeline_gl_context().describe());
  } catch (const std::exception& e) {
    std::cerr << "bench_dprsm_mesh: no GL context: " << e.what() << "\n";
    return 1;
  }
  return vplkit_bench::run_main(argc, argv);
}
