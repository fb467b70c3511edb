// SPDX-License-Identifier: MIT
// The GPU backend's DPRSM plane records (render/gpu/gpu_dprsm_planes.hpp, glsl/vplkit/vpl/
// dprsm_planes.comp): the frame pipeline builds them once the DPRSM is written, and every kernel
// that samples patch VPLs reads them (VPLKIT_DPRSM_PLANE_ACCESSOR) instead of computing a plane per
// neighbour and sample. The image must be the one of the kernels that compute them
// (render_settings::dprsm_planes = false), bit for bit: every method with patch VPLs, with and
// without the clamp's compensation. And the per-pixel buffers (gpu_scene_buffers::pixels) are kept
// from one render to the next: the second render of a frame reuses them.
#include "cli/render_options.hpp"
#include "cli/scene_setup.hpp"
#include "raster/gpu_scene_buffers.hpp"
#include "render/gpu/gpu_backend.hpp"
#include "render/pipeline.hpp"
#include "renderer_gl_fixture.hpp"

#include <headless_gl/compute.hpp>

#include <vplkit/vpl/dprsm_planes.hpp>

#include <catch2/catch.hpp>

#include <cstring>
#include <string>
#include <vector>

using namespace vplrender;

namespace {

// A small cornell frame with a DPRSM of 2 x 16^2 (creases inside texels: hidden plane points) and
// the exact rays on the GPU.
using frame = vplrender_test::gl_fixture;

const frame& small_frame() {
  static const frame* f = new frame(vplrender_test::make_pipeline_fixture([] {
    options o = vplrender_test::small_options("cornell", 24, 16, 16);
    o.visibility = visibility_choice::exact;
    return o;
  }()));
  return *f;
}

image_rgb render(const render_settings& es) {
  stage_timer t;
  return render_gpu(small_frame().b, es, t).image;
}

bool same_bits(const image_rgb& a, const image_rgb& b) {
  return a.rgb.size() == b.rgb.size() && std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)) == 0;
}

}  // namespace

TEST_CASE("the pipeline builds the DPRSM's plane records: those of vplkit::build_dprsm_planes") {
  const frame& f = small_frame();
  const gpu_scene_buffers& g = *f.b.gpu;
  REQUIRE(g.dprsm_planes.resolution == f.b.dprsm.resolution);
  CHECK(g.dprsm_planes.light_position == f.b.dprsm.light.position);
  // Against the C++ builder on the DPRSM read back: the class (sign of the height) exactly, the
  // values within the GLSL normalisation's few ulps (parity_dprsm_planes_test bounds them).
  const dprsm_data host = read_back_dprsm(g, f.b.dprsm.resolution, f.b.dprsm.light);
  const std::vector<vplkit::dprsm_plane<float>> cpu = vplkit::build_dprsm_planes(host.view());
  const std::vector<vplkit::dprsm_plane<float>> gpu = g.dprsm_planes.records.read<vplkit::dprsm_plane<float>>(cpu.size());
  int can_hide = 0;
  for (std::size_t t = 0; t < cpu.size(); ++t) {
    INFO("texel " << t);
    const int cc = cpu[t].height > 0 ? 1 : cpu[t].height < 0 ? -1 : 0;
    const int gc = gpu[t].height > 0 ? 1 : gpu[t].height < 0 ? -1 : 0;
    CHECK(cc == gc);
    CHECK(gpu[t].height == Approx(cpu[t].height).epsilon(1e-5).margin(1e-6));
    can_hide += cc > 0 ? 1 : 0;
  }
  CHECK(can_hide > 100);
}

TEST_CASE("patch VPLs through the plane records: the image of the kernels that compute the planes") {
  const frame& f = small_frame();
  struct planes_case {
    method m;
    bool compensate;
  };
  const planes_case cases[] = {{method::reference, false}, {method::global, false}, {method::global, true},
                               {method::gbg, false},       {method::local, true},   {method::mis, false},
                               {method::ris, false}};
  for (const planes_case& c : cases) {
    options o = f.o;
    o.meth = c.m;
    o.vpl_mode = vpl_mode_choice::patch;
    render_settings es = make_render_settings(o, f.p.s);
    if (c.compensate) es.dmin *= 5.0f;
    es.clamp_compensation = c.compensate ? clamp_compensation_choice::on : clamp_compensation_choice::off;
    render_settings direct = es;
    direct.dprsm_planes = false;
    const image_rgb with = render(es), without = render(direct);
    INFO(to_string(c.m) << (c.compensate ? " with the clamp's compensation" : ""));
    CHECK(same_bits(with, without));
    double sum = 0.0;
    for (float v : with.rgb) sum += v;
    CHECK(sum > 0.0);  // a black image would agree with anything
  }
}

TEST_CASE("the per-pixel buffers are kept from one render of a frame to the next") {
  const frame& f = small_frame();
  options o = f.o;
  o.meth = method::global;
  render_settings es = make_render_settings(o, f.p.s);
  es.loop_budget = loop_budget_choice::always;  // split: the state buffer too
  es.max_units_per_pass = 3;
  const image_rgb first = render(es);
  const gpu_pixel_buffers& px = f.b.gpu->pixels;
  const int made = px.allocations;
  REQUIRE(made >= 2);  // the estimates and the state, at the latest in this render
  const std::size_t pixels = static_cast<std::size_t>(f.o.width) * static_cast<std::size_t>(f.o.height);
  CHECK(px.out.size_bytes() == 16 * pixels);
  CHECK(px.state.size_bytes() == 48 * pixels);
  const image_rgb second = render(es);
  CHECK(px.allocations == made);  // nothing made: both reused (cleared on the GPU)
  CHECK(same_bits(first, second));
}
