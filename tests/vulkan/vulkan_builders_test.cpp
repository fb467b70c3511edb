// SPDX-License-Identifier: MIT
// The builder kernels glsl/vplkit/builders/*.comp on Vulkan, with the default bindings of their
// parameter headers, against the C++ builders (T = float), on the scene of the GL parity test
// (tests/parity/parity_builders_test.cpp): tests/support/synthetic_scene.hpp with a DPRSM R = 32,
// a 32^3 voxel grid and a 24 x 24 G-buffer with a band and a block of background pixels.
//  - gather_subset.comp: the stratified subsets, EXACT (the GL test's 9 rectangles).
//  - global_weights.comp: global (4 subsets, dmin 0.05 and 0) and 2 x 2 local weights within
//    2e-6 relative; zero / non-zero per texel exact.
//  - gbg_accumulate.comp + gbg_finish.comp against build_gbg_weights, both accumulators, raw and
//    filled, with the GL test's fixed-point parameters: |G| exact; hits and lit hits within 0.5 %
//    of the rays (a ray whose GPU sin/cos flips a decision near a tie; 0 measured on lavapipe);
//    per texel |gpu - cpu| <= L 0.5 / scale / (|G| n_dirs) + 5e-6 |cpu| (L = all lit hits, an upper
//    bound of any texel's hits), at most 2 % of the texels outside it (the flipped rays' texels);
//    three direction ranges give the sums of one dispatch exactly; sums of ~2^40 units per texel
//    (the low word wraps: carries) within the same bound; an all-background G-buffer gives +0.
#include "vulkan_test_support.hpp"

#include "builder_params.hpp"
#include "std430_types.hpp"
#include "synthetic_scene.hpp"

#include <vplkit/builders/gather_subset.hpp>
#include <vplkit/builders/gather_subset_params.h>
#include <vplkit/builders/gbg_accumulate_params.h>
#include <vplkit/builders/gbg_finish_params.h>
#include <vplkit/builders/gbg_weights.hpp>
#include <vplkit/builders/global_weights.hpp>
#include <vplkit/builders/global_weights_params.h>
#include <vplkit/builders/local_weights.hpp>
#include <vplkit/paraboloid/texel_grid.hpp>
#include <vplkit/visibility/visibility_callables.hpp>
#include <vplkit/vpl/luminance.hpp>

#include <glm/vec4.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace {

using namespace vplkit::vk_test;
using v3f = vplkit::vec3<float>;
using vplkit_test::surfels;
constexpr slot_kind S = slot_kind::storage;
constexpr slot_kind U = slot_kind::uniform;

struct scene_fixture {
  vplkit_test::synthetic_scene<float> scene;
  int R = 32;
  vplkit_test::dprsm_data<float> dprsm = scene.make_dprsm(32);
  vplkit::voxel_grid<float> grid = scene.make_voxel_grid(32);
  vplkit_test::gbuffer_data<float> gbuffer = scene.make_gbuffer(24, 24);
  scene_fixture() {
    // Background pixels: rows 3..5 and a block of columns, so that strata retry and drop.
    for (int y = 3; y < 6; ++y)
      for (int x = 0; x < 24; ++x) gbuffer.normal[std::size_t(y * 24 + x)] = v3f(0);
    for (int y = 12; y < 24; ++y)
      for (int x = 0; x < 5; ++x) gbuffer.normal[std::size_t(y * 24 + x)] = v3f(0);
  }
};

const scene_fixture& fx() {
  static const scene_fixture* f = new scene_fixture();
  return *f;
}


}  // namespace

