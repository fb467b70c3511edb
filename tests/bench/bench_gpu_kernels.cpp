// SPDX-License-Identifier: MIT
// Device time of the GLSL pack's compute kernels (glsl/vplkit/**/*.comp) on the headless GL
// context of support/headless_gl (VPLKIT_GL picks the path; llvmpipe on a CPU-only machine).
// Each iteration's time is the GL work between timer_query::begin and end, reported through
// UseManualTime: a GL_TIME_ELAPSED query on a GPU, glFinish + steady_clock on Mesa's software
// renderers (whose GL_TIME_ELAPSED does not cover compute; see compute.hpp). Uploads, clears and
// read-backs are outside the timed region; the per-pass uniform updates of cdf_build are inside.
//  - cdf_build.comp: the CDF + guide build of one distribution of 2 x 512 x 512 float weights
//    (exponential, fixed seed), local size 256 x 4 items (items = weights), driven two ways:
//    dispatches:3 as the renderer drives it (gpu_cdf.cpp: one program per pass, the parameter
//    block written once, the passes vplkit::gpu::cdf_build_pass_needed names: 1, 3, 5) and
//    dispatches:6 as a host that runs all six passes of one program, rewriting the pass number
//    in the parameter block between them (the kernel's older protocol, still valid);
//  - gbg_accumulate.comp + gbg_finish.comp: GBG weights of the synthetic room, 64 x 64 G-buffer,
//    16 directions, DPRSM 2 x R x R, voxel grid 64^3, gathering accumulator, hole fill on
//    (items = rays = 4096 x 16); accumulate alone and finish alone are listed too;
//  - median_fill.comp: 2 x 512 x 512 weights with 10 % / 90 % holes (items = texels);
//  - voxelize.comp: the dense mesh of bench_common.hpp (5388 triangles) at 64^3 / 128^3
//    (items = triangles).
#include "bench_common.hpp"

#include <cdf_build_kernel.hpp>
#include <gbg_kernels.hpp>
#include <gl_kernels.hpp>
#include <std430_types.hpp>

#include <headless_gl/compute.hpp>
#include <headless_gl/context.hpp>

#include <vplkit/distribution/discrete_cdf.hpp>
#include <vplkit/image/median_fill_params.h>
#include <vplkit/paraboloid/texel_grid.hpp>
#include <vplkit/visibility/visibility_callables.hpp>
#include <vplkit/visibility/voxelize_params.h>

#include <iostream>
#include <string>

