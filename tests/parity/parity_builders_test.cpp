// SPDX-License-Identifier: MIT
// CPU/GPU parity of the builder kernels glsl/vplkit/builders/*.comp (and their include files) with
// include/vplkit/builders/*.hpp (T = float) on the synthetic scene of tests/support/
// synthetic_scene.hpp: DPRSM R = 32, 32^3 voxel grid, a 24 x 24 G-buffer (with a band of background
// pixels), the voxel tracer on both sides.
//
//  - gather_subset.comp: the stratified subsets, whole image and 2 x 2 regions: EXACT pixel indices
//    (integer arithmetic, one correctly rounded float product, the bit-exact counter_rng).
//  - global_weights.comp: global and local weights against build_global_weights /
//    build_local_weights within a relative bound (float sums in the same order; per-term float
//    error of the VPL model), exact zeros on texels without a VPL.
//  - flux_weights.comp: every texel's flux weight against build_flux_weights within 16 ulps (the
//    solid angle's division and a few products), exact zeros on texels without a VPL.
//  - gbg_accumulate.comp + gbg_finish.comp against build_gbg_weights, both accumulators, fill on
//    and off. Three layers:
//      1. every ray replayed on the GPU (the include functions, one invocation per ray) against the
//         C++ per-ray decisions: texel and lit EXACT except where the direction's sin/cos (a few
//         ulp off on the GPU) flips a voxel, a texel, the depth test or the back-face sign near a
//         tie -- those rays are counted and bounded; hit values within a relative bound;
//      2. the kernel's 64-bit fixed-point sums EXACTLY equal the host's integer sum of the replayed
//         GPU values' units (the atomics and the carry are exact and order-independent), also
//         with carries forced (units above 2^32), saturation (counted exactly), and the rays split
//         over two dispatches;
//      3. the finished (and filled) weights against the C++ within the stated fixed-point
//         precision plus the per-hit float bound, texels touched by a flipped ray (and, with the
//         fill, their 3 x 3 neighbourhood) excluded and counted; stats equal the C++ gbg_stats.
#include "parity_estimators_support.hpp"

#include <gbg_kernels.hpp>
#include <gpu_precision.hpp>

#include <vplkit/builders/flux_weights.hpp>
#include <vplkit/builders/flux_weights_params.h>
#include <vplkit/builders/gather_subset.hpp>
#include <vplkit/builders/gather_subset_params.h>
#include <vplkit/builders/gbg_accumulate_params.h>
#include <vplkit/builders/gbg_finish_params.h>
#include <vplkit/builders/gbg_weights.hpp>
#include <vplkit/builders/global_weights.hpp>
#include <vplkit/builders/global_weights_params.h>
#include <vplkit/builders/local_weights.hpp>
#include <vplkit/builders/tile_blocks.hpp>
#include <vplkit/builders/tile_blocks_params.h>
#include <vplkit/builders/tile_weights_params.h>
#include <vplkit/paraboloid/texel_grid.hpp>
#include <vplkit/visibility/visibility_callables.hpp>
#include <vplkit/vpl/luminance.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <map>
#include <set>
#include <string>
#include <vector>

using namespace vplkit::parity;
using namespace vplkit::parity::est;
using vplkit_test::gbg_setup;

namespace {
// A GBG hit's value is a gathering sample's (spec::gathering_sample_rel); over the synthetic
// scene's rays t / d1 reaches 10.8 (parity_estimators_test prints it per estimate): 12, 3.8e-5.
const double hit_rel = vplkit_test::spec::gathering_sample_rel(12);
}  // namespace

namespace {

struct fixture_t {
  scene_fixture s{32, 32, 24, 24};
  fixture_t() {
    // Background pixels: a band of rows 3..5 and a block of columns, so that strata retry and drop.
    for (int y = 3; y < 6; ++y)
      for (int x = 0; x < 24; ++x) s.gbuffer.normal[std::size_t(y * 24 + x)] = v3f(0);
    for (int y = 12; y < 24; ++y)
      for (int x = 0; x < 5; ++x) s.gbuffer.normal[std::size_t(y * 24 + x)] = v3f(0);
    // Two normals at every third pixel: the shading normal 50 degrees off the geometric one, so
    // GBG's frame is the shading normal's and some of its directions fall below the surface.
    s.gbuffer.shading_normal.assign(s.gbuffer.position.size(), v3f(0));
    for (std::size_t p = 0; p < s.gbuffer.position.size(); p += 3) {
      const v3f n = s.gbuffer.normal[p];
      if (!(glm::dot(n, n) > 0.0f)) continue;
      const v3f nn = glm::normalize(n);
      const v3f side = glm::normalize(glm::cross(nn, std::abs(nn.x) < 0.9f ? v3f(1, 0, 0) : v3f(0, 1, 0)));
      s.gbuffer.shading_normal[p] = 0.6428f * nn + 0.7660f * side;
    }
  }
};

const fixture_t& fx() {
  static const fixture_t* f = new fixture_t();
  return *f;
}

std::vector<float4> gbuffer_surfels(const vplkit_test::gbuffer_data<float>& g) {
  return vplkit_test::surfels(g.position, g.normal, g.albedo, g.shading_normal.empty() ? nullptr : &g.shading_normal);
}
std::vector<float4> dprsm_surfels(const vplkit_test::dprsm_data<float>& d) {
  return vplkit_test::surfels(d.position, d.normal, d.albedo);
}

}  // namespace

// =================================================================================================

