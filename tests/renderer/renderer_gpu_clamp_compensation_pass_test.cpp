// SPDX-License-Identifier: MIT
// The GPU backend's compacted clamp compensation (--clamp-compensation-pass compacted, the default;
// examples/vplrender/shaders/clamp_compensation.comp, docs/renderer.md, "The clamp compensation's
// passes"): a mark pass lists the pixels whose near-surface test says another surface may lie
// within dmin, an indirect dispatch traces their directions, and the estimate kernel adds the
// terms. Checked on a small cornell frame:
// - the list holds exactly the valid pixels for which the CPU backend's test
//   (vplkit::clamp_compensation_may_add with its tracer) says maybe, each once, for every kind of
//   visibility;
// - the image is the inline form's (the directions in the estimate kernel) bit for bit, for every
//   method that takes the compensation, and the term is really there (the image is brighter than
//   the clamped one);
// - the directions split over dispatches into other ranges (llvmpipe's loop budget, forced to a few
//   directions per dispatch) give the same image.
#include "cli/render_options.hpp"
#include "cli/scene_setup.hpp"
#include "raster/gpu_scene_buffers.hpp"
#include "render/cpu/cpu_visibility.hpp"
#include "render/gpu/gpu_backend.hpp"
#include "render/pipeline.hpp"
#include "renderer_gl_fixture.hpp"

#include <vplkit/core/gather_point.hpp>
#include <vplkit/estimators/clamp_compensation.hpp>

#include <headless_gl/compute.hpp>

#include <catch2/catch.hpp>

#include <glm/vec4.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

using namespace vplrender;