TEST_CASE("gather_subset.comp on Vulkan: the C++ stratified subsets pixel for pixel") {
  const auto& s = fx();
  const auto gb = s.gbuffer.view();
  struct case_t {
    vplkit::pixel_rect rect;
    int count;
    std::uint32_t seed, offset;
    int attempts;
  };
  std::vector<case_t> cases = {{vplkit::full_image_rect(gb), 64, 7u, 0u, 4},
                               {vplkit::full_image_rect(gb), 576, 9u, 0u, 4},
                               {vplkit::full_image_rect(gb), 1000, 9u, 5u, 1},
                               {vplkit::pixel_rect{0, 12, 5, 12}, 20, 3u, 0u, 4},
                               {vplkit::pixel_rect{3, 2, 7, 1}, 5, 3u, 0u, 2}};
  const auto regions = vplkit::make_image_regions(gb, 2, 2);
  for (int i = 0; i < regions.count(); ++i) cases.push_back({regions.region_rect(i), 16, 11u, std::uint32_t(i) * 16u, 4});

  with_vulkan([&](context& ctx) {
    const kernel k(ctx, "gather_subset",
                   {{VPLKIT_GATHER_SUBSET_BINDING_GBUFFER, S}, {VPLKIT_GATHER_SUBSET_BINDING_PIXELS, S},
                    {VPLKIT_GATHER_SUBSET_BINDING_PARAMS, U}});
    const buffer gbuf = buffer::from_vector(ctx, surfels(s.gbuffer.position, s.gbuffer.normal, s.gbuffer.albedo));
    std::size_t dropped_total = 0;
    for (const case_t& c : cases) {
      const auto shape = vplkit::gather_subset_grid(c.rect, c.count);
      const vplkit::gpu::gather_subset_params p =
          vplkit::gpu::make_gather_subset_params(gb, c.rect, c.count, c.seed, c.offset, c.attempts, 3u);
      const buffer params = buffer::from_bytes(ctx, &p, sizeof p);
      const buffer out(ctx, std::size_t(shape.count + 3) * 4, 0xFF);  // -1 everywhere
      run(ctx, k,
          {{VPLKIT_GATHER_SUBSET_BINDING_GBUFFER, &gbuf}, {VPLKIT_GATHER_SUBSET_BINDING_PIXELS, &out},
           {VPLKIT_GATHER_SUBSET_BINDING_PARAMS, &params}},
          groups_for(std::size_t(shape.count), VPLKIT_GATHER_SUBSET_LOCAL_SIZE));
      const auto all = out.read<std::int32_t>();
      const std::vector<std::int32_t> gpu(all.begin() + 3, all.end());
      std::vector<std::int32_t> cpu;
      std::vector<int> compact;
      for (int k2 = 0; k2 < shape.count; ++k2) {
        cpu.push_back(vplkit::gather_subset_pick(gb, c.rect, shape, k2, c.seed, c.offset, c.attempts));
        if (cpu.back() >= 0) compact.push_back(cpu.back());
      }
      dropped_total += cpu.size() - compact.size();
      INFO("rect (" << c.rect.x0 << ", " << c.rect.y0 << ", " << c.rect.width << " x " << c.rect.height << "), count "
                    << c.count << ", first differing stratum " << first_difference(gpu, cpu));
      CHECK(compact == vplkit::stratified_gather_subset(gb, c.rect, c.count, c.seed, c.offset, c.attempts));
      CHECK(all[0] == -1);  // before out_offset: untouched
      CHECK(gpu == cpu);
    }
    std::cout << "  " << cases.size() << " rectangles, " << dropped_total << " strata dropped, all equal\n";
    CHECK(dropped_total > 0);  // the background made strata drop: the -1 path ran
  });
}

