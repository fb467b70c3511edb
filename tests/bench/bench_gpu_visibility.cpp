// SPDX-License-Identifier: MIT
// What visibility costs the GPU estimator: vplrender's estimate kernels (`--method global`, 64 x 64
// pixels, 16 VPLs per pixel, DPRSM 2 x 128^2, 128^3 voxels) with the triangle voxels (the voxel
// march, --visibility voxels) and with the exact BVH (--visibility exact) on one prepared frame,
// in turn within each iteration, so both see the same machine load. The time of an iteration is
// the voxel estimate's ("estimate (gpu)", GL timer; glFinish + wall clock on llvmpipe); the
// counters are the two estimates' smallest times over the run and
//   voxels_over_exact = min(voxel estimate) / min(exact estimate),
// the ratio the voxel march has to keep at or below 1 to earn its place beside the BVH (docs/
// results/visibility_gpu.md). The smallest time is the least disturbed by other work on
// a shared machine; run with --benchmark_min_time=20 (or more) for a stable ratio.
// Scenes: cornell and open (built in); Sponza when VPLKIT_BENCH_SPONZA names its OBJ file (the
// camera and light of docs/results.md). Each kernel variant runs once before timing (llvmpipe
// compiles on first use).
#include <cli/options.hpp>
#include <cli/render_options.hpp>
#include <cli/scene_setup.hpp>
#include <render/frame_buffers.hpp>
#include <render/pipeline.hpp>

#include <headless_gl/context.hpp>

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdlib>
#include <iostream>
#include <limits>
#include <map>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace {

struct prepared_frame {
  vplrender::prepared_scene scene;
  vplrender::options opts;
  vplrender::frame_buffers buffers;
};

std::vector<std::string> scene_args(const std::string& name) {
  if (name != "sponza") return {"bench", "--scene", name};
  const char* path = std::getenv("VPLKIT_BENCH_SPONZA");
  return {"bench", "--scene", path != nullptr ? path : "", "--light", "0,11.5,0", "--camera",
          "-15,2.5,0,5,4.5,0,0,1,0,60"};
}

// The frame of a scene, prepared once for the GPU backend with exact rays (both kinds need it).
const prepared_frame& frame(const std::string& name) {
  static auto* cache = new std::map<std::string, std::unique_ptr<prepared_frame>>();
  auto& p = (*cache)[name];
  if (!p) {
    std::vector<std::string> args = scene_args(name);
    args.insert(args.end(), {"--method", "global", "--size", "64x64", "--vpls", "16", "--dprsm", "128", "--voxels",
                             "128", "--backend", "gpu"});
    const vplrender::parse_result parsed = vplrender::parse_command_line(args);
    vplrender::prepared_scene sc = vplrender::prepare_scene(parsed.opts);
    vplrender::frame_settings f = vplrender::make_frame_settings(parsed.opts);
    f.exact_rays = true;
    vplrender::stage_timer timer;
    nlohmann::json details;
    vplrender::frame_buffers b = vplrender::prepare_buffers(sc.s, f, timer, details);
    p.reset(new prepared_frame{std::move(sc), parsed.opts, std::move(b)});
  }
  return *p;
}

// One estimate with visibility v: the GPU time of its "estimate (gpu)" stage, in ms.
double estimate_ms(const prepared_frame& p, vplrender::visibility_choice v) {
  vplrender::render_settings s = vplrender::make_render_settings(p.opts, p.scene.s);
  s.visibility = v;
  vplrender::stage_timer timer;
  nlohmann::json details;
  vplrender::run_estimator(p.buffers, s, timer, {}, details);
  for (const vplrender::stage_time& t : timer.stages())
    if (t.name == "estimate (gpu)") return t.ms;
  throw std::runtime_error("bench_gpu_visibility: no \"estimate (gpu)\" stage");
}

void BM_estimate_voxels_vs_exact(benchmark::State& state, const std::string& name) {
  const prepared_frame& p = frame(name);
  estimate_ms(p, vplrender::visibility_choice::voxels);  // compile both variants first
  estimate_ms(p, vplrender::visibility_choice::exact);
  double best_voxels = std::numeric_limits<double>::infinity(), best_exact = best_voxels;
  for (auto _ : state) {
    const double v = estimate_ms(p, vplrender::visibility_choice::voxels);
    const double e = estimate_ms(p, vplrender::visibility_choice::exact);
    best_voxels = std::min(best_voxels, v);
    best_exact = std::min(best_exact, e);
    state.SetIterationTime(v * 1e-3);
  }
  state.counters["voxels_min_ms"] = best_voxels;
  state.counters["exact_min_ms"] = best_exact;
  state.counters["voxels_over_exact"] = best_voxels / best_exact;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    benchmark::AddCustomContext("gl", vplrender::pipeline_gl_context().describe());
  } catch (const std::exception& e) {
    std::cerr << "bench_gpu_visibility: no GL context: " << e.what() << "\n";
    return 1;
  }
  std::vector<std::string> scenes = {"cornell", "open"};
  if (std::getenv("VPLKIT_BENCH_SPONZA") != nullptr) scenes.push_back("sponza");
  for (const std::string& s : scenes)
    benchmark::RegisterBenchmark(("BM_estimate_voxels_vs_exact/" + s).c_str(),
                                 [s](benchmark::State& st) { BM_estimate_voxels_vs_exact(st, s); })
        ->UseManualTime()
        ->Unit(benchmark::kMillisecond);
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
    std::cerr << "bench_gpu_visibility: " << e.what() << "\n";
    return 1;
  }
  benchmark::Shutdown();
  return 0;
}