TEST_CASE("gather_subset.comp: the C++ stratified subsets, pixel for pixel") {
  const auto& s = fx().s;
  const auto gb = s.gbuffer.view();
  const auto& prog = pack_kernel("vplkit/builders/gather_subset.comp");
  const auto gbuf = vplkit::gl::buffer::from_vector(gbuffer_surfels(s.gbuffer));
  struct run {
    vplkit::pixel_rect rect;
    int count;
    std::uint32_t seed, offset;
    int attempts;
  };
  std::vector<run> runs = {{vplkit::full_image_rect(gb), 64, 7u, 0u, 4}, {vplkit::full_image_rect(gb), 576, 9u, 0u, 4},
                           {vplkit::full_image_rect(gb), 1000, 9u, 5u, 1}, {vplkit::pixel_rect{0, 12, 5, 12}, 20, 3u, 0u, 4},
                           {vplkit::pixel_rect{3, 2, 7, 1}, 5, 3u, 0u, 2}};
  const auto regions = vplkit::make_image_regions(gb, 2, 2);
  for (int i = 0; i < regions.count(); ++i)
    runs.push_back({regions.region_rect(i), 16, 11u, std::uint32_t(i) * 16u, 4});
  std::size_t dropped_total = 0;
  for (const run& r : runs) {
    const auto shape = vplkit::gather_subset_grid(r.rect, r.count);
    const auto ub = vplkit_test::uniform_buffer(
        vplkit::gpu::make_gather_subset_params(gb, r.rect, r.count, r.seed, r.offset, r.attempts, 3u));
    const auto out = vplkit::gl::buffer::filled(std::size_t(shape.count + 3) * 4, 0xFF);
    vplkit_test::dispatch(prog, {vplkit::gl::groups_for(std::size_t(shape.count), VPLKIT_GATHER_SUBSET_LOCAL_SIZE), 1, 1},
                          {vplkit_test::storage_at(VPLKIT_GATHER_SUBSET_BINDING_GBUFFER, gbuf),
                           vplkit_test::storage_at(VPLKIT_GATHER_SUBSET_BINDING_PIXELS, out),
                           vplkit_test::uniform_at(VPLKIT_GATHER_SUBSET_BINDING_PARAMS, ub)});
    const auto gpu = out.read<std::int32_t>();
    std::vector<std::int32_t> g(gpu.begin() + 3, gpu.end()), c;
    for (int k = 0; k < shape.count; ++k)
      c.push_back(vplkit::gather_subset_pick(gb, r.rect, shape, k, r.seed, r.offset, r.attempts));
    // The C++ list is the same without the dropped strata.
    std::vector<int> compact;
    for (int v : c)
      if (v >= 0) compact.push_back(v);
    const std::size_t dropped = c.size() - compact.size();
    dropped_total += dropped;
    CHECK(compact == vplkit::stratified_gather_subset(gb, r.rect, r.count, r.seed, r.offset, r.attempts));
    CHECK(gpu[0] == -1);  // untouched before out_offset
    const std::string what = "gather_subset rect (" + std::to_string(r.rect.x0) + ", " + std::to_string(r.rect.y0) + ", " +
                             std::to_string(r.rect.width) + " x " + std::to_string(r.rect.height) + ") count " +
                             std::to_string(r.count) + " (" + std::to_string(dropped) + " dropped)";
    VPLKIT_CHECK_PARITY(compare_exact(g, c, [](std::size_t k) { return "stratum " + std::to_string(k); }, what));
  }
  CHECK(dropped_total > 0);  // the background band made some strata drop: the -1 path ran
}

// ---- global / local weights ----------------------------------------------------------------------
namespace {

std::vector<float> run_global_weights(const std::vector<std::vector<int>>& subsets, float dmin) {
  const auto& s = fx().s;
  const auto& prog = pack_kernel("vplkit/builders/global_weights.comp");
  const vplkit_test::global_weights_inputs in =
      vplkit_test::make_global_weights_inputs(subsets, s.dprsm, s.gbuffer.width * s.gbuffer.height, dmin);
  const int n = vplkit::texel_count(s.R);
  const int N = int(subsets.size());
  const auto gb = vplkit::gl::buffer::from_vector(gbuffer_surfels(s.gbuffer));
  const auto dp = vplkit::gl::buffer::from_vector(dprsm_surfels(s.dprsm));
  const auto sb = vplkit::gl::buffer::from_vector(in.flat);
  const auto ob = vplkit::gl::buffer::from_vector(in.offsets);
  const auto wb = vplkit::gl::buffer::filled(std::size_t(N * n) * 4, 0xFF);
  const auto ub = vplkit_test::uniform_buffer(in.params);
  // The texels spread over x and y, the regions along z (global_weights.comp).
  vplkit_test::bind({vplkit_test::storage_at(VPLKIT_GLOBAL_WEIGHTS_BINDING_GBUFFER, gb),
                     vplkit_test::storage_at(VPLKIT_GLOBAL_WEIGHTS_BINDING_DPRSM, dp),
                     vplkit_test::storage_at(VPLKIT_GLOBAL_WEIGHTS_BINDING_SUBSET, sb),
                     vplkit_test::storage_at(VPLKIT_GLOBAL_WEIGHTS_BINDING_OFFSETS, ob),
                     vplkit_test::storage_at(VPLKIT_GLOBAL_WEIGHTS_BINDING_WEIGHTS, wb),
                     vplkit_test::uniform_at(VPLKIT_GLOBAL_WEIGHTS_BINDING_PARAMS, ub)});
  vplkit::gl::dispatch_linear(prog, vplkit::gl::groups_for(std::size_t(n), VPLKIT_GLOBAL_WEIGHTS_LOCAL_SIZE), GLuint(N));
  return wb.read<float>();
}

}  // namespace