namespace {

std::vector<float> run_global_weights(context& ctx, const kernel& k, const std::vector<std::vector<int>>& subsets,
                                      float dmin) {
  const auto& s = fx();
  const vplkit_test::global_weights_inputs in =
      vplkit_test::make_global_weights_inputs(subsets, s.dprsm, s.gbuffer.width * s.gbuffer.height, dmin);
  const int n = vplkit::texel_count(s.R);
  const int N = int(subsets.size());
  const buffer gb = buffer::from_vector(ctx, surfels(s.gbuffer.position, s.gbuffer.normal, s.gbuffer.albedo));
  const buffer dp = buffer::from_vector(ctx, surfels(s.dprsm.position, s.dprsm.normal, s.dprsm.albedo));
  const buffer sb = buffer::from_vector(ctx, in.flat);
  const buffer ob = buffer::from_vector(ctx, in.offsets);
  const buffer wb(ctx, std::size_t(N * n) * 4, 0xFF);
  const buffer ub = buffer::from_bytes(ctx, &in.params, sizeof in.params);
  run(ctx, k,
      {{VPLKIT_GLOBAL_WEIGHTS_BINDING_GBUFFER, &gb}, {VPLKIT_GLOBAL_WEIGHTS_BINDING_DPRSM, &dp},
       {VPLKIT_GLOBAL_WEIGHTS_BINDING_SUBSET, &sb}, {VPLKIT_GLOBAL_WEIGHTS_BINDING_OFFSETS, &ob},
       {VPLKIT_GLOBAL_WEIGHTS_BINDING_WEIGHTS, &wb}, {VPLKIT_GLOBAL_WEIGHTS_BINDING_PARAMS, &ub}},
      groups_for(std::size_t(n), VPLKIT_GLOBAL_WEIGHTS_LOCAL_SIZE), 1u, std::uint32_t(N));  // regions along z
  return wb.read<float>();
}

void check_weights(const std::vector<float>& gpu, const std::vector<float>& cpu, double rel, const std::string& what) {
  std::size_t zero_mismatch = 0;
  for (std::size_t t = 0; t < cpu.size(); ++t) zero_mismatch += (gpu[t] == 0.0f) != (cpu[t] == 0.0f);
  const worst_relative w = max_relative(gpu, cpu);
  std::cout << "  " << what << ": worst relative difference " << show(w.value) << " (bound " << rel << ")\n";
  INFO(what << ": worst at " << w.index << ", gpu " << show(gpu[w.index]) << " cpu " << show(cpu[w.index]));
  REQUIRE(gpu.size() == cpu.size());
  CHECK(zero_mismatch == 0u);
  CHECK(w.value <= rel);
}

}  // namespace

TEST_CASE("global_weights.comp on Vulkan: global and local weights against the C++ builders") {
  const auto& s = fx();
  const auto gb = s.gbuffer.view();
  const auto view = s.dprsm.view();
  const int n = view.texel_count();
  const double rel = 2e-6;  // the GL parity test's bound (per-term float error of the VPL model)
  with_vulkan([&](context& ctx) {
    const kernel k(ctx, "global_weights",
                   {{VPLKIT_GLOBAL_WEIGHTS_BINDING_GBUFFER, S}, {VPLKIT_GLOBAL_WEIGHTS_BINDING_DPRSM, S},
                    {VPLKIT_GLOBAL_WEIGHTS_BINDING_SUBSET, S}, {VPLKIT_GLOBAL_WEIGHTS_BINDING_OFFSETS, S},
                    {VPLKIT_GLOBAL_WEIGHTS_BINDING_WEIGHTS, S}, {VPLKIT_GLOBAL_WEIGHTS_BINDING_PARAMS, U}});
    for (float dmin : {0.05f, 0.0f}) {
      // A stratified subset; the same with background entries (both sides skip them), a -1 and an
      // index outside the image (GPU only: the C++ would throw); empty; all background.
      const auto subset = vplkit::stratified_gather_subset(gb, vplkit::full_image_rect(gb), 64, 7u);
      std::vector<int> odd = subset;
      odd.insert(odd.begin() + 3, 3 * 24 + 4);
      odd.push_back(13 * 24 + 1);
      std::vector<int> odd_gpu = odd;
      odd_gpu.insert(odd_gpu.begin() + 7, -1);
      odd_gpu.push_back(24 * 24 + 5);
      const std::vector<std::vector<int>> gpu_cases = {subset, odd_gpu, {}, {3 * 24}};
      const std::vector<std::vector<int>> cpu_cases = {subset, odd, {}, {3 * 24}};
      const char* names[] = {"stratified |S| = 64", "background / -1 / outside entries", "empty subset",
                             "all-background subset"};
      for (std::size_t c = 0; c < gpu_cases.size(); ++c)
        check_weights(run_global_weights(ctx, k, {gpu_cases[c]}, dmin),
                      vplkit::build_global_weights(gb, cpu_cases[c], view, dmin), rel,
                      std::string("global weights, ") + names[c] + ", dmin " + show(dmin));
    }
    const auto regions = vplkit::make_image_regions(gb, 2, 2);
    const auto subsets = vplkit::local_gather_subsets(gb, regions, 16, 11u);
    std::vector<float> cpu(std::size_t(4 * n));
    int used[4];
    vplkit::build_local_weights(gb, regions, subsets, view, 0.05f, cpu.data(), cpu.size(), used);
    check_weights(run_global_weights(ctx, k, subsets, 0.05f), cpu, rel, "local weights, 2 x 2 regions");
  });
}