namespace {

using frame = vplrender_test::gl_fixture;

// A small cornell frame with the voxel grid and the exact rays, its G-buffer also read back to the
// host (the CPU test of the list reads it). dmin is the default 1 % of the diagonal unless a case
// scales it.
frame& small_frame() {
  static frame* f = [] {
    auto* fr = new frame(vplrender_test::make_pipeline_fixture([] {
      options o = vplrender_test::small_options("cornell", 32, 24, 16);
      o.visibility = visibility_choice::exact;
      return o;
    }()));
    read_back_host_copies(fr->b);
    return fr;
  }();
  return *f;
}

struct rendered {
  image_rgb image;
  nlohmann::json details;
};

// `budget` automatic: split where the driver needs it (llvmpipe's loop limit would cut the reference's
// texels and 256 directions short in one dispatch).
rendered render(render_settings es, clamp_compensation_pass_choice where,
                loop_budget_choice budget = loop_budget_choice::automatic,
                int max_units = 0) {
  es.clamp_compensation_pass = where;
  es.loop_budget = budget;
  es.max_units_per_pass = max_units;
  stage_timer t;
  render_result r = render_gpu(small_frame().b, es, t);
  return {std::move(r.image), std::move(r.details)};
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

double sum_of(const image_rgb& a) {
  double s = 0.0;
  for (float v : a.rgb) s += v;
  return s;
}

// The pixels the last compacted render listed, sorted.
std::vector<std::uint32_t> listed_pixels() {
  const vplkit::gl::buffer& list = small_frame().b.gpu->pixels.clamp_list;
  glm::uvec4 header(0u);
  list.read_bytes(&header, 0, sizeof header);
  std::vector<std::uint32_t> pixels(header.w);
  if (header.w > 0) list.read_bytes(pixels.data(), sizeof header, pixels.size() * sizeof(std::uint32_t));
  std::sort(pixels.begin(), pixels.end());
  return pixels;
}

}  // namespace

TEST_CASE("the compacted clamp compensation lists exactly the pixels whose near-surface test says maybe") {
  frame& f = small_frame();
  for (visibility_choice vis : {visibility_choice::exact, visibility_choice::voxels, visibility_choice::paper_voxels}) {
    options o = f.o;
    o.meth = method::global;
    o.visibility = vis;
    const render_settings es = make_render_settings(o, f.p.s);
    REQUIRE(uses_clamp_compensation(es));
    const rendered r = render(es, clamp_compensation_pass_choice::compacted);
    const std::vector<std::uint32_t> gpu = listed_pixels();
    // The CPU backend's test on the same G-buffer (the tracer of its visibility kind).
    const cpu_tracer tracer = make_cpu_tracer(f.b, vis);
    const vplkit::gbuffer_view<float> g = f.b.gbuf.view();
    std::vector<std::uint32_t> cpu;
    int valid = 0;
    for (int p = 0; p < g.width * g.height; ++p) {
      const vplkit::gather_point<float> gp = g.at(p);
      if (!vplkit::gather_point_valid(gp)) continue;
      ++valid;
      if (vplkit::clamp_compensation_may_add(tracer, gp, es.dmin)) cpu.push_back(static_cast<std::uint32_t>(p));
    }
    INFO(to_string(vis) << ": " << gpu.size() << " listed on the GPU, " << cpu.size() << " by the CPU's test, " << valid
                        << " valid pixels; " << r.details["gpu"].dump());
    CHECK(std::adjacent_find(gpu.begin(), gpu.end()) == gpu.end());  // each pixel once
    CHECK(gpu == cpu);
    CHECK(r.details["gpu"]["clamp_compensation"]["pixels"] == gpu.size());
    if (vis == visibility_choice::paper_voxels) {
      CHECK(int(cpu.size()) == valid);  // the paper's voxels cannot say: every valid pixel traces
    } else {
      CHECK(cpu.size() > 0);  // the box's junctions
      CHECK(int(cpu.size()) < valid / 2);  // most pixels have no other surface within dmin
    }
  }
}

TEST_CASE("the compacted clamp compensation gives the inline image bit for bit, every method that takes it") {
  frame& f = small_frame();
  struct pass_case {
    method m;
    visibility_choice vis;
    vpl_mode_choice vmode;
    bool direct;
    int spatial;  // ris: spatial-reuse neighbours (the reuse rounds add the term in their last round)
  };
  const pass_case cases[] = {
      {method::reference, visibility_choice::exact, vpl_mode_choice::patch, false, 0},
      {method::global, visibility_choice::exact, vpl_mode_choice::patch, true, 0},
      {method::local, visibility_choice::voxels, vpl_mode_choice::patch, false, 0},
      {method::gbg, visibility_choice::voxels, vpl_mode_choice::point, false, 0},
      {method::gbg, visibility_choice::exact, vpl_mode_choice::patch, false, 0},
      {method::ris, visibility_choice::exact, vpl_mode_choice::patch, false, 0},
      {method::ris, visibility_choice::voxels, vpl_mode_choice::patch, false, 2},
  };
  for (const pass_case& c : cases) {
    options o = f.o;
    o.meth = c.m;
    o.visibility = c.vis;
    o.vpl_mode = c.vmode;
    o.direct = c.direct;
    o.candidates = 4;
    o.spatial = c.spatial;
    render_settings es = make_render_settings(o, f.p.s);
    es.dmin *= 5.0f;  // most gather points near the box's junctions have a term
    REQUIRE(uses_clamp_compensation(es));
    render_settings off = es;
    off.clamp_compensation = clamp_compensation_choice::off;
    const rendered compacted = render(es, clamp_compensation_pass_choice::compacted);
    const rendered in_kernel = render(es, clamp_compensation_pass_choice::inline_pass);
    const rendered clamped = render(off, clamp_compensation_pass_choice::compacted);
    INFO(to_string(c.m) << ", " << to_string(c.vis) << ", --vpl-mode " << to_string(c.vmode)
                        << (c.direct ? ", --direct" : "") << ", --spatial " << c.spatial << ": "
                        << compacted.details["gpu"].dump());
    CHECK(compacted.details["clamp_compensation_pass"] == "compacted");
    CHECK(in_kernel.details["clamp_compensation_pass"] == "inline");
    CHECK(compacted.details["gpu"]["clamp_compensation"]["pixels"].get<int>() > 0);
    CHECK(!in_kernel.details["gpu"].contains("clamp_compensation"));
    INFO("worst relative difference " << worst_relative(compacted.image, in_kernel.image));
    CHECK(same_bits(compacted.image, in_kernel.image));
    CHECK(sum_of(compacted.image) > 1.001 * sum_of(clamped.image));  // the term is really there
  }
}

TEST_CASE("the compacted clamp compensation's directions split into other ranges give the same image") {
  frame& f = small_frame();
  for (method m : {method::global, method::reference}) {
    options o = f.o;
    o.meth = m;
    o.vpls = 64;
    render_settings es = make_render_settings(o, f.p.s);
    // 16 directions (the reference: 256), enough to split into 5 or more passes of 3
    es.clamp_compensation_dirs_rule = {clamp_compensation_dirs_choice::rule::fixed, 16};
    es.dmin *= 5.0f;
    const rendered one = render(es, clamp_compensation_pass_choice::compacted);
    const rendered split = render(es, clamp_compensation_pass_choice::compacted, loop_budget_choice::always, 3);
    INFO(to_string(m) << ": " << split.details["gpu"].dump());
    const int one_passes = one.details["gpu"]["clamp_compensation"]["direction_passes"].get<int>();
    const int split_passes = split.details["gpu"]["clamp_compensation"]["direction_passes"].get<int>();
    CHECK(split_passes >= 5);
    CHECK(split_passes > one_passes);
    CHECK(same_bits(one.image, split.image));
  }
}