TEST_CASE("global_weights.comp: global and local weights against the C++ builders") {
  const auto& s = fx().s;
  const auto gb = s.gbuffer.view();
  const auto view = s.view();
  const int n = view.texel_count();
  // Per texel: |S| terms luminance(vpl_contribution), each within a few ulps (FMA contraction,
  // the GPU's normalisation; parity_vpl_test), summed in the same order: the relative error of a
  // sum of positive terms is at most the largest term's. Measured worst: docs/glsl/builders.md;
  // bound 2e-6.
  const double rel = 2e-6;
  for (float dmin : {0.05f, 0.0f}) {
    // Global: a stratified subset, plus a hand-made one with background pixels, an index outside
    // the image and a dropped-stratum marker (skipped and not counted on the GPU; the C++ skips the
    // background entries; it would throw for the others, so they are left out there).
    auto subset = vplkit::stratified_gather_subset(gb, vplkit::full_image_rect(gb), 64, 7u);
    std::vector<int> odd = subset;
    odd.insert(odd.begin() + 3, 3 * 24 + 4);  // background (row 3)
    odd.push_back(13 * 24 + 1);               // background (column block)
    std::vector<int> odd_gpu = odd;
    odd_gpu.insert(odd_gpu.begin() + 7, -1);
    odd_gpu.push_back(24 * 24 + 5);           // outside the image
    const std::vector<std::vector<int>> cases_gpu = {subset, odd_gpu, {}, {3 * 24}};
    const std::vector<std::vector<int>> cases_cpu = {subset, odd, {}, {3 * 24}};
    const char* names[4] = {"stratified |S| = 64", "with background / -1 / outside entries", "empty subset",
                            "all-background subset"};
    for (std::size_t c = 0; c < cases_gpu.size(); ++c) {
      const auto gpu = run_global_weights({cases_gpu[c]}, dmin);
      const auto cpu = vplkit::build_global_weights(gb, cases_cpu[c], view, dmin);
      std::vector<std::int32_t> gz, cz;
      for (int t = 0; t < n; ++t) {
        gz.push_back(gpu[std::size_t(t)] == 0.0f);
        cz.push_back(cpu[std::size_t(t)] == 0.0f);
      }
      const std::string what = std::string("global weights [") + names[c] + "] dmin " + show(dmin);
      VPLKIT_CHECK_PARITY(compare_exact(gz, cz, [](std::size_t t) { return "texel " + std::to_string(t); },
                                        what + ": zero / non-zero"));
      VPLKIT_CHECK_PARITY(compare_floats(gpu, cpu, within_rel(rel),
                                         [](std::size_t t) { return "texel " + std::to_string(t); }, what));
    }
  }
  // Local: 2 x 2 regions, the C++ subsets, region-major output.
  {
    const auto regions = vplkit::make_image_regions(gb, 2, 2);
    const auto subsets = vplkit::local_gather_subsets(gb, regions, 16, 11u);
    std::vector<float> cpu(std::size_t(4 * n));
    int used[4];
    vplkit::build_local_weights(gb, regions, subsets, view, 0.05f, cpu.data(), cpu.size(), used);
    const auto gpu = run_global_weights(subsets, 0.05f);
    std::cout << "  local subsets |S_i| = " << used[0] << ", " << used[1] << ", " << used[2] << ", " << used[3] << "\n";
    VPLKIT_CHECK_PARITY(compare_floats(gpu, cpu, within_rel(rel),
                                       [n](std::size_t t) {
                                         return "region " + std::to_string(t / std::size_t(n)) + " texel " +
                                                std::to_string(t % std::size_t(n));
                                       },
                                       "local weights 2 x 2, 16 per region"));
  }
}

// ---- flux weights ---------------------------------------------------------------------------------
TEST_CASE("flux_weights.comp: build_flux_weights on every texel") {
  const auto& s = fx().s;
  const auto view = s.view();
  const int n = view.texel_count();
  vplkit::gpu::flux_weights_params params{};
  params.light = vplkit::gpu::make_light_params(view.light);
  params.resolution = s.R;
  const auto& prog = pack_kernel("vplkit/builders/flux_weights.comp");
  const auto dp = vplkit::gl::buffer::from_vector(dprsm_surfels(s.dprsm));
  const auto wb = vplkit::gl::buffer::filled(std::size_t(n) * 4, 0xFF);  // NaN: a texel not written fails
  const auto ub = vplkit_test::uniform_buffer(params);
  vplkit_test::bind({vplkit_test::storage_at(VPLKIT_FLUX_WEIGHTS_BINDING_DPRSM, dp),
                     vplkit_test::storage_at(VPLKIT_FLUX_WEIGHTS_BINDING_WEIGHTS, wb),
                     vplkit_test::uniform_at(VPLKIT_FLUX_WEIGHTS_BINDING_PARAMS, ub)});
  vplkit::gl::dispatch_linear(prog, vplkit::gl::groups_for(std::size_t(n), VPLKIT_FLUX_WEIGHTS_LOCAL_SIZE));
  const std::vector<float> gpu = wb.read<float>();
  const std::vector<float> cpu = vplkit::build_flux_weights(view);
  std::vector<std::int32_t> gz, cz;
  for (int t = 0; t < n; ++t) {
    gz.push_back(gpu[std::size_t(t)] == 0.0f);
    cz.push_back(cpu[std::size_t(t)] == 0.0f);
  }
  CHECK(std::count(cz.begin(), cz.end(), 0) > n / 4);  // the scene lights a good share of the texels
  const auto where = [](std::size_t t) { return "texel " + std::to_string(t); };
  VPLKIT_CHECK_PARITY(compare_exact(gz, cz, where, "flux weights: zero / non-zero"));
  // rho I Omega (a division in the solid angle, a few products) and the luminance's three terms.
  VPLKIT_CHECK_PARITY(compare_floats(gpu, cpu, within_ulps(16) | within_abs(0.0), where, "flux weights"));
}