// ---- GBG ----------------------------------------------------------------------------------------
namespace {

struct gbg_result {
  std::vector<std::uint32_t> acc;    // (lo, hi) per texel
  std::vector<std::uint32_t> stats;  // VPLKIT_GBG_STAT_*
  std::vector<float> weights;
};

struct gbg_kernels {
  kernel accumulate, finish;
  explicit gbg_kernels(context& ctx)
      : accumulate(ctx, "gbg_accumulate",
                   {{VPLKIT_GBG_BINDING_GBUFFER, S}, {VPLKIT_GBG_BINDING_DPRSM, S}, {VPLKIT_GBG_BINDING_VOXELS, S},
                    {VPLKIT_GBG_BINDING_ACC, S}, {VPLKIT_GBG_BINDING_STATS, S}, {VPLKIT_GBG_BINDING_PARAMS, U}}),
        finish(ctx, "gbg_finish",
               {{VPLKIT_GBG_FINISH_BINDING_ACC, S}, {VPLKIT_GBG_FINISH_BINDING_STATS, S},
                {VPLKIT_GBG_FINISH_BINDING_DPRSM, S}, {VPLKIT_GBG_FINISH_BINDING_WEIGHTS, S},
                {VPLKIT_GBG_FINISH_BINDING_PARAMS, U}}) {}
};

// One accumulation dispatch per direction range, then the finish, in one command buffer.
gbg_result run_gbg(context& ctx, const gbg_kernels& k, const vplkit_test::gbuffer_data<float>& gbuffer,
                   const vplkit_test::gbg_setup& st, const std::vector<std::pair<int, int>>& ranges, bool fill) {
  const auto& s = fx();
  const int n = vplkit::texel_count(s.R);
  const buffer gb = buffer::from_vector(ctx, surfels(gbuffer.position, gbuffer.normal, gbuffer.albedo));
  const buffer dp = buffer::from_vector(ctx, surfels(s.dprsm.position, s.dprsm.normal, s.dprsm.albedo));
  const buffer vx = buffer::from_vector(ctx, s.grid.words());
  const buffer acc(ctx, std::size_t(2 * n) * 4, 0);
  const buffer stats(ctx, VPLKIT_GBG_STATS_SIZE * 4, 0);
  const buffer weights(ctx, std::size_t(n) * 4, 0xFF);
  std::vector<buffer> blocks;
  blocks.reserve(ranges.size() + 1);
  std::vector<dispatch_step> steps;
  for (std::size_t r = 0; r < ranges.size(); ++r) {
    const vplkit::gpu::gbg_accumulate_params p = vplkit_test::gbg_accumulate_block(
        s.dprsm, s.grid, gbuffer.width, gbuffer.height, st, ranges[r].first, ranges[r].second, r == 0);
    blocks.push_back(buffer::from_bytes(ctx, &p, sizeof p));
    steps.push_back({&k.accumulate,
                     {{VPLKIT_GBG_BINDING_GBUFFER, &gb}, {VPLKIT_GBG_BINDING_DPRSM, &dp}, {VPLKIT_GBG_BINDING_VOXELS, &vx},
                      {VPLKIT_GBG_BINDING_ACC, &acc}, {VPLKIT_GBG_BINDING_STATS, &stats},
                      {VPLKIT_GBG_BINDING_PARAMS, &blocks.back()}},
                     groups_for(std::size_t(gbuffer.width * gbuffer.height), VPLKIT_GBG_LOCAL_SIZE)});
  }
  const vplkit::gpu::gbg_finish_params f = vplkit_test::gbg_finish_block(s.dprsm, st, fill);
  blocks.push_back(buffer::from_bytes(ctx, &f, sizeof f));
  const std::uint32_t g = groups_for(std::size_t(s.R), VPLKIT_GBG_FINISH_LOCAL_SIZE);
  steps.push_back({&k.finish,
                   {{VPLKIT_GBG_FINISH_BINDING_ACC, &acc}, {VPLKIT_GBG_FINISH_BINDING_STATS, &stats},
                    {VPLKIT_GBG_FINISH_BINDING_DPRSM, &dp}, {VPLKIT_GBG_FINISH_BINDING_WEIGHTS, &weights},
                    {VPLKIT_GBG_FINISH_BINDING_PARAMS, &blocks.back()}},
                   g, g, 2});
  run(ctx, steps);
  return {acc.read<std::uint32_t>(), stats.read<std::uint32_t>(), weights.read<float>()};
}

// Weights against the C++ within the stated bound; returns the texels outside it.
std::size_t texels_outside(const std::vector<float>& gpu, const std::vector<float>& cpu, const vplkit_test::gbg_setup& st,
                           std::uint32_t lit_hits, int gather_points, const std::string& what) {
  const double quantum = double(lit_hits) * 0.5 / double(st.scale) / (double(gather_points) * st.n_dirs);
  std::size_t outside = 0;
  double worst = 0;
  std::size_t worst_t = 0;
  for (std::size_t t = 0; t < cpu.size(); ++t) {
    const double a = gpu[t], b = cpu[t];
    const double bound = quantum + 5e-6 * std::fabs(b);
    const double r = std::fabs(a - b) / bound;
    if (!(r <= 1.0) || (a == 0) != (b == 0)) ++outside;
    if (!(r <= worst)) {
      worst = r;
      worst_t = t;
    }
  }
  std::cout << "  " << what << ": worst |gpu - cpu| / bound " << show(worst) << " at texel " << worst_t << " (gpu "
            << show(gpu[worst_t]) << ", cpu " << show(cpu[worst_t]) << "), " << outside << " texels outside\n";
  return outside;
}

int valid_points(const vplkit_test::gbuffer_data<float>& g) {
  int n = 0;
  for (int p = 0; p < g.width * g.height; ++p) n += vplkit::gather_point_valid(g.view().at(p)) ? 1 : 0;
  return n;
}

}  // namespace

