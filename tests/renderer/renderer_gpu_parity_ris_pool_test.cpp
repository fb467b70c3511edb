// SPDX-License-Identifier: MIT
// --method ris-mis --candidate-pool on the GPU backend (estimate_ris_mis.comp with VR_RIS_POOL: a
// pool pass, then the estimate's passes drawing their candidates from it) against the CPU backend
// (render/cpu/ris_render.hpp: fill_ris_candidate_pool, vplkit::estimate_ris_mis_pooled), with
// patch and point VPLs, one pool and a pool per region (local), with spatial reuse, split over
// dispatches; the pool records' layout in the kernel against ris_pool_params.h; the details.
//
// The bound is renderer_gpu_parity_ris_mis_test's: the GPU builds its own distributions (float
// neighbours of the CPU's values) and traces through its own sin/cos, so an entry's draw, a
// selection or a ray at a tie may differ in a few pixels: >= 97 % of the pixels within 2e-4
// relative, every pixel finite and non-negative.
#include "renderer_gl_fixture.hpp"
#include "renderer_image_parity.hpp"

#include "cli/render_options.hpp"
#include "render/cpu/cpu_backend.hpp"
#include "render/gpu/estimate_kernels.hpp"
#include "render/gpu/gpu_backend.hpp"
#include "render/pipeline.hpp"

#include "estimate_params.h"
#include "estimate_ris_params.h"

#include <vplkit/builders/local_weights.hpp>
#include <vplkit/estimators/ris_pool_params.h>

#include <headless_gl/compute.hpp>

#include <catch2/catch.hpp>

#include "gl_program_resources.hpp"

#include <glm/geometric.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstddef>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

using namespace vplrender;

namespace {

using fixture = vplrender_test::gl_fixture;

constexpr double rel_bound = 2e-4;
constexpr double required_fraction = 0.97;

const fixture& shared_fixture() {
  static const fixture f = vplrender_test::make_gl_fixture(vplrender_test::small_options("cornell", 24, 16, 16, 32));
  return f;
}

render_settings settings_of(const fixture& f, options o) {
  render_settings es = make_render_settings(o, f.p.s);
  es.threads = 2;
  return es;
}

double mean_of(const image_rgb& a) {
  double s = 0.0;
  for (float v : a.rgb) s += v;
  return s / double(std::max<std::size_t>(1, a.rgb.size()));
}

options pool_options(const fixture& f, ris_source_choice source, int pool, int spatial, int candidates, int vpls,
                     int dirs, vpl_mode_choice mode) {
  options o = f.o;
  o.meth = method::ris_mis;
  o.candidate_source = source;
  o.candidate_pool = pool;
  o.spatial = spatial;
  o.candidates = candidates;
  o.vpls = vpls;
  o.dirs = dirs;
  o.vpl_mode = mode;
  o.regions = 2;
  return o;
}

using member = vplkit_test::block_member;
using vplkit_test::resource_value;
#define VR_MEMBER VPLKIT_TEST_BLOCK_MEMBER

}  // namespace

TEST_CASE("ris-mis --candidate-pool: the GPU image equals the CPU backend's, with and without reuse") {
  const fixture& f = shared_fixture();
  struct run {
    ris_source_choice source;
    int pool, spatial, candidates, vpls, dirs;
    vpl_mode_choice mode;
  };
  const run runs[] = {{ris_source_choice::flux, 512, 0, 8, 3, 4, vpl_mode_choice::patch},
                      {ris_source_choice::local, 300, 0, 8, 3, 4, vpl_mode_choice::patch},  // a pool per region
                      {ris_source_choice::flux, 256, 0, 4, 4, 2, vpl_mode_choice::point},
                      {ris_source_choice::flux, 512, 3, 8, 3, 4, vpl_mode_choice::patch},   // rounds with reuse
                      {ris_source_choice::local, 300, 2, 4, 2, 2, vpl_mode_choice::patch}};
  bool first = true;
  for (const run& r : runs) {
    const render_settings es =
        settings_of(f, pool_options(f, r.source, r.pool, r.spatial, r.candidates, r.vpls, r.dirs, r.mode));
    stage_timer tc, tg;
    const render_result c = render_cpu(f.b, es, tc), g = render_gpu(f.b, es, tg);
    // Every value finite and non-negative (compare requires it), >= 97 % of the pixels agreeing.
    const double within = vplrender_test::compare(c.image, g.image, rel_bound).within;
    std::printf("ris-mis --candidate-pool %d %-6s --spatial %d --candidates %d --vpls %d --dirs %d --vpl-mode %s: "
                "%.1f %% of pixels within %g, means cpu %.6f gpu %.6f\n",
                r.pool, to_string(r.source), r.spatial, r.candidates, r.vpls, r.dirs, to_string(r.mode),
                100.0 * within, rel_bound, mean_of(c.image), mean_of(g.image));
    INFO(to_string(r.source) << " --candidate-pool " << r.pool << " --spatial " << r.spatial);
    CHECK(mean_of(g.image) > 0.0);
    CHECK(within >= required_fraction);
    CHECK(g.details["ris"]["pool"] == r.pool);
    CHECK(c.details["ris"]["pool"] == r.pool);
    // The pool changes the draws (the comparison above is between two pooled renders).
    if (first) {
      render_settings direct = es;
      direct.ris_pool = 0;
      stage_timer t0;
      const render_result d = render_gpu(f.b, direct, t0);
      CHECK(d.image.rgb != g.image.rgb);
      CHECK_FALSE(d.details["ris"].contains("pool"));
      first = false;
    }
  }
}