// ---- GBG ----------------------------------------------------------------------------------------
namespace {

struct gbg_gpu_result {
  std::vector<std::uint32_t> acc;    // (lo, hi) per texel
  std::vector<std::uint32_t> stats;  // VPLKIT_GBG_STATS_SIZE counters (VPLKIT_GBG_STAT_*)
  std::vector<float> weights;
};

// Accumulate over the direction ranges (one parameter block each), then finish.
gbg_gpu_result run_gbg(const vplkit_test::gbuffer_data<float>& gbuf, const gbg_setup& st,
                       const std::vector<std::pair<int, int>>& ranges, bool fill) {
  const auto& s = fx().s;
  context();
  const vplkit_test::gbg_buffers b(gbuf, s.dprsm, s.grid, 0xFF);
  bool first = true;
  for (const auto& range : ranges) {
    b.accumulate(vplkit_test::uniform_buffer(
        vplkit_test::gbg_accumulate_block(s.dprsm, s.grid, gbuf.width, gbuf.height, st, range.first, range.second, first)));
    first = false;
  }
  b.finish(vplkit_test::uniform_buffer(vplkit_test::gbg_finish_block(s.dprsm, st, fill)));
  return {b.acc.read<std::uint32_t>(), b.stats.read<std::uint32_t>(), b.weights.read<float>()};
}

// One ray of the GBG loop: pixel, direction j.
struct ray_out {
  std::int32_t texel;  // -1: no hit / horizon; else the lookup's texel
  std::uint32_t flags;  // 1: hit, 2: counted (lit and carries a VPL)
  float value;
  std::uint32_t pad;
};

std::vector<ray_out> gpu_rays(const vplkit_test::gbuffer_data<float>& gbuf, const gbg_setup& st) {
  const std::string body = R"(
#include "vplkit/builders/gbg_weights.glsl"
struct ray_out { int texel; uint flags; float value; uint pad; };
layout(std430, binding = 1) writeonly buffer Out { ray_out result[]; };
void vplkit_store_gbg_hit(int texel, float value) {}
void main() {
  uint i = gl_GlobalInvocationID.x;
  if (i >= VPLKIT_PARITY_COUNT) return;
  int pixel = int(i) / ip.w, j = int(i) % ip.w;
  vplkit_gather_point g = vplkit_load_gather_point(pixel);
  ray_out o = ray_out(-1, 0u, 0.0, 0u);
  if (vplkit_gather_point_valid(g)) {
    // The body of vplkit_gbg_accumulate_gather_point for direction j.
    vplkit_counter_rng rng = vplkit_make_counter_rng(uint(ip.z), uint(pixel));
    rng.counter = 2u * uint(j);
    float u0 = vplkit_rng_next_unit(rng);
    float u1 = vplkit_rng_next_unit(rng);
    vec3 local = vplkit_sample_cosine_hemisphere(vec2(u0, u1));
    vec3 dir = vplkit_to_world(vplkit_make_orthonormal_basis(vplkit_gather_point_shading_normal(g)), local);
    if (local.z > 0.0 && vplkit_gather_point_accepts_direction(g, dir)) {
      vplkit_ray_hit h = vplkit_voxel_tracer_trace(vplkit_make_voxel_tracer(load_grid()), g.position, g.normal, dir);
      if (h.hit) {
        o.flags = 1u;
        vplkit_dprsm_view view = load_view();
        vplkit_dprsm_lookup_result r = vplkit_dprsm_lookup(view, h.position, fp.y);
        o.texel = r.texel;
        if (!vplkit_vpl_hit_on_own_plane(g.position, h) && r.lit && vplkit_vpl_has_flux(vplkit_dprsm_view_vpl_at(view, r.texel))) {
          o.flags = 3u;
          o.value = vplkit_gbg_hit_value(g, view, r, h, fp.x, ip2.x, fp.y);
        }
      }
    }
  }
  result[i] = o;
}
)";
  const auto& f = fx().s;
  scene_params p = f.params();
  p.ip.z = int(st.seed);
  p.ip.w = st.n_dirs;
  p.ip2.x = st.accumulator;
  p.fp.x = st.dmin;
  p.fp.y = st.tol;
  vplkit::parity::kernel_call call;
  call.name = "gbg_rays.comp";
  call.source = std::string(scene_prelude) + body;
  call.inputs = f.inputs();
  for (auto& in : call.inputs)
    if (in.binding == 8) in = input(8, gbuffer_surfels(gbuf));
  call.inputs.push_back(input(5, std::vector<scene_params>{p}));
  call.inputs.push_back(input(7, std::vector<float4>{{0, 0, 0, 0}}));
  call.output_binding = 1;
  return vplkit::parity::run_compute<ray_out>(call, std::size_t(gbuf.width * gbuf.height * st.n_dirs));
}

