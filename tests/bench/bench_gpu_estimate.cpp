// SPDX-License-Identifier: MIT
// What one VPL sample costs on the GPU backend, in units of the rays of --method exact: the ratio
// issue 17's targets are stated in (docs/renderer.md, "The estimate kernels"). On one prepared
// frame (vplrender's pipeline: G-buffer, DPRSM, voxel grid and BVH on the headless GL context),
// every iteration renders
//   A: --method global --vpls N with the benchmark's visibility (one VPL sample = a CDF draw, the
//      VPL's contribution and one visibility query), and
//   B: --method exact --dirs M (one direction = a closest-hit ray and a shadow ray: 2 rays),
// back to back, and reads each render's "estimate (gpu)" stage (the GL time of the estimate
// dispatches: a GL_TIME_ELAPSED query on a GPU, glFinish + steady_clock on llvmpipe). The
// builders and CDFs of A run too but are not counted. Reported:
//   ratio          = (A's ms / (pixels N)) / (B's ms / (pixels 2 M)) over all iterations: the cost
//                    of one VPL sample in exact rays (at most 1.5 with exact visibility on
//                    llvmpipe is the target; 6.8 was measured on an NVIDIA H200 before the
//                    estimate kernels were split per method);
//   vpl_sample_ns, exact_ray_ns: the two per-item costs (per valid or invalid pixel alike);
// and the iteration time is A's estimate time (UseManualTime). A and B alternate, so a drift of
// the machine's speed moves both; the ratio is the figure to compare across builds and machines.
// Each variant is rendered once before timing: llvmpipe JIT-compiles a kernel variant at its
// first dispatch (seconds) and counts that in the GL timer. One iteration per repetition by
// default (bench_common.hpp's --benchmark_min_time=0.05): ask for --benchmark_repetitions=N.
//
// Arguments: image side W (W x W pixels), N VPL samples, M exact directions, visibility
// (0 exact = the BVH of --visibility exact, 1 voxels = the triangle voxel grid), scene (0 cornell,
// 1 open). DPRSM 2 x 128^2, 64^3 voxels: the builders stay cheap beside the estimate.
#include "bench_common.hpp"

#include <cli/options.hpp>
#include <cli/render_options.hpp>
#include <cli/scene_setup.hpp>
#include <render/gpu/gpu_backend.hpp>
#include <render/pipeline.hpp>

#include <benchmark/benchmark.h>

#include <iostream>
#include <map>
#include <memory>
#include <string>
#include <tuple>

namespace {

using namespace vplrender;

struct frame {
  options o;
  prepared_scene p;
  frame_buffers b;
};

// One frame per (scene, side), prepared once (GL context, rasterisation, voxels, BVH).
const frame& frame_for(int scene, int side) {
  static auto* frames = new std::map<std::pair<int, int>, std::unique_ptr<frame>>();
  auto& f = (*frames)[{scene, side}];
  if (!f) {
    options o;
    o.scene = scene == 0 ? "cornell" : "open";
    o.width = o.height = side;
    o.dprsm = 128;
    o.voxels = 64;
    o.visibility = visibility_choice::exact;  // the frame gets its BVH (both A and B need it)
    o.progress = progress_mode::never;
    prepared_scene p = prepare_scene(o);
    stage_timer t;
    nlohmann::json det;
    frame_buffers b = prepare_buffers(o, p, t, det);
    f.reset(new frame{o, std::move(p), std::move(b)});
  }
  return *f;
}

double estimate_ms(const frame& f, const render_settings& es) {
  stage_timer t;
  (void)render_gpu(f.b, es, t);
  for (const stage_time& s : t.stages())
    if (s.name == "estimate (gpu)") return s.ms;
  throw std::runtime_error("bench_gpu_estimate: no \"estimate (gpu)\" stage");
}

void BM_gpu_vpl_sample_in_exact_rays(benchmark::State& state) {
  const int side = int(state.range(0)), n = int(state.range(1)), m = int(state.range(2));
  const visibility_choice vis = state.range(3) == 0 ? visibility_choice::exact : visibility_choice::voxels;
  const frame& f = frame_for(int(state.range(4)), side);
  options oa = f.o;
  oa.meth = method::global;
  oa.vpls = n;
  oa.visibility = vis;
  options ob = f.o;
  ob.meth = method::exact;
  ob.dirs = m;
  const render_settings a = make_render_settings(oa, f.p.s), b = make_render_settings(ob, f.p.s);
  estimate_ms(f, a);  // warm-up: the JIT compile of each variant
  estimate_ms(f, b);
  double sum_a = 0.0, sum_b = 0.0;
  for (auto _ : state) {
    const double ta = estimate_ms(f, a), tb = estimate_ms(f, b);
    sum_a += ta;
    sum_b += tb;
    state.SetIterationTime(ta * 1e-3);
  }
  const double pixels = double(side) * double(side);
  const double per_sample = sum_a / (pixels * n), per_ray = sum_b / (pixels * 2.0 * m);
  state.counters["ratio"] = per_sample / per_ray;
  state.counters["vpl_sample_ns"] = per_sample * 1e6 / double(state.iterations());
  state.counters["exact_ray_ns"] = per_ray * 1e6 / double(state.iterations());
  state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(pixels) * n);
  state.SetLabel(std::string(to_string(vis)) + " visibility, " + f.o.scene);
}

}  // namespace

// {W, N, M, visibility, scene}. The first row is the target's measurement; the 32 x 32 row is the
// one the smoke test (ctest -L bench) runs.
BENCHMARK(BM_gpu_vpl_sample_in_exact_rays)
    ->ArgNames({"W", "N", "M", "vis", "scene"})
    ->Args({128, 64, 32, 0, 0})
    ->Args({128, 64, 32, 1, 0})
    ->Args({128, 64, 32, 0, 1})
    ->Args({32, 16, 8, 0, 0})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);

int main(int argc, char** argv) {
  try {
    benchmark::AddCustomContext("gl", pipeline_gl_context().describe());
  } catch (const std::exception& e) {
    std::cerr << "bench_gpu_estimate: no GL context: " << e.what() << "\n";
    return 1;
  }
  return vplkit_bench::run_main(argc, argv);
}
