// Device time of the GLSL pack's compute kernels (glsl/vplkit/**/*.comp) on the headless GL
// context of support/headless_gl (VPLKIT_GL picks the path; llvmpipe on a CPU-only machine).
// Each iteration's time is the GL work between timer_query::begin and end, reported through
// UseManualTime: a GL_TIME_ELAPSED query on a GPU, glFinish + steady_clock on Mesa's software
// renderers (whose GL_TIME_ELAPSED does not cover compute; see compute.hpp). Uploads, clears and
// read-backs are outside the timed region; the per-pass uniform updates of cdf_build are inside.
//  - cdf_build.comp: the 6-pass CDF + guide build of one distribution of 2 x 512 x 512 float
//    weights (exponential, fixed seed), local size 256 x 4 items (items = weights);
//  - gbg_accumulate.comp + gbg_finish.comp: GBG weights of the synthetic room, 64 x 64 G-buffer,
//    16 directions, DPRSM 2 x R x R, voxel grid 64^3, gathering accumulator, hole fill on
//    (items = rays = 4096 x 16); accumulate alone and finish alone are listed too;
//  - median_fill.comp: 2 x 512 x 512 weights with 10 % / 90 % holes (items = texels);
//  - voxelize.comp: the dense mesh of bench_common.hpp (5388 triangles) at 64^3 / 128^3
//    (items = triangles).
#include "bench_common.hpp"

#include <headless_gl/compute.hpp>
#include <headless_gl/context.hpp>

#include <vplkit/builders/gbg_accumulate_params.h>
#include <vplkit/builders/gbg_finish_params.h>
#include <vplkit/distribution/cdf_build_params.h>
#include <vplkit/distribution/discrete_cdf.hpp>
#include <vplkit/image/median_fill_params.h>
#include <vplkit/paraboloid/texel_grid.hpp>
#include <vplkit/visibility/visibility_callables.hpp>
#include <vplkit/visibility/voxelize_params.h>
#include <vplkit/vpl/luminance.hpp>

#include <iostream>
#include <string>

