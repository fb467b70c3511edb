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

#include <vplkit/distribution/discrete_cdf.hpp>
#include <vplkit/paraboloid/texel_grid.hpp>
#include <vplkit/visibility/visibility_callables.hpp>
#include <vplkit/vpl/luminance.hpp>

#include <iostream>
#include <string>

namespace {

using namespace vplkit_bench;
namespace gl = vplkit::gl;

struct float4 {
  float x, y, z, w;
};
struct int4 {
  int x, y, z, w;
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
  gl::buffer blk = gl::buffer::filled(std::size_t(blocks) * 32);
  gl::buffer info = gl::buffer::filled(16);
  gl::buffer params = gl::buffer::filled(16);
  wb.bind(0);
  cdf.bind(1);
  guide.bind(2);
  blk.bind(3);
  info.bind(4);
  bind_uniform(params, 0);
  timed(
      state, [] {},
      [&] {
        for (std::uint32_t pass = 1; pass <= 6; ++pass) {
          const std::uint32_t p[4] = {n, pass, 0, 0};
          params.write_bytes(p, 0, sizeof p);
          const std::uint32_t gx = pass == 2 || pass == 4 ? 1u : pass == 6 ? guide_groups : groups;
          gl::dispatch(prog, gx, 1, 1);
        }
      });
  const std::vector<float> c = cdf.read<float>();
  if (c.back() != 1.0f) state.SkipWithError("cdf_build.comp: cdf[n] != 1");
  state.SetItemsProcessed(std::int64_t(state.iterations()) * n);
}

// ---- gbg_accumulate.comp + gbg_finish.comp ------------------------------------------------------
struct light_block {
  float4 position, intensity, axis_x, axis_y, axis_z;
};
struct gbg_block {
  light_block light;
  float4 grid_min, grid_max;
  int4 grid_res;
  int4 sizes;    // W, H, R, n_dirs
  int4 options;  // accumulator, dir_begin, dir_end, count_gather_points
  std::uint32_t seed, pad0, pad1, pad2;
  float4 reals;  // dmin, depth_tolerance, offset_voxels
  float4 fixed;  // scale, max_units
};
struct finish_block {
  light_block light;
  int4 sizes;    // R, n_dirs, fill
  float4 fixed;  // 1 / scale
};

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

  const auto& L = dp.light;
  const light_block lb{f4(L.position), f4(L.intensity), f4(L.frame.axis_x), f4(L.frame.axis_y), f4(L.frame.axis_z)};
  const vplkit::ivec3 r = grid.resolution();
  const gbg_block p{lb, f4(grid.bounds_min()), f4(grid.bounds_max()), {r.x, r.y, r.z, 0}, {W, W, R, n_dirs},
                    {1, 0, n_dirs, 1}, 21u, 0, 0, 0, {0.1f, tol, 1.75f, 0}, {scale, max_units, 0, 0}};
  const finish_block fp{lb, {R, n_dirs, 1, 0}, {1.0f / scale, 0, 0, 0}};
  const auto& acc_prog = kernel("vplkit/builders/gbg_accumulate.comp");
  const auto& fin_prog = kernel("vplkit/builders/gbg_finish.comp");
  auto gb = gl::buffer::from_vector(surfels(gbd.position, gbd.normal, gbd.albedo));
  auto dpb = gl::buffer::from_vector(surfels(dp.position, dp.normal, dp.albedo));
  auto vx = gl::buffer::from_vector(grid.words());
  auto acc = gl::buffer::filled(std::size_t(2 * n) * 4, 0);
  auto stats = gl::buffer::filled(8 * 4, 0);
  auto weights = gl::buffer::filled(std::size_t(n) * 4, 0);
  auto ub_acc = gl::buffer::from_bytes(&p, sizeof p);
  auto ub_fin = gl::buffer::from_bytes(&fp, sizeof fp);
  const std::vector<std::uint32_t> zeros(std::size_t(2 * n), 0u);
  const std::vector<std::uint32_t> zero_stats(8, 0u);
  auto accumulate = [&] {
    gb.bind(0);
    dpb.bind(1);
    vx.bind(2);
    acc.bind(3);
    stats.bind(4);
    bind_uniform(ub_acc, 0);
    gl::dispatch(acc_prog, gl::groups_for(std::size_t(W * W), 64));
  };
  auto finish = [&] {
    acc.bind(0);
    stats.bind(1);
    dpb.bind(2);
    weights.bind(3);
    bind_uniform(ub_fin, 0);
    const GLuint g = gl::groups_for(std::size_t(R), 8);
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
  state.counters["lit_hit_fraction"] = double(s[2]) / H;
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
  const int params[4] = {R, 0, 0, 0};
  auto ub = gl::buffer::from_bytes(params, sizeof params);
  in.bind(0);
  out.bind(1);
  bind_uniform(ub, 2);
  const GLuint gxy = gl::groups_for(std::size_t(R), 8);
  timed(state, [] {}, [&] { gl::dispatch(prog, gxy, gxy, 2); });
  state.SetItemsProcessed(std::int64_t(state.iterations()) * std::int64_t(w.size()));
}

// ---- voxelize.comp ------------------------------------------------------------------------------
struct voxelize_params {
  float4 bmin, bmax;
  int4 res;
  std::uint32_t triangle_count;
  float margin;
  std::uint32_t pad[2];
};

void BM_gpu_voxelize(benchmark::State& state) {
  const int res = int(state.range(0));
  static const mesh* m = new mesh(dense_mesh());
  const auto bounds = vplkit::fit_voxel_bounds(m->positions.data(), m->positions.size());
  const std::size_t words = vplkit::voxel_word_count(vplkit::ivec3(res));
  std::vector<float4> pos;
  for (const v3f& q : m->positions) pos.push_back(f4(q, 1.0f));
  const std::size_t T = m->triangle_count();
  const voxelize_params params{f4(bounds.min), f4(bounds.max), {res, res, res, 0}, std::uint32_t(T), 1e-4f, {0, 0}};
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
        pb.bind(0);
        ib.bind(1);
        wb.bind(2);
        bind_uniform(ub, 3);
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