// The same rays in C++ (gbg_accumulate_gather_point's loop body, per direction).
std::vector<ray_out> cpu_rays(const vplkit_test::gbuffer_data<float>& gbuf, const gbg_setup& st) {
  const auto& s = fx().s;
  const auto view = s.view();
  const auto gb = gbuf.view();
  const vplkit::voxel_tracer<float> tracer{s.grid.view()};
  std::vector<ray_out> out;
  for (int p = 0; p < gb.pixel_count(); ++p) {
    const auto g = gb.at(p);
    const auto frame = vplkit::make_orthonormal_basis(vplkit::gather_point_shading_normal(g));
    vplkit::counter_rng rng = vplkit::make_counter_rng(st.seed, std::uint32_t(p));
    for (int j = 0; j < st.n_dirs; ++j) {
      ray_out o{-1, 0u, 0.0f, 0u};
      const float u0 = vplkit::rng_next_unit<float>(rng), u1 = vplkit::rng_next_unit<float>(rng);
      if (vplkit::gather_point_valid(g)) {
        const v3f local = vplkit::sample_cosine_hemisphere(vplkit::vec2<float>(u0, u1));
        const v3f dir = vplkit::to_world(frame, local);
        if (local.z > 0 && vplkit::gather_point_accepts_direction(g, dir)) {
          const auto h = tracer(g.position, g.normal, dir);
          if (h.hit) {
            o.flags = 1u;
            const auto r = vplkit::dprsm_lookup(view, h.position, st.tol);
            o.texel = r.texel;
            if (!vplkit::vpl_hit_on_own_plane(g.position, h) && r.lit && vplkit::vpl_has_flux(view.vpl_at(r.texel))) {
              o.flags = 3u;
              o.value = vplkit::gbg_hit_value(g, view, r, h, st.dmin,
                                              st.accumulator == 0 ? vplkit::gbg_accumulator::paper
                                                                  : vplkit::gbg_accumulator::gathering,
                                              st.tol);
            }
          }
        }
      }
      out.push_back(o);
    }
  }
  return out;
}

// The kernel's units for one value, on the host (vplkit_gbg_fixed_units: float arithmetic,
// roundEven = nearbyint in the default rounding mode).
std::uint64_t host_units(float v, float scale, float max_units) {
  if (!(v > 0.0f)) return 0;
  const float q = std::nearbyint(std::min(v * scale, max_units));
  return std::uint64_t(double(q));
}

int valid_points(const vplkit_test::gbuffer_data<float>& gbuf) {
  int n = 0;
  const auto gb = gbuf.view();
  for (int p = 0; p < gb.pixel_count(); ++p) n += vplkit::gather_point_valid(gb.at(p)) ? 1 : 0;
  return n;
}

}  // namespace