namespace {

using namespace vplkit_bench;
namespace gl = vplkit::gl;

struct float4 {
  float x, y, z, w;
};
float4 f4(v3f v, float w = 0.0f) { return {v.x, v.y, v.z, w}; }

gl::headless_context& context() {
  // Kept until exit on purpose (tearing Mesa down from a static destructor races its atexit).
  static gl::headless_context* const ctx = new gl::headless_context();
  return *ctx;
}

const gl::program& kernel(const std::string& file, const std::string& defines = "") {
  context();
  static auto* cache = new std::map<std::string, gl::program>();
  const std::string key = file + '\x01' + defines;
  auto it = cache->find(key);
  if (it == cache->end())
    it = cache
             ->emplace(key, gl::program::compute_with_includes("#version 430\n#include \"" + file + "\"\n", file,
                                                               {gl::glsl_source_dir()}, defines))
             .first;
  return it->second;
}

void bind_uniform(const gl::buffer& b, GLuint binding) {
  glBindBufferBase(GL_UNIFORM_BUFFER, binding, b.id());
  gl::check_gl("glBindBufferBase(GL_UNIFORM_BUFFER)");
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
  const unsigned local = 256, items = 4;
  const auto& prog = kernel("vplkit/distribution/cdf_build.comp",
                            "#define VPLKIT_CDF_BUILD_LOCAL_SIZE 256\n#define VPLKIT_CDF_BUILD_ITEMS 4\n");
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
  wb.bind(VPLKIT_CDF_BUILD_BINDING_WEIGHTS);
  cdf.bind(VPLKIT_CDF_BUILD_BINDING_CDF);
  guide.bind(VPLKIT_CDF_BUILD_BINDING_GUIDE);
  blk.bind(VPLKIT_CDF_BUILD_BINDING_BLOCKS);
  info.bind(VPLKIT_CDF_BUILD_BINDING_INFO);
  bind_uniform(params, VPLKIT_CDF_BUILD_BINDING_PARAMS);
  timed(
      state, [] {},
      [&] {
        for (std::uint32_t pass = 1; pass <= 6; ++pass) {
          vplkit::gpu::cdf_build_params p{};
          p.n = n;
          p.pass = pass;
          params.write_bytes(&p, 0, sizeof p);
          const std::uint32_t gx = pass == 2 || pass == 4 ? 1u : pass == 6 ? guide_groups : groups;
          gl::dispatch(prog, gx, 1, 1);
        }
      });
  const std::vector<float> c = cdf.read<float>();
  if (c.back() != 1.0f) state.SkipWithError("cdf_build.comp: cdf[n] != 1");
  state.SetItemsProcessed(std::int64_t(state.iterations()) * n);
}

// ---- gbg_accumulate.comp + gbg_finish.comp ------------------------------------------------------
std::vector<float4> surfels(const std::vector<v3f>& p, const std::vector<v3f>& n, const std::vector<v3f>& a) {
  std::vector<float4> out;
  for (std::size_t i = 0; i < p.size(); ++i) {
    out.push_back(f4(p[i]));
    out.push_back(f4(n[i]));
    out.push_back(f4(a[i]));
  }
  return out;
}

enum class gbg_part { both, accumulate, finish };

void run_gpu_gbg(benchmark::State& state, gbg_part part) {
  const int R = int(state.range(0));
  const int W = 64, n_dirs = 16, res = 64;
  const auto& gbd = room_gbuffer(W);
  const auto& dp = room_dprsm(R);
  const auto& grid = room_grid(res);
  const int n = vplkit::texel_count(R);
  const float tol = vplkit::voxel_tracer_depth_tolerance(grid.view()) + 0.05f;
  const int G = int(room_gather_points(W).size());
  // Fixed point as in tests/parity/parity_builders_test.cpp (gathering accumulator).
  const double H = double(G) * n_dirs;
  const float max_units = float(std::ldexp(1.0, 63 - int(std::ceil(std::log2(H)))));
  double d1min = 1e30;
  for (std::size_t t = 0; t < dp.position.size(); ++t)
    if (dp.albedo[t] != v3f(0)) d1min = std::min(d1min, double(glm::length(dp.position[t] - dp.light.position)));
  d1min = std::max(d1min - double(tol), 1e-3);
  const double v_bound = double(vplkit::luminance(dp.light.intensity)) / (3.141592653589793 * d1min * d1min);
  const float scale = float(std::ldexp(1.0, int(std::floor(std::log2(double(max_units) / v_bound)))));

  vplkit::gpu::gbg_accumulate_params p{};
  p.light = vplkit::gpu::make_light_params(dp.light);
  p.grid_min = glm::vec4(grid.bounds_min(), 0.0f);
  p.grid_max = glm::vec4(grid.bounds_max(), 0.0f);
  p.grid_resolution = glm::ivec4(grid.resolution(), 0);
  p.width = W;
  p.height = W;
  p.resolution = R;
  p.n_dirs = n_dirs;
  p.accumulator = 1;
  p.dir_begin = 0;
  p.dir_end = n_dirs;
  p.count_gather_points = 1;
  p.seed = 21u;
  p.dmin = 0.1f;
  p.depth_tolerance = tol;
  p.offset_voxels = 1.75f;
  p.scale = scale;
  p.max_units = max_units;
  vplkit::gpu::gbg_finish_params fp{};
  fp.light = p.light;
  fp.resolution = R;
  fp.n_dirs = n_dirs;
  fp.fill_holes = 1;
  fp.inv_scale = 1.0f / scale;
  const auto& acc_prog = kernel("vplkit/builders/gbg_accumulate.comp");
  const auto& fin_prog = kernel("vplkit/builders/gbg_finish.comp");
  auto gb = gl::buffer::from_vector(surfels(gbd.position, gbd.normal, gbd.albedo));
  auto dpb = gl::buffer::from_vector(surfels(dp.position, dp.normal, dp.albedo));
  auto vx = gl::buffer::from_vector(grid.words());
  auto acc = gl::buffer::filled(std::size_t(2 * n) * 4, 0);
  auto stats = gl::buffer::filled(VPLKIT_GBG_STATS_SIZE * 4, 0);
  auto weights = gl::buffer::filled(std::size_t(n) * 4, 0);
  auto ub_acc = gl::buffer::from_bytes(&p, sizeof p);
  auto ub_fin = gl::buffer::from_bytes(&fp, sizeof fp);
  const std::vector<std::uint32_t> zeros(std::size_t(2 * n), 0u);
  const std::vector<std::uint32_t> zero_stats(VPLKIT_GBG_STATS_SIZE, 0u);
  auto accumulate = [&] {
    gb.bind(VPLKIT_GBG_BINDING_GBUFFER);
    dpb.bind(VPLKIT_GBG_BINDING_DPRSM);
    vx.bind(VPLKIT_GBG_BINDING_VOXELS);
    acc.bind(VPLKIT_GBG_BINDING_ACC);
    stats.bind(VPLKIT_GBG_BINDING_STATS);
    bind_uniform(ub_acc, VPLKIT_GBG_BINDING_PARAMS);
    gl::dispatch(acc_prog, gl::groups_for(std::size_t(W * W), VPLKIT_GBG_LOCAL_SIZE));
  };
  auto finish = [&] {
    acc.bind(VPLKIT_GBG_FINISH_BINDING_ACC);
    stats.bind(VPLKIT_GBG_FINISH_BINDING_STATS);
    dpb.bind(VPLKIT_GBG_FINISH_BINDING_DPRSM);
    weights.bind(VPLKIT_GBG_FINISH_BINDING_WEIGHTS);
    bind_uniform(ub_fin, VPLKIT_GBG_FINISH_BINDING_PARAMS);
    const GLuint g = gl::groups_for(std::size_t(R), VPLKIT_GBG_FINISH_LOCAL_SIZE);
    gl::dispatch(fin_prog, g, g, 2);
  };
  auto clear = [&] {
    acc.write(zeros);
    stats.write(zero_stats);
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
  const std::vector<std::uint32_t> s = stats.read<std::uint32_t>();
  state.counters["lit_hit_fraction"] = double(s[VPLKIT_GBG_STAT_LIT_HITS]) / H;
  state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(part == gbg_part::finish ? n : G * n_dirs));
}

void BM_gpu_gbg_accumulate_finish(benchmark::State& state) { run_gpu_gbg(state, gbg_part::both); }
void BM_gpu_gbg_accumulate(benchmark::State& state) { run_gpu_gbg(state, gbg_part::accumulate); }
void BM_gpu_gbg_finish(benchmark::State& state) { run_gpu_gbg(state, gbg_part::finish); }

// ---- median_fill.comp ---------------------------------------------------------------------------
void BM_gpu_median_fill(benchmark::State& state) {
  const int R = int(state.range(0)), holes = int(state.range(1));
  std::mt19937 g(std::uint32_t(R * 100 + holes));
  std::exponential_distribution<float> ex(1.0f);
  std::uniform_int_distribution<int> pct(0, 99);
  std::vector<float> w(std::size_t(vplkit::texel_count(R)), 0.0f);
  for (int face = 0; face < 2; ++face)
    for (int y = 0; y < R; ++y)
      for (int x = 0; x < R; ++x) {
        const float v = ex(g) + 1e-3f;
        if (!vplkit::texel_is_valid(x, y, R) || pct(g) < holes) continue;
        w[std::size_t(vplkit::texel_index(face, x, y, R))] = v;
      }
  const auto& prog = kernel("vplkit/image/median_fill.comp");
  auto in = gl::buffer::from_vector(w);
  auto out = gl::buffer::filled(w.size() * 4);
  vplkit::gpu::median_fill_params params{};
  params.resolution = R;
  auto ub = gl::buffer::from_bytes(&params, sizeof params);
  in.bind(VPLKIT_MEDIAN_FILL_BINDING_IN);
  out.bind(VPLKIT_MEDIAN_FILL_BINDING_OUT);
  bind_uniform(ub, VPLKIT_MEDIAN_FILL_BINDING_PARAMS);
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
  for (const v3f& q : m->positions) pos.push_back(f4(q, 1.0f));
  const std::size_t T = m->triangle_count();
  vplkit::gpu::voxelize_params params{};
  params.bounds_min = glm::vec4(bounds.min, 0.0f);
  params.bounds_max = glm::vec4(bounds.max, 0.0f);
  params.resolution = glm::ivec4(res, res, res, 0);
  params.triangle_count = std::uint32_t(T);
  params.margin_voxels = 1e-4f;
  const auto& prog = kernel("vplkit/visibility/voxelize.comp");
  auto pb = gl::buffer::from_vector(pos);
  auto ib = gl::buffer::from_vector(m->indices);
  auto wb = gl::buffer::filled(words * 4, 0);
  auto ub = gl::buffer::from_bytes(&params, sizeof params);
  const std::vector<std::uint32_t> zeros(words, 0u);
  const GLuint gx = GLuint(std::min<std::size_t>(T, 65535)), gy = GLuint((T + 65534) / 65535);
  timed(
      state, [&] { wb.write(zeros); },
      [&] {
        pb.bind(VPLKIT_VOXELIZE_BINDING_POSITIONS);
        ib.bind(VPLKIT_VOXELIZE_BINDING_INDICES);
        wb.bind(VPLKIT_VOXELIZE_BINDING_WORDS);
        bind_uniform(ub, VPLKIT_VOXELIZE_BINDING_PARAMS);
        gl::dispatch(prog, gx, gy);
      });
  std::int64_t occupied = 0;
  for (std::uint32_t w : wb.read<std::uint32_t>()) occupied += __builtin_popcount(w);
  state.counters["occupied"] = double(occupied);
  state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(T));
}

}  // namespace

BENCHMARK(BM_gpu_cdf_build)->Arg(2 * 512 * 512)->UseManualTime()->Unit(benchmark::kMillisecond)->Apply(vplkit_bench::standard);
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