TEST_CASE("ris-mis --candidate-pool on the GPU: the steps split over dispatches give the image of one dispatch") {
  // The pool is filled once, before the first of the split dispatches, and read by all of them.
  const fixture& f = shared_fixture();
  render_settings es =
      settings_of(f, pool_options(f, ris_source_choice::flux, 700, 0, 4, 5, 3, vpl_mode_choice::patch));
  es.loop_budget = loop_budget_choice::never;
  stage_timer t1, t2;
  const render_result one = render_gpu(f.b, es, t1);
  es.loop_budget = loop_budget_choice::always;
  es.max_units_per_pass = 2;
  const render_result split = render_gpu(f.b, es, t2);
  CHECK(one.details["gpu"]["passes"] == 1);
  CHECK(split.details["gpu"]["passes"] == 3);
  CHECK(mean_of(one.image) > 0.0);
  CHECK(one.image.rgb == split.image.rgb);
}

TEST_CASE("ris-mis --candidate-pool: the loop bound of a step charges no CDF search per candidate") {
  // A pooled candidate is an index, a load and its contribution (no loop): the step's bound must not
  // grow with the DPRSM (the CDF's length), and M candidates must cost less than M searches, so that
  // llvmpipe's loop budget does not split the dispatch more than the step needs. The direct draws
  // keep their search; --method ris has no pool and is unchanged by the setting.
  render_settings s;
  s.meth = method::ris_mis;
  s.ris_candidates = 16;
  s.vpls = s.dirs = 64;
  const auto cost = [&](method m, int pool, int dprsm) {
    render_settings t = s;
    t.meth = m;
    t.ris_pool = pool;
    shape_inputs in;
    in.dprsm_resolution = dprsm;
    in.query_cost = 300;
    return gpu_kernel_for(m).stages.front().shape(t, in).cost;
  };
  CHECK(cost(method::ris_mis, 16384, 128) == cost(method::ris_mis, 16384, 512));
  CHECK(cost(method::ris_mis, 0, 128) < cost(method::ris_mis, 0, 512));
  // The 16 searches over 2 x 512^2 texels are at least 16 x 2 x 19 iterations.
  CHECK(cost(method::ris_mis, 0, 512) - cost(method::ris_mis, 16384, 512) >= 16 * 2 * 19);
  CHECK(cost(method::ris, 16384, 512) == cost(method::ris, 0, 512));
  // The pooled step still bounds its two queries (a gathering ray and the kept sample's).
  CHECK(cost(method::ris_mis, 16384, 512) > 2 * 300);
}

