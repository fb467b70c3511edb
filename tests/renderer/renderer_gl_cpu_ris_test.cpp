// SPDX-License-Identifier: MIT
// --method ris on the CPU backend (render/cpu/ris_render.hpp), on cornell at 48x32 (DPRSM 2x32^2,
// 32^3 voxels, point VPLs so that the exhaustive VPL sum is an exact reference): every candidate
// source with and without spatial reuse converges to the VPL sum (the image mean, and the mean
// over the pixels at depth edges, where a biased reuse darkens); the image does not depend on the
// thread count; the flags reach the settings; and the GPU backend runs it (renderer_gpu_parity_ris_test
// compares the images).
#include "renderer_gl_fixture.hpp"

#include "cli/render_options.hpp"
#include "io/errors.hpp"
#include "render/cpu/cpu_backend.hpp"
#include "render/pipeline.hpp"

#include <vplkit/estimators/ris_spatial_reuse.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <vector>

using namespace vplrender;

namespace {

using fixture = vplrender_test::gl_fixture;

const fixture& shared_fixture() {
  static const fixture f = [] {
    options o = vplrender_test::small_options("cornell", 48, 32, 32, 32);
    o.vpl_mode = vpl_mode_choice::point;
    o.back = backend::cpu;
    return vplrender_test::make_gl_fixture(o);
  }();
  return f;
}

image_rgb render(const fixture& f, const options& o, int threads = 2) {
  render_settings es = make_render_settings(o, f.p.s);
  es.threads = threads;
  stage_timer t;
  return render_cpu(f.b, es, t).image;
}

// Mean over the pixels in `which` (all when empty) and channels.
double mean_of(const image_rgb& a, const std::vector<int>& which = {}) {
  double s = 0.0;
  std::size_t n = 0;
  for (std::size_t p = 0; p < a.rgb.size() / 3; ++p) {
    if (!which.empty() && std::find(which.begin(), which.end(), int(p)) == which.end()) continue;
    for (int c = 0; c < 3; ++c) s += a.rgb[3 * p + std::size_t(c)];
    n += 3;
  }
  return s / double(n);
}

bool finite_non_negative(const image_rgb& a) {
  for (float v : a.rgb)
    if (!std::isfinite(v) || v < 0.0f) return false;
  return true;
}

// Pixels next to a depth edge: a 4-neighbour whose point lies off this pixel's tangent plane.
std::vector<int> edge_pixels(const fixture& f) {
  const auto g = f.b.gbuf.view();
  std::vector<int> out;
  for (int y = 1; y + 1 < g.height; ++y)
    for (int x = 1; x + 1 < g.width; ++x) {
      const int p = y * g.width + x;
      bool edge = false;
      for (const int q : {p - 1, p + 1, p - g.width, p + g.width})
        edge = edge || !vplkit::ris_neighbour_similar(g.at(p), g.at(q), -2.0f, 0.1f);
      if (edge) out.push_back(p);
    }
  return out;
}

}  // namespace

TEST_CASE("ris on the CPU backend: every source, with and without reuse, converges to the VPL sum") {
  const fixture& f = shared_fixture();
  options ref_o = f.o;
  ref_o.meth = method::reference;
  const image_rgb ref = render(f, ref_o);
  const std::vector<int> edges = edge_pixels(f);
  REQUIRE(edges.size() > 20);
  const double ref_mean = mean_of(ref), ref_edges = mean_of(ref, edges);
  std::printf("ris on cornell 48x32 (point VPLs): reference mean %.5f, at %zu edge pixels %.5f\n", ref_mean,
              edges.size(), ref_edges);
  for (const ris_source_choice source :
       {ris_source_choice::global, ris_source_choice::local, ris_source_choice::gbg, ris_source_choice::flux})
    for (const int spatial : {0, 4}) {
      options o = f.o;
      o.meth = method::ris;
      o.candidate_source = source;
      o.spatial = spatial;
      o.candidates = 16;
      o.vpls = 64;
      o.eps = 0.1;
      const image_rgb img = render(f, o);
      const double m = mean_of(img), e = mean_of(img, edges);
      std::printf("  %-6s spatial %d: mean %+.2f %%, edge pixels %+.2f %%\n", to_string(source), spatial,
                  100.0 * (m / ref_mean - 1.0), 100.0 * (e / ref_edges - 1.0));
      INFO(to_string(source) << " spatial " << spatial);
      CHECK(finite_non_negative(img));
      CHECK(std::abs(m / ref_mean - 1.0) < 0.01);
      CHECK(std::abs(e / ref_edges - 1.0) < 0.03);
    }
}

TEST_CASE("ris on the CPU backend: the image does not depend on the thread count") {
  const fixture& f = shared_fixture();
  options o = f.o;
  o.meth = method::ris;
  o.vpls = 3;
  o.candidates = 8;
  for (const int spatial : {0, 3}) {
    o.spatial = spatial;
    const image_rgb one = render(f, o, 1), two = render(f, o, 2);
    INFO("spatial " << spatial);
    CHECK(mean_of(one) > 0.0);
    CHECK(std::memcmp(one.rgb.data(), two.rgb.data(), one.rgb.size() * sizeof(float)) == 0);
  }
}

TEST_CASE("ris: the flags reach the settings, and the GPU backend runs it") {
  const fixture& f = shared_fixture();
  options o = f.o;
  o.meth = method::ris;
  o.candidates = 9;
  o.candidate_source = ris_source_choice::flux;
  o.spatial = 3;
  o.vpls = 2;
  o.clamp_compensation = clamp_compensation_choice::off;  // the GPU backend does not have it
  const render_settings r = make_render_settings(o, f.p.s);
  CHECK(r.meth == method::ris);
  CHECK(r.ris_candidates == 9);
  CHECK(r.ris_source == ris_source_choice::flux);
  CHECK(r.ris_spatial == 3);
  CHECK(r.vpls == 2);
  frame_buffers gpu_frame{backend::gpu, "", f.b.gbuf, f.b.dprsm, f.b.grid, f.b.gpu, nullptr, {}, f.b.facts, nullptr};
  stage_timer t;
  nlohmann::json det;
  const render_result g = run_estimator(gpu_frame, r, t, {}, det);
  CHECK(finite_non_negative(g.image));
  CHECK(mean_of(g.image) > 0.0);
  CHECK(g.details["ris"]["candidates"] == 9);
  CHECK(g.details["ris"]["spatial"] == 3);
  CHECK(g.details["gpu"]["passes"] == 4);  // two rounds of a candidate and a reuse pass
}
