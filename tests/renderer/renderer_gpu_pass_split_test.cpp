// SPDX-License-Identifier: MIT
// The GPU backend's split of an estimate over dispatches (render/gpu/loop_budget.hpp): where the
// driver leaves loops after 65535 iterations (llvmpipe) the units are split into ranges with the
// pixel's state kept in a buffer between dispatches (the VR_SPLIT 1 variants); elsewhere one
// dispatch does all (VR_SPLIT 0, no state buffer). Both must give the same image: the ranges
// perform exactly the float operations and draws of the one loop. Checked for every estimate
// kernel on small frames, the split forced on any driver (loop_budget_choice::always with a few
// units per dispatch) against one dispatch (never; the work here is far below llvmpipe's budget).
#include "cli/render_options.hpp"
#include "cli/scene_setup.hpp"
#include "render/gpu/gpu_backend.hpp"
#include "render/gpu/loop_budget.hpp"
#include "render/pipeline.hpp"
#include "renderer_gl_fixture.hpp"

#include <headless_gl/compute.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>

using namespace vplrender;

namespace {

// A small cornell frame (DPRSM 2 x 8^2: the exhaustive sum in one dispatch stays far below
// llvmpipe's budget too) with the voxel grid and the exact rays (BVH and shading) on the GPU.
using frame = vplrender_test::gl_fixture;

const frame& small_frame() {
  static const frame* f = new frame(vplrender_test::make_pipeline_fixture([] {
    options o = vplrender_test::small_options("cornell", 24, 16, 8);
    o.visibility = visibility_choice::exact;
    return o;
  }()));
  return *f;
}

struct rendered {
  image_rgb image;
  nlohmann::json gpu;
};

rendered render(render_settings es, loop_budget_choice budget, int max_units) {
  es.loop_budget = budget;
  es.max_units_per_pass = max_units;
  stage_timer t;
  render_result r = render_gpu(small_frame().b, es, t);
  return {std::move(r.image), r.details["gpu"]};
}

double worst_relative(const image_rgb& a, const image_rgb& b) {
  double w = 0.0;
  for (std::size_t i = 0; i < a.rgb.size(); ++i) {
    const double m = std::max(std::abs(double(a.rgb[i])), std::abs(double(b.rgb[i])));
    if (m > 0.0) w = std::max(w, std::abs(double(a.rgb[i]) - double(b.rgb[i])) / m);
  }
  return w;
}

bool same_bits(const image_rgb& a, const image_rgb& b) {
  return a.rgb.size() == b.rgb.size() && std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)) == 0;
}

}  // namespace

TEST_CASE("split dispatches give the one dispatch's image, every estimate kernel") {
  const frame& f = small_frame();
  struct split_case {
    method m;
    visibility_choice vis;
    vpl_mode_choice vmode;
    bool direct;
    int max_units;  // per dispatch when split
  };
  // 8 VPLs / 8 directions / 2 local rounds (8 VPLs over 2 x 2 regions) / 128 reference texels.
  const split_case cases[] = {
      {method::reference, visibility_choice::exact, vpl_mode_choice::patch, true, 50},
      {method::global, visibility_choice::exact, vpl_mode_choice::patch, false, 3},
      {method::gbg, visibility_choice::paper_voxels, vpl_mode_choice::point, true, 3},
      {method::local, visibility_choice::voxels, vpl_mode_choice::patch, false, 1},
      {method::gather, visibility_choice::exact, vpl_mode_choice::patch, false, 3},
      {method::mis, visibility_choice::voxels, vpl_mode_choice::patch, true, 3},
      {method::exact, visibility_choice::exact, vpl_mode_choice::patch, true, 3},
  };

  for (const split_case& c : cases) {
    options o = f.o;
    o.meth = c.m;
    o.visibility = c.vis;
    o.vpl_mode = c.vmode;
    o.direct = c.direct;
    const render_settings es = make_render_settings(o, f.p.s);
    const rendered one = render(es, loop_budget_choice::never, 0);
    const rendered split = render(es, loop_budget_choice::always, c.max_units);
    INFO(to_string(c.m) << ", " << to_string(c.vis) << ", --vpl-mode " << to_string(c.vmode)
                        << (c.direct ? ", --direct" : "") << ": " << split.gpu.dump());
    CHECK(one.gpu["passes"] == 1);
    CHECK(one.gpu["loop_budget"] == "none");
    CHECK(split.gpu["passes"].get<int>() >= 2);
    CHECK(split.gpu["loop_budget"] == gpu_loop_budget);
    INFO("worst relative difference " << worst_relative(one.image, split.image));
    CHECK(same_bits(one.image, split.image));
    double sum = 0.0;
    for (float v : one.image.rgb) sum += v;
    CHECK(sum > 0.0);  // a black image would agree with anything
  }
}

// The clamp's compensation inline (--clamp-compensation-pass inline): its directions follow the
// estimator's units and its sum and stream counter ride in vr_pixel_state's free lanes between
// dispatches. (The compacted passes' split: renderer_gpu_clamp_compensation_pass_test.) dmin at 5 % of
// the diagonal, so that most gather points near the box's junctions have a term to carry.
TEST_CASE("split dispatches give the one dispatch's image with the clamp compensation") {
  const frame& f = small_frame();
  for (method m : {method::reference, method::global, method::local}) {
    options o = f.o;
    o.meth = m;
    render_settings es = make_render_settings(o, f.p.s);
    es.dmin *= 5.0f;
    es.clamp_compensation_pass = clamp_compensation_pass_choice::inline_pass;
    // One direction per 4 VPL samples: several directions for the ranges to cut.
    es.clamp_compensation_dirs_rule = {clamp_compensation_dirs_choice::rule::per_vpls, 4};
    REQUIRE(uses_clamp_compensation(es));
    render_settings off = es;
    off.clamp_compensation = clamp_compensation_choice::off;
    const rendered one = render(es, loop_budget_choice::never, 0);
    // Ranges that cut the compensation's directions too (reference: 128 texels, then 256 directions).
    const rendered split = render(es, loop_budget_choice::always, m == method::reference ? 50 : 1);
    const rendered clamped = render(off, loop_budget_choice::never, 0);
    INFO(to_string(m) << ": " << split.gpu.dump());
    CHECK(split.gpu["passes"].get<int>() >= 4);
    CHECK(same_bits(one.image, split.image));
    double with = 0.0, without = 0.0;
    for (float v : one.image.rgb) with += v;
    for (float v : clamped.image.rgb) without += v;
    CHECK(with > 1.001 * without);  // the compensation is really there to be split
  }
}

TEST_CASE("the loop budget applies by itself only where GL_RENDERER names a software renderer") {
  const frame& f = small_frame();
  options o = f.o;
  o.meth = method::reference;  // 512 texels at 32^3 triangle voxels: over the budget in one dispatch
  o.visibility = visibility_choice::voxels;
  const rendered r = render(make_render_settings(o, f.p.s), loop_budget_choice::automatic, 0);
  if (vplkit::gl::is_software_renderer()) {
    CHECK(r.gpu["loop_budget"] == gpu_loop_budget);
    CHECK(r.gpu["passes"].get<int>() >= 2);
  } else {
    CHECK(r.gpu["loop_budget"] == "none");
    CHECK(r.gpu["passes"] == 1);
  }
}