TEST_CASE("estimate_ris_mis.comp: the pool records have ris_pool_params.h's layout in every pass") {
  using Q = vplkit::gpu::ris_pool_record;
  const std::vector<member> members = {
      VR_MEMBER(Q, position_x), VR_MEMBER(Q, position_y), VR_MEMBER(Q, position_z), VR_MEMBER(Q, pmf),
      VR_MEMBER(Q, normal_x),   VR_MEMBER(Q, normal_y),   VR_MEMBER(Q, normal_z),   VR_MEMBER(Q, area),
      VR_MEMBER(Q, radiance_x), VR_MEMBER(Q, radiance_y), VR_MEMBER(Q, radiance_z), VR_MEMBER(Q, texel),
      VR_MEMBER(Q, xi_x),       VR_MEMBER(Q, xi_y),       VR_MEMBER(Q, at_centre)};
  const gpu_kernel_stage& stage = gpu_kernel_for(method::ris_mis).stages.front();
  for (int pass : {ris_pass_pool, ris_pass_estimate, ris_pass_candidates}) {
    INFO("VR_RIS_PASS " << pass);
    pipeline_gl_context();
    std::string d = "#define VR_VISIBILITY 2\n#define VR_SPLIT 1\n#define VR_VPL_MODE 1\n#define VR_VARIANT 1\n"
                    "#define VR_RIS_POOL\n";
    if (pass != ris_pass_estimate) d += "#define VR_RIS_PASS " + std::to_string(pass) + "\n";
    const GLuint prog = gpu_kernel_program(stage, d).id();
    CHECK(resource_value(prog, GL_SHADER_STORAGE_BLOCK, "VrRisPool", GL_BUFFER_BINDING) == VR_RIS_BINDING_POOL);
    for (const member& m : members) {
      const std::string name = "vr_pool[0]." + m.name;
      INFO(name);
      CHECK(std::size_t(resource_value(prog, GL_BUFFER_VARIABLE, name, GL_OFFSET)) == m.offset);
      CHECK(std::size_t(resource_value(prog, GL_BUFFER_VARIABLE, name, GL_TOP_LEVEL_ARRAY_STRIDE)) == sizeof(Q));
    }
  }
}

TEST_CASE("ris-mis with tile candidates: the GPU image equals the CPU backend's, with and without pool and reuse") {
  // The GPU builds the tiles itself (render/gpu/gpu_tiles.hpp: the pack's tile_blocks.comp, the
  // tiles' subsets, tile_weights.comp, the block CDFs) and draws through estimate_tiles.glsl; the CPU backend
  // through render/cpu/tiled_candidates.hpp. 2 x 2 tiles, blocks of 4 x 4 texels of a 2 x 16^2 DPRSM.
  const fixture& f = shared_fixture();
  struct run {
    int pool, spatial, candidates, vpls, dirs;
    double eps;
    vpl_mode_choice mode;
  };
  const run runs[] = {{0, 0, 8, 3, 4, 0.1, vpl_mode_choice::patch},    // each candidate its own tile draw
                      {300, 0, 8, 3, 4, 0.1, vpl_mode_choice::patch},  // a pool per tile
                      {300, 2, 4, 2, 2, 0.1, vpl_mode_choice::patch},  // rounds with reuse
                      {300, 0, 4, 4, 2, 0.0, vpl_mode_choice::point}};  // no fallback: the blocks alone
  for (const run& r : runs) {
    options o = pool_options(f, ris_source_choice::tiles, r.pool, r.spatial, r.candidates, r.vpls, r.dirs, r.mode);
    o.tiles = 4;
    o.tile_points = 4;
    o.tile_block = 4;
    o.eps = r.eps;
    const render_settings es = settings_of(f, o);
    stage_timer tc, tg;
    const render_result c = render_cpu(f.b, es, tc), g = render_gpu(f.b, es, tg);
    const double within = vplrender_test::compare(c.image, g.image, rel_bound).within;
    std::printf("ris-mis tiles --candidate-pool %d --spatial %d --candidates %d --vpls %d --dirs %d --eps %g "
                "--vpl-mode %s: %.1f %% of pixels within %g, means cpu %.6f gpu %.6f\n",
                r.pool, r.spatial, r.candidates, r.vpls, r.dirs, r.eps, to_string(r.mode), 100.0 * within,
                rel_bound, mean_of(c.image), mean_of(g.image));
    INFO("tiles --candidate-pool " << r.pool << " --spatial " << r.spatial << " --eps " << r.eps);
    CHECK(mean_of(g.image) > 0.0);
    CHECK(within >= required_fraction);
    // The same tiles, gather points and blocks on both sides.
    CHECK(g.details["tiles"]["grid"] == c.details["tiles"]["grid"]);
    CHECK(g.details["tiles"]["points"] == c.details["tiles"]["points"]);
    CHECK(g.details["tiles"]["blocks"] == 2 * 4 * 4);
    CHECK(c.details["tiles"]["blocks"] == 2 * 4 * 4);
    CHECK(g.details["ris"]["candidate_source"] == "tiles");
  }
  // Tiles draw otherwise than flux: the tile distributions are built and used, not flux's.
  options o = pool_options(f, ris_source_choice::flux, 300, 0, 8, 3, 4, vpl_mode_choice::patch);
  options ot = o;
  ot.candidate_source = ris_source_choice::tiles;
  ot.tiles = 4;
  ot.tile_points = 4;
  ot.tile_block = 4;
  stage_timer t0, t1;
  CHECK(render_gpu(f.b, settings_of(f, o), t0).image.rgb != render_gpu(f.b, settings_of(f, ot), t1).image.rgb);
}