namespace {

using namespace vplkit_bench;
namespace gl = vplkit::gl;

using vplkit_test::float4;

gl::headless_context& context() {
  // Kept until exit on purpose (tearing Mesa down from a static destructor races its atexit).
  static gl::headless_context* const ctx = new gl::headless_context();
  return *ctx;
}

// Times `work` (GL commands only) once per iteration; `prepare` runs untimed before each.
template <class Prepare, class Work>
void timed(benchmark::State& state, Prepare&& prepare, Work&& work) {
  gl::timer_query timer;
  // One untimed run first: llvmpipe compiles a kernel at its first dispatch, and a GPU driver
  // may too.
  prepare();
  work();
  glFinish();
  for (auto _ : state) {
    prepare();
    timer.begin();
    work();
    timer.end();
    state.SetIterationTime(timer.milliseconds() * 1e-3);
  }
  state.SetLabel(timer.method());
}

// ---- cdf_build.comp -----------------------------------------------------------------------------
void BM_gpu_cdf_build(benchmark::State& state) {
  const std::uint32_t n = std::uint32_t(state.range(0));
  std::vector<float> w(n);
  std::mt19937 g(61u);
  std::exponential_distribution<float> ex(1.0f);
  for (float& x : w) x = ex(g);
  const bool all_six = state.range(1) == 6;
  const unsigned local = 256, items = 4;
  const std::string sizes = "#define VPLKIT_CDF_BUILD_LOCAL_SIZE 256\n#define VPLKIT_CDF_BUILD_ITEMS 4\n";
  const auto& prog = vplkit_test::pack_kernel("vplkit/distribution/cdf_build.comp", sizes);
  std::vector<const gl::program*> per_pass;
  for (int pass = 1; pass <= 6; ++pass)
    per_pass.push_back(&vplkit_test::pack_kernel("vplkit/distribution/cdf_build.comp",
                                                 sizes + "#define VPLKIT_CDF_BUILD_PASS " + std::to_string(pass) + "\n"));
  const std::uint32_t m = std::uint32_t(vplkit::discrete_guide_size(n));
  const std::size_t block = std::size_t(local) * items;
  const std::uint32_t blocks = std::uint32_t((n + block - 1) / block);
  const std::uint32_t groups = std::min<std::uint32_t>(blocks, 65535u);
  const std::uint32_t guide_groups = std::min<std::uint32_t>(std::uint32_t((std::size_t(m) + block) / block), 65535u);
  gl::buffer wb = gl::buffer::from_vector(w);
  gl::buffer cdf = gl::buffer::filled(std::size_t(n + 1) * 4);
  gl::buffer guide = gl::buffer::filled(std::size_t(m + 1) * 4);
  gl::buffer blk = gl::buffer::filled(std::size_t(blocks) * sizeof(vplkit::gpu::cdf_build_block));
  gl::buffer info = gl::buffer::filled(sizeof(vplkit::gpu::cdf_build_info));
  gl::buffer params = gl::buffer::filled(sizeof(vplkit::gpu::cdf_build_params));
  vplkit_test::bind_cdf_build(wb, cdf, guide, blk, info, params);
  timed(
      state, [] {},
      [&] {
        vplkit::gpu::cdf_build_params p{};
        p.n = n;
        if (!all_six) params.write_bytes(&p, 0, sizeof p);
        for (std::uint32_t pass = 1; pass <= 6; ++pass) {
          const std::uint32_t gx = pass == 2 || pass == 4 ? 1u : pass == 6 ? guide_groups : groups;
          if (all_six) {
            p.pass = pass;
            params.write_bytes(&p, 0, sizeof p);
            gl::dispatch(prog, gx, 1, 1);
          } else if (vplkit::gpu::cdf_build_pass_needed(pass, n, local * items)) {
            gl::dispatch(*per_pass[pass - 1], gx, 1, 1);
          }
        }
      });
  const std::vector<float> c = cdf.read<float>();
  if (c.back() != 1.0f) state.SkipWithError("cdf_build.comp: cdf[n] != 1");
  state.SetItemsProcessed(std::int64_t(state.iterations()) * n);
}

// ---- gbg_accumulate.comp + gbg_finish.comp ------------------------------------------------------
enum class gbg_part { both, accumulate, finish };

// The dispatches of the GBG parity test (support/gbg_kernels.hpp), gathering accumulator.
void run_gpu_gbg(benchmark::State& state, gbg_part part) {
  const int R = int(state.range(0));
  const int W = 64, res = 64;
  const auto& gbd = room_gbuffer(W);
  const auto& dp = room_dprsm(R);
  const auto& grid = room_grid(res);
  const int n = vplkit::texel_count(R);
  const int G = int(room_gather_points(W).size());
  vplkit_test::gbg_setup st;
  st.dmin = 0.1f;
  st.tol = vplkit::voxel_tracer_depth_tolerance(grid.view()) + 0.05f;
  vplkit_test::choose_gbg_fixed_point(st, G, dp);
  vplkit_test::gbg_buffers b(gbd, dp, grid, 0);
  const auto ub_acc =
      vplkit_test::uniform_buffer(vplkit_test::gbg_accumulate_block(dp, grid, W, W, st, 0, st.n_dirs, true));
  const auto ub_fin = vplkit_test::uniform_buffer(vplkit_test::gbg_finish_block(dp, st, true));
  const std::vector<std::uint32_t> zeros(std::size_t(2 * n), 0u);
  const std::vector<std::uint32_t> zero_stats(VPLKIT_GBG_STATS_SIZE, 0u);
  auto accumulate = [&] { b.accumulate(ub_acc); };
  auto finish = [&] { b.finish(ub_fin); };
  auto clear = [&] {
    b.acc.write(zeros);
    b.stats.write(zero_stats);
  };
  if (part == gbg_part::finish) {
    clear();
    accumulate();
    timed(state, [] {}, finish);
  } else if (part == gbg_part::accumulate) {
    timed(state, clear, accumulate);
  } else {
    timed(state, clear, [&] {
      accumulate();
      finish();
    });
  }
  const std::vector<std::uint32_t> s = b.stats.read<std::uint32_t>();
  state.counters["lit_hit_fraction"] = double(s[VPLKIT_GBG_STAT_LIT_HITS]) / (double(G) * st.n_dirs);
  state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(part == gbg_part::finish ? n : G * st.n_dirs));
}

void BM_gpu_gbg_accumulate_finish(benchmark::State& state) { run_gpu_gbg(state, gbg_part::both); }
void BM_gpu_gbg_accumulate(benchmark::State& state) { run_gpu_gbg(state, gbg_part::accumulate); }
void BM_gpu_gbg_finish(benchmark::State& state) { run_gpu_gbg(state, gbg_part::finish); }