TEST_CASE("gbg_accumulate.comp + gbg_finish.comp on Vulkan: fixed-point GBG weights against build_gbg_weights") {
  const auto& s = fx();
  const auto view = s.dprsm.view();
  const int n = view.texel_count();
  const int G = valid_points(s.gbuffer);
  const std::size_t rays = std::size_t(s.gbuffer.width * s.gbuffer.height) * 16u;
  with_vulkan([&](context& ctx) {
    const gbg_kernels k(ctx);
    for (int accumulator : {1, 0}) {
      vplkit_test::gbg_setup st;
      st.accumulator = accumulator;
      st.tol = 0.2f + vplkit::voxel_tracer_depth_tolerance(s.grid.view());
      vplkit_test::choose_gbg_fixed_point(st, G, s.dprsm);
      const std::string name = accumulator == 1 ? "GBG gathering" : "GBG paper";
      const gbg_result one = run_gbg(ctx, k, s.gbuffer, st, {{0, st.n_dirs}}, false);
      const gbg_result split = run_gbg(ctx, k, s.gbuffer, st, {{0, 5}, {5, 11}, {11, st.n_dirs}}, false);
      CHECK(split.acc == one.acc);  // exact, order-independent sums
      CHECK(split.stats == one.stats);
      CHECK(one.stats[VPLKIT_GBG_STAT_SATURATED_HITS] == 0u);

      for (bool fill : {false, true}) {
        vplkit::gbg_stats cs;
        const auto cpu = vplkit::build_gbg_weights(s.gbuffer.view(), view, vplkit::voxel_tracer<float>{s.grid.view()},
                                                   vplkit_test::gbg_cpu_params(st, fill), &cs);
        const gbg_result gpu = fill ? run_gbg(ctx, k, s.gbuffer, st, {{0, st.n_dirs}}, true) : one;
        const std::string what = name + (fill ? ", filled" : ", raw");
        const auto& g = gpu.stats;
        std::cout << "  " << what << ": |G| " << g[VPLKIT_GBG_STAT_GATHER_POINTS] << " / " << cs.gather_points
                  << ", hits " << g[VPLKIT_GBG_STAT_HITS] << " / " << cs.hits << ", lit hits "
                  << g[VPLKIT_GBG_STAT_LIT_HITS] << " / " << cs.lit_hits << ", reached "
                  << g[VPLKIT_GBG_STAT_REACHED_TEXELS] << " / " << cs.reached_texels << ", holes "
                  << g[VPLKIT_GBG_STAT_HOLES] << " / " << cs.holes << ", filled " << g[VPLKIT_GBG_STAT_FILLED] << " / "
                  << cs.filled << " (GPU / C++)\n";
        CHECK(g[VPLKIT_GBG_STAT_GATHER_POINTS] == std::uint32_t(cs.gather_points));
        const auto off = [](std::uint32_t a, std::size_t b) { return std::size_t(std::llabs(std::int64_t(a) - std::int64_t(b))); };
        CHECK(off(g[VPLKIT_GBG_STAT_HITS], cs.hits) + off(g[VPLKIT_GBG_STAT_LIT_HITS], cs.lit_hits) <= rays / 200);
        CHECK(texels_outside(gpu.weights, cpu, st, g[VPLKIT_GBG_STAT_LIT_HITS], G, what) <= std::size_t(n) / 50);
      }

      // Carries: a scale that puts ~2^40 units in a typical reached texel, so its low word wraps
      // about 256 times; a lost or doubled carry would be off by 2^32 units (2^-8 relative).
      std::vector<float> sums;
      const auto cpu = vplkit::build_gbg_weights(s.gbuffer.view(), view, vplkit::voxel_tracer<float>{s.grid.view()},
                                                 vplkit_test::gbg_cpu_params(st, false));
      for (float w : cpu)
        if (w > 0) sums.push_back(w * float(G) * float(st.n_dirs));
      REQUIRE(!sums.empty());
      std::nth_element(sums.begin(), sums.begin() + std::ptrdiff_t(sums.size() / 2), sums.end());
      vplkit_test::gbg_setup big = st;
      big.scale = std::ldexp(1.0f, 40 - int(std::floor(std::log2(sums[sums.size() / 2]))));
      big.max_units = std::ldexp(1.0f, 52);
      const gbg_result r = run_gbg(ctx, k, s.gbuffer, big, {{0, big.n_dirs}}, false);
      std::size_t high = 0;
      for (std::size_t t = 0; t < r.acc.size(); t += 2) high += r.acc[t + 1] != 0 ? 1 : 0;
      std::cout << "  " << name << " carries: scale 2^" << std::log2(big.scale) << ", " << high
                << " texels with a non-zero high word\n";
      CHECK(high > 100);
      CHECK(r.stats[VPLKIT_GBG_STAT_SATURATED_HITS] == 0u);
      CHECK(texels_outside(r.weights, cpu, big, r.stats[VPLKIT_GBG_STAT_LIT_HITS], G, name + ", carries") <=
            std::size_t(n) / 50);
    }
  });
}

TEST_CASE("GBG kernels on Vulkan: an all-background G-buffer gives +0 weights and zero counts") {
  const auto& s = fx();
  const vplkit_test::all_background_gbg bg(s.gbuffer, s.dprsm.view(), s.grid);
  with_vulkan([&](context& ctx) {
    const gbg_kernels k(ctx);
    const gbg_result r = run_gbg(ctx, k, bg.gbuffer, bg.setup, {{0, bg.setup.n_dirs}}, true);
    CHECK(bits_of(r.weights) == std::vector<std::uint32_t>(r.weights.size(), 0u));
    for (int c : vplkit_test::all_background_gbg::zero_stats) CHECK(r.stats[std::size_t(c)] == 0u);
    CHECK(r.stats[VPLKIT_GBG_STAT_HOLES] == bg.cpu_holes);  // every VPL texel stays a hole
  });
}