TEST_CASE("ris-mis with tile candidates on the GPU: a tile whose blocks all weigh 0 draws from the fallback alone") {
  // Hard case: the gather points of tile 0 (of 2 x 2) moved far outside the scene, facing away
  // from it, so every block's proxy lies behind them: the tile's block weights are all 0, its
  // learned part empty, its mixture the fallback alone (effective eps 1). Both backends must draw
  // it so, finite, and agree; the other tiles keep their blocks.
  static const fixture f = [] {
    fixture x = vplrender_test::make_gl_fixture(vplrender_test::small_options("cornell", 24, 16, 16, 32));
    glm::vec3 centre(0.0f);
    int lit = 0;
    for (std::size_t t = 0; t < x.b.dprsm.position.size(); ++t)
      if (x.b.dprsm.albedo[t] != glm::vec3(0.0f)) {
        centre += x.b.dprsm.position[t];
        ++lit;
      }
    centre /= float(std::max(lit, 1));
    float radius = 0.0f;
    for (std::size_t t = 0; t < x.b.dprsm.position.size(); ++t)
      if (x.b.dprsm.albedo[t] != glm::vec3(0.0f)) radius = std::max(radius, glm::length(x.b.dprsm.position[t] - centre));
    const glm::vec3 away = glm::normalize(glm::vec3(1.0f, 2.0f, 3.0f));
    vplrender::gbuffer_data& g = x.b.gbuf;
    const vplkit::pixel_rect r = vplkit::image_regions(g.width, g.height, 2, 2).region_rect(0);
    for (int y = r.y0; y < r.y0 + r.height; ++y)
      for (int px = r.x0; px < r.x0 + r.width; ++px) {
        const std::size_t p = std::size_t(y) * std::size_t(g.width) + std::size_t(px);
        g.position[p] = centre + 100.0f * std::max(radius, 1.0f) * away;
        g.normal[p] = away;
        if (g.shading_normal.size() == g.position.size()) g.shading_normal[p] = away;
      }
    x.b.gpu = std::make_shared<vplrender::gpu_scene_buffers>(
        vplrender::upload_scene_buffers(x.b.gbuf, x.b.dprsm, x.b.grid.view()));
    return x;
  }();
  options o = pool_options(f, ris_source_choice::tiles, 300, 0, 4, 3, 2, vpl_mode_choice::patch);
  o.tiles = 4;
  o.tile_points = 4;
  o.tile_block = 4;
  o.direct = true;  // the moved points still shade their direct light: a non-zero image there
  for (const int pool : {300, 0}) {
    o.candidate_pool = pool;
    const render_settings es = settings_of(f, o);
    stage_timer tc, tg;
    const render_result c = render_cpu(f.b, es, tc), g = render_gpu(f.b, es, tg);
    const std::vector<int> points = g.details["tiles"]["points"].get<std::vector<int>>();
    CHECK(points == c.details["tiles"]["points"].get<std::vector<int>>());
    CHECK(points[0] > 0);  // the points are valid: their blocks, not their count, weigh 0
    CHECK(g.details["tiles"]["empty"] == 1);  // tile 0's learned part, and only it
    CHECK(c.details["tiles"]["empty"] == 1);
    const double within = vplrender_test::compare(c.image, g.image, rel_bound).within;
    std::printf("ris-mis tiles, tile 0 facing away, --candidate-pool %d: %.1f %% of pixels within %g, means cpu %.6f "
                "gpu %.6f\n",
                pool, 100.0 * within, rel_bound, mean_of(c.image), mean_of(g.image));
    CHECK(within >= required_fraction);
    CHECK(mean_of(g.image) > 0.0);
  }
}