TEST_CASE("gbg_accumulate.comp + gbg_finish.comp: fixed-point GBG weights against build_gbg_weights") {
  const auto& s = fx().s;
  const auto view = s.view();
  const int n = view.texel_count();
  const auto gb = s.gbuffer.view();
  const int G = valid_points(s.gbuffer);
  const float tol = 0.2f + vplkit::voxel_tracer_depth_tolerance(s.grid.view());
  for (int accumulator : {1, 0}) {
    gbg_setup st;
    st.accumulator = accumulator;
    st.tol = tol;
    vplkit_test::choose_gbg_fixed_point(st, G, s.dprsm);
    const std::string acc_name = accumulator == 1 ? "gathering" : "paper";
    std::cout << "GBG " << acc_name << ": |G| = " << G << ", " << st.n_dirs << " directions, scale 2^"
              << std::log2(st.scale) << ", max_units 2^" << std::log2(st.max_units) << "\n";

    // 1. Rays: GPU vs C++.
    const auto gr = gpu_rays(s.gbuffer, st);
    const auto cr = cpu_rays(s.gbuffer, st);
    REQUIRE(gr.size() == cr.size());
    std::set<int> flipped_texels;
    std::size_t flips = 0, counted = 0;
    std::vector<float> gv, cv;
    for (std::size_t i = 0; i < gr.size(); ++i) {
      if (gr[i].texel != cr[i].texel || gr[i].flags != cr[i].flags) {
        ++flips;
        if (gr[i].flags == 3u) flipped_texels.insert(gr[i].texel);
        if (cr[i].flags == 3u) flipped_texels.insert(cr[i].texel);
        continue;
      }
      if (cr[i].flags == 3u) {
        ++counted;
        gv.push_back(gr[i].value);
        cv.push_back(cr[i].value);
      }
    }
    std::cout << "  " << gr.size() << " rays, " << counted << " counted hits agree on texel and lit, " << flips
              << " flipped (GPU sin/cos near a tie)\n";
    CHECK(flips <= gr.size() / 200);  // <= 0.5 % of the rays (measured: docs/glsl/builders.md)
    // Per hit: the accumulator's value at the voxel entry point, whose position carries the
    // direction's sin/cos error; L_o ~ 1 / d1^2, vpl_contribution ~ 1 / d2^2: the gathering
    // sample's bound (hit_rel). llvmpipe measured below 1e-6 (docs/glsl/builders.md); an NVIDIA
    // H200 1.2e-5.
    VPLKIT_CHECK_PARITY(compare_floats(gv, cv, within_rel(hit_rel), {}, "GBG " + acc_name + ": per-hit value"));

    // 2. The fixed-point sums: exactly the host's integer sum of the GPU rays' units.
    auto expected_acc = [&](const gbg_setup& q, std::size_t* saturated) {
      std::vector<std::uint64_t> e(std::size_t(n), 0);
      *saturated = 0;
      for (const auto& r : gr) {
        if (r.flags != 3u) continue;
        e[std::size_t(r.texel)] += host_units(r.value, q.scale, q.max_units);
        if (r.value * q.scale > q.max_units) ++*saturated;
      }
      std::vector<std::uint32_t> words;
      for (std::uint64_t v : e) {
        words.push_back(std::uint32_t(v & 0xFFFFFFFFu));
        words.push_back(std::uint32_t(v >> 32));
      }
      return words;
    };
    std::size_t sat = 0;
    const auto one = run_gbg(s.gbuffer, st, {{0, st.n_dirs}}, false);
    VPLKIT_CHECK_PARITY(compare_exact(one.acc, expected_acc(st, &sat), {}, "GBG " + acc_name + ": fixed-point sums (lo, hi)"));
    CHECK(one.stats[VPLKIT_GBG_STAT_SATURATED_HITS] == sat);
    CHECK(sat == 0);
    const auto split = run_gbg(s.gbuffer, st, {{0, 5}, {5, 11}, {11, st.n_dirs}}, false);
    VPLKIT_CHECK_PARITY(compare_exact(split.acc, one.acc, {}, "GBG " + acc_name + ": 3 direction ranges = 1 dispatch"));
    {
      // Carries: units of 2^33 and more per hit (the low word wraps on most adds).
      std::vector<float> counted_values;
      for (const auto& r : gr)
        if (r.flags == 3u && r.value > 0) counted_values.push_back(r.value);
      std::nth_element(counted_values.begin(), counted_values.begin() + std::ptrdiff_t(counted_values.size() / 2),
                       counted_values.end());
      const float median = counted_values[counted_values.size() / 2];
      gbg_setup big = st;
      big.scale = std::ldexp(1.0f, 34 - int(std::floor(std::log2(median))));  // the median hit: ~2^34 units
      big.max_units = std::ldexp(1.0f, 52);
      const auto r = run_gbg(s.gbuffer, big, {{0, big.n_dirs}}, false);
      std::size_t sat_big = 0;
      VPLKIT_CHECK_PARITY(compare_exact(r.acc, expected_acc(big, &sat_big), {}, "GBG " + acc_name + ": sums with carries"));
      std::size_t high = 0;
      for (std::size_t t = 0; t < r.acc.size(); t += 2) high += r.acc[t + 1] != 0 ? 1 : 0;
      std::cout << "  carry test: " << high << " texels with a non-zero high word\n";
      CHECK(high > 100);
      CHECK(r.stats[VPLKIT_GBG_STAT_SATURATED_HITS] == sat_big);
      // Saturation: max_units below most values.
      gbg_setup low = st;
      low.max_units = std::ldexp(1.0f, 20);
      low.scale = st.scale;
      std::size_t sat_low = 0;
      const auto expected = expected_acc(low, &sat_low);
      const auto rl = run_gbg(s.gbuffer, low, {{0, low.n_dirs}}, false);
      std::cout << "  saturation test: " << sat_low << " of " << counted << " hits saturate\n";
      CHECK(sat_low > 0);
      CHECK(rl.stats[VPLKIT_GBG_STAT_SATURATED_HITS] == sat_low);
      VPLKIT_CHECK_PARITY(compare_exact(rl.acc, expected, {}, "GBG " + acc_name + ": saturated sums"));
    }

    // 3. Weights and stats against build_gbg_weights.
    for (bool fill : {false, true}) {
      const vplkit::gbg_params<float> params = vplkit_test::gbg_cpu_params(st, fill);
      vplkit::gbg_stats cs;
      const auto cpu = vplkit::build_gbg_weights(gb, view, vplkit::voxel_tracer<float>{s.grid.view()}, params, &cs);
      const auto gpu = fill ? run_gbg(s.gbuffer, st, {{0, st.n_dirs}}, true) : one;
      const std::string what = "GBG " + acc_name + (fill ? ", filled" : ", raw");
      // Stats: exact unless a ray flipped.
      std::vector<std::uint32_t> gstat = {
          gpu.stats[VPLKIT_GBG_STAT_GATHER_POINTS], gpu.stats[VPLKIT_GBG_STAT_HITS], gpu.stats[VPLKIT_GBG_STAT_LIT_HITS],
          gpu.stats[VPLKIT_GBG_STAT_REACHED_TEXELS], gpu.stats[VPLKIT_GBG_STAT_HOLES]};
      std::vector<std::uint32_t> cstat = {std::uint32_t(cs.gather_points), std::uint32_t(cs.hits), std::uint32_t(cs.lit_hits),
                                          std::uint32_t(cs.reached_texels), std::uint32_t(cs.holes)};
      if (fill) {
        gstat.push_back(gpu.stats[VPLKIT_GBG_STAT_FILLED]);
        cstat.push_back(std::uint32_t(cs.filled));
      }
      if (flips == 0) {
        VPLKIT_CHECK_PARITY(compare_exact(gstat, cstat, {}, what + ": stats (|G|, hits, lit hits, reached, holes[, filled])"));
      } else {
        CHECK(gstat[0] == cstat[0]);
      }
      // Excluded texels: those a flipped ray counted in, and with the fill their 3 x 3 neighbours.
      std::set<int> excluded = flipped_texels;
      if (fill) {
        for (int t : flipped_texels) {
          const int R = s.R, face = t / (R * R), xy = t % (R * R), x = xy % R, y = xy / R;
          for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx)
              if (x + dx >= 0 && x + dx < R && y + dy >= 0 && y + dy < R) excluded.insert(face * R * R + (y + dy) * R + x + dx);
        }
      }
      // Per texel: |gpu - cpu| <= H_t 0.5 / scale / (|G| n_dirs) (quantisation) + hit_rel |cpu| (the
      // per-hit float bound above; the read-out and the division add 4 ulps, inside it). With the fill a
      // filled texel is one neighbour's value: the same bound with that neighbour's H.
      std::vector<int> hits(std::size_t(n), 0);
      for (const auto& r : cr)
        if (r.flags == 3u) ++hits[std::size_t(r.texel)];
      int max_hits = *std::max_element(hits.begin(), hits.end());
      std::vector<float> g, c;
      std::vector<int> idx;
      std::size_t zero_mismatch = 0;
      double worst = 0;
      int worst_t = -1;
      for (int t = 0; t < n; ++t) {
        if (excluded.count(t)) continue;
        const double a = double(gpu.weights[std::size_t(t)]), b = double(cpu[std::size_t(t)]);
        if ((a == 0) != (b == 0)) ++zero_mismatch;
        const double h = fill ? max_hits : hits[std::size_t(t)];
        const double bound = h * 0.5 / double(st.scale) / (double(G) * st.n_dirs) + hit_rel * std::abs(b);
        const double r = std::abs(a - b) / std::max(bound, 1e-300);
        if (r > worst) {
          worst = r;
          worst_t = t;
        }
        g.push_back(float(a));
        c.push_back(float(b));
        idx.push_back(t);
      }
      std::cout << "  " << what << ": " << excluded.size() << " texels excluded (flipped rays), worst |diff| / bound "
                << worst;
      if (worst_t >= 0)
        std::cout << " at texel " << worst_t << " gpu " << show(gpu.weights[std::size_t(worst_t)]) << " cpu "
                  << show(cpu[std::size_t(worst_t)]) << " (" << hits[std::size_t(worst_t)] << " hits)";
      std::cout << "\n";
      VPLKIT_CHECK_PARITY(compare_floats(g, c, within_rel(hit_rel) | within_abs(max_hits * 0.5 / double(st.scale) / (double(G) * st.n_dirs)),
                                         [&](std::size_t k) { return "texel " + std::to_string(idx[k]); }, what + ": weights"));
      CHECK(worst <= 1.0);
      CHECK(zero_mismatch == 0);
      CHECK(excluded.size() <= std::size_t(n) / 50);
    }
  }
}