// ---- median_fill.comp ---------------------------------------------------------------------------
void BM_gpu_median_fill(benchmark::State& state) {
  const int R = int(state.range(0)), holes = int(state.range(1));
  const std::vector<float> w = holey_weights(R, holes);
  const auto& prog = vplkit_test::pack_kernel("vplkit/image/median_fill.comp");
  auto in = gl::buffer::from_vector(w);
  auto out = gl::buffer::filled(w.size() * 4);
  vplkit::gpu::median_fill_params params{};
  params.resolution = R;
  const auto ub = vplkit_test::uniform_buffer(params);
  vplkit_test::bind({vplkit_test::storage_at(VPLKIT_MEDIAN_FILL_BINDING_IN, in),
                     vplkit_test::storage_at(VPLKIT_MEDIAN_FILL_BINDING_OUT, out),
                     vplkit_test::uniform_at(VPLKIT_MEDIAN_FILL_BINDING_PARAMS, ub)});
  const GLuint gxy = gl::groups_for(std::size_t(R), VPLKIT_MEDIAN_FILL_LOCAL_SIZE);
  timed(state, [] {}, [&] { gl::dispatch(prog, gxy, gxy, 2); });
  state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(w.size()));
}

// ---- voxelize.comp ------------------------------------------------------------------------------
void BM_gpu_voxelize(benchmark::State& state) {
  const int res = int(state.range(0));
  static const mesh* m = new mesh(dense_mesh());
  const auto bounds = vplkit::fit_voxel_bounds(m->positions.data(), m->positions.size());
  const std::size_t words = vplkit::voxel_word_count(vplkit::ivec3(res));
  std::vector<float4> pos;
  for (const v3f& q : m->positions) pos.push_back(vplkit_test::f4(q, 1.0f));
  const std::size_t T = m->triangle_count();
  vplkit::gpu::voxelize_params params{};
  params.bounds_min = glm::vec4(bounds.min, 0.0f);
  params.bounds_max = glm::vec4(bounds.max, 0.0f);
  params.resolution = glm::ivec4(res, res, res, 0);
  params.triangle_count = std::uint32_t(T);
  params.margin_voxels = 1e-4f;
  const auto& prog = vplkit_test::pack_kernel("vplkit/visibility/voxelize.comp");
  auto pb = gl::buffer::from_vector(pos);
  auto ib = gl::buffer::from_vector(m->indices);
  auto wb = gl::buffer::filled(words * 4, 0);
  const auto ub = vplkit_test::uniform_buffer(params);
  const std::vector<std::uint32_t> zeros(words, 0u);
  timed(
      state, [&] { wb.write(zeros); },
      [&] {
        vplkit_test::dispatch(prog, vplkit_test::spread_groups(T),
                              {vplkit_test::storage_at(VPLKIT_VOXELIZE_BINDING_POSITIONS, pb),
                               vplkit_test::storage_at(VPLKIT_VOXELIZE_BINDING_INDICES, ib),
                               vplkit_test::storage_at(VPLKIT_VOXELIZE_BINDING_WORDS, wb),
                               vplkit_test::uniform_at(VPLKIT_VOXELIZE_BINDING_PARAMS, ub)});
      });
  std::int64_t occupied = 0;
  for (std::uint32_t w : wb.read<std::uint32_t>()) occupied += __builtin_popcount(w);
  state.counters["occupied"] = double(occupied);
  state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(T));
}

}  // namespace

BENCHMARK(BM_gpu_cdf_build)->ArgNames({"", "dispatches"})->Args({2 * 512 * 512, 3})->Args({2 * 512 * 512, 6})->UseManualTime()->Unit(benchmark::kMillisecond)->Apply(vplkit_bench::standard);
BENCHMARK(BM_gpu_gbg_accumulate_finish)->ArgName("R")->Arg(64)->Arg(256)->UseManualTime()->Unit(benchmark::kMillisecond)->Apply(vplkit_bench::standard);
BENCHMARK(BM_gpu_gbg_accumulate)->ArgName("R")->Arg(64)->UseManualTime()->Unit(benchmark::kMillisecond)->Apply(vplkit_bench::standard);
BENCHMARK(BM_gpu_gbg_finish)->ArgName("R")->Arg(64)->Arg(256)->UseManualTime()->Unit(benchmark::kMillisecond)->Apply(vplkit_bench::standard);
BENCHMARK(BM_gpu_median_fill)->ArgNames({"R", "holes"})->Args({512, 10})->Args({512, 90})->UseManualTime()->Unit(benchmark::kMillisecond)->Apply(vplkit_bench::standard);
BENCHMARK(BM_gpu_voxelize)->ArgName("res")->Arg(64)->Arg(128)->UseManualTime()->Unit(benchmark::kMillisecond)->Apply(vplkit_bench::standard);

int main(int argc, char** argv) {
  try {
    benchmark::AddCustomContext("gl", context().describe());
  } catch (const std::exception& e) {
    std::cerr << "bench_gpu_kernels: no GL context: " << e.what() << "\n";
    return 1;
  }
  return vplkit_bench::run_main(argc, argv);
}