TEST_CASE("GBG kernels: all-background G-buffer gives zero weights and stats, no NaN") {
  const auto& s = fx().s;
  const vplkit_test::all_background_gbg bg(s.gbuffer, s.view(), s.grid);
  const auto r = run_gbg(bg.gbuffer, bg.setup, {{0, bg.setup.n_dirs}}, true);
  const int n = vplkit::texel_count(s.R);
  std::vector<std::uint32_t> bits, zeros(std::size_t(n), 0u);
  for (float w : r.weights) bits.push_back(bits_of(w));
  VPLKIT_CHECK_PARITY(compare_exact(bits, zeros, {}, "GBG all background: weights are +0 (bits)"));
  for (int k : vplkit_test::all_background_gbg::zero_stats) CHECK(r.stats[std::size_t(k)] == 0u);
  // Every texel carrying a VPL is a hole that stays one.
  CHECK(r.stats[VPLKIT_GBG_STAT_HOLES] == bg.cpu_holes);
}


// ---- tiled distributions: tile_blocks.comp, tile_weights.comp -------------------------------------
TEST_CASE("tile_blocks.comp and tile_weights.comp: make_tile_blocks and tile_block_weight") {
  // Blocks of 5 texels at R = 32 (the last row and column of blocks cut to 2). Per block the sums
  // run over at most 25 texels in the C++ order; l (flux weights: 16 ulps), l * p + P (an FMA or
  // two roundings) and l / L (2.5 ulp) put every share, proxy and L within 1e-5 relative (the
  // normal: 1e-5 absolute, a unit vector). The weights kernel is fed the C++ proxies, so its
  // bound is the global weights' (2e-6: the same sum of contributions).
  const auto& s = fx().s;
  const auto view = s.view();
  const int n = view.texel_count();
  const vplkit::tile_blocks<float> tb = vplkit::make_tile_blocks(view, 5);
  const int Nb = tb.count();
  REQUIRE(Nb == 2 * 7 * 7);
  // The kernels first: pack_kernel makes the GL context the buffers below need.
  const auto& blocks_prog = pack_kernel("vplkit/builders/tile_blocks.comp");
  const auto& weights_prog = pack_kernel("vplkit/builders/tile_weights.comp");
  vplkit::gpu::tile_blocks_params bp{};
  bp.light = vplkit::gpu::make_light_params(view.light);
  bp.resolution = s.R;
  bp.block = 5;
  const auto dp = vplkit::gl::buffer::from_vector(dprsm_surfels(s.dprsm));
  const auto shares_b = vplkit::gl::buffer::filled(std::size_t(n) * 4, 0xFF);  // NaN: a texel not written fails
  const auto proxies_b = vplkit::gl::buffer::filled(std::size_t(Nb) * 48, 0xFF);
  const auto bub = vplkit_test::uniform_buffer(bp);
  vplkit_test::bind({vplkit_test::storage_at(VPLKIT_TILE_BLOCKS_BINDING_DPRSM, dp),
                     vplkit_test::storage_at(VPLKIT_TILE_BLOCKS_BINDING_SHARES, shares_b),
                     vplkit_test::storage_at(VPLKIT_TILE_BLOCKS_BINDING_PROXIES, proxies_b),
                     vplkit_test::uniform_at(VPLKIT_TILE_BLOCKS_BINDING_PARAMS, bub)});
  vplkit::gl::dispatch_linear(blocks_prog,
                              vplkit::gl::groups_for(std::size_t(Nb), VPLKIT_TILE_BLOCKS_LOCAL_SIZE));
  const std::vector<float> shares = shares_b.read<float>();
  const std::vector<float4> proxies = proxies_b.read<float4>();
  std::vector<std::int32_t> gz, cz;
  for (int t = 0; t < n; ++t) {
    gz.push_back(shares[std::size_t(t)] == 0.0f);
    cz.push_back(tb.share[std::size_t(t)] == 0.0f);
  }
  CHECK(std::count(cz.begin(), cz.end(), 0) > n / 4);
  const auto texel = [](std::size_t t) { return "texel " + std::to_string(t); };
  VPLKIT_CHECK_PARITY(compare_exact(gz, cz, texel, "tile shares: zero / non-zero"));
  VPLKIT_CHECK_PARITY(compare_floats(shares, tb.share, within_rel(1e-5) | within_abs(0.0), texel, "tile shares"));
  std::vector<float> gpos, cpos, gnrm, cnrm, gflux, cflux, gl_, cl;
  for (int b = 0; b < Nb; ++b) {
    const vplkit::tile_block_proxy<float> p = vplkit::tile_block_proxy_of(view, tb.grid, b);
    for (int k = 0; k < 3; ++k) {
      gpos.push_back(proxies[std::size_t(3 * b)][k]);
      cpos.push_back(p.proxy.position[k]);
      gnrm.push_back(proxies[std::size_t(3 * b + 1)][k]);
      cnrm.push_back(p.proxy.normal[k]);
      gflux.push_back(proxies[std::size_t(3 * b + 2)][k]);
      cflux.push_back(p.proxy.flux[k]);
    }
    gl_.push_back(proxies[std::size_t(3 * b)].w);
    cl.push_back(p.flux_luminance);
  }
  const auto block3 = [](std::size_t k) { return "block " + std::to_string(k / 3) + " component " + std::to_string(k % 3); };
  const auto block = [](std::size_t b) { return "block " + std::to_string(b); };
  // Positions: relative to the room's size (coordinates near 0 have no relative bound).
  VPLKIT_CHECK_PARITY(compare_floats(gpos, cpos, within_rel(1e-5) | within_abs(1e-5 * 4.0), block3, "tile proxy positions"));
  VPLKIT_CHECK_PARITY(compare_floats(gnrm, cnrm, within_abs(1e-5), block3, "tile proxy normals"));
  VPLKIT_CHECK_PARITY(compare_floats(gflux, cflux, within_rel(1e-5) | within_abs(0.0), block3, "tile proxy flux"));
  VPLKIT_CHECK_PARITY(compare_floats(gl_, cl, within_rel(1e-5) | within_abs(0.0), block, "tile block flux luminance"));

  // Weights: 2 x 2 tiles of 8 points each (the C++ subsets; dropped strata -1 on the GPU side).
  const auto gb = s.gbuffer.view();
  const auto regions = vplkit::make_image_regions(gb, 2, 2);
  const int count = 8;
  const auto subsets = vplkit::local_gather_subsets(gb, regions, count, 13u);
  std::vector<std::int32_t> pixels(std::size_t(4 * count), -1);
  std::vector<std::uint32_t> offsets;
  for (int i = 0; i <= 4; ++i) offsets.push_back(std::uint32_t(i * count));
  for (int i = 0; i < 4; ++i)
    for (std::size_t k = 0; k < subsets[std::size_t(i)].size(); ++k)
      pixels[std::size_t(i * count) + k] = subsets[std::size_t(i)][k];
  std::vector<float4> cproxies;
  for (int b = 0; b < Nb; ++b) {
    const vplkit::vpl<float>& v = tb.proxy[std::size_t(b)];
    cproxies.push_back(vplkit_test::f4(v.position));
    cproxies.push_back(vplkit_test::f4(v.normal));
    cproxies.push_back(vplkit_test::f4(v.flux));
  }
  for (float dmin : {0.05f, 0.0f}) {
    vplkit::gpu::tile_weights_params wp{};
    wp.blocks = Nb;
    wp.tiles = 4;
    wp.pixel_count = gb.width * gb.height;
    wp.dmin = dmin;
    const auto gbuf = vplkit::gl::buffer::from_vector(gbuffer_surfels(s.gbuffer));
    const auto pix = vplkit::gl::buffer::from_vector(pixels);
    const auto off = vplkit::gl::buffer::from_vector(offsets);
    const auto prox = vplkit::gl::buffer::from_vector(cproxies);
    const auto wb = vplkit::gl::buffer::filled(std::size_t(4 * Nb) * 4, 0xFF);
    const auto wub = vplkit_test::uniform_buffer(wp);
    vplkit_test::bind({vplkit_test::storage_at(VPLKIT_TILE_WEIGHTS_BINDING_GBUFFER, gbuf),
                       vplkit_test::storage_at(VPLKIT_TILE_WEIGHTS_BINDING_SUBSET, pix),
                       vplkit_test::storage_at(VPLKIT_TILE_WEIGHTS_BINDING_OFFSETS, off),
                       vplkit_test::storage_at(VPLKIT_TILE_WEIGHTS_BINDING_PROXIES, prox),
                       vplkit_test::storage_at(VPLKIT_TILE_WEIGHTS_BINDING_WEIGHTS, wb),
                       vplkit_test::uniform_at(VPLKIT_TILE_WEIGHTS_BINDING_PARAMS, wub)});
    vplkit::gl::dispatch_linear(weights_prog,
                                vplkit::gl::groups_for(std::size_t(Nb), VPLKIT_TILE_WEIGHTS_LOCAL_SIZE), 4);
    const std::vector<float> gpu = wb.read<float>();
    std::vector<float> cpu;
    int positive = 0;
    for (int i = 0; i < 4; ++i) {
      std::vector<vplkit::gather_point<float>> pts;
      for (int p : subsets[std::size_t(i)]) pts.push_back(gb.at(p));
      for (int b = 0; b < Nb; ++b) {
        cpu.push_back(vplkit::tile_block_weight(pts.data(), pts.size(), tb.proxy[std::size_t(b)], dmin));
        positive += cpu.back() > 0.0f ? 1 : 0;
      }
    }
    CHECK(positive > Nb);
    VPLKIT_CHECK_PARITY(compare_floats(gpu, cpu, within_rel(2e-6) | within_abs(0.0),
                                       [Nb](std::size_t k) {
                                         return "tile " + std::to_string(k / std::size_t(Nb)) + " block " +
                                                std::to_string(k % std::size_t(Nb));
                                       },
                                       "tile block weights, dmin " + show(dmin)));
  }
}
