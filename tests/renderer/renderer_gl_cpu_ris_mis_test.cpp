// SPDX-License-Identifier: MIT
// --method ris-mis on the CPU backend (render/cpu/ris_render.hpp, vplkit::estimate_ris_mis), on
// cornell at 48x32 (DPRSM 2x32^2, 32^3 voxels, patch VPLs): its image mean equals mis's (the same
// estimand, the unclamped one-bounce integral) with every candidate source, over the whole image
// and at the pixels on depth edges; it has no clamp (dmin changes nothing, no compensation is
// added); with spatial reuse (--spatial 4, vplkit::ris_mis_spatial_reuse) its image mean is mis's
// too, over the image and at the depth edges; the image does not depend on the thread count, with
// and without reuse; its details name its settings.
#include "renderer_gl_fixture.hpp"

#include "cli/render_options.hpp"
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
    o.back = backend::cpu;
    return vplrender_test::make_gl_fixture(o);
  }();
  return f;
}

render_result render(const fixture& f, const options& o, int threads = 2) {
  render_settings es = make_render_settings(o, f.p.s);
  es.threads = threads;
  stage_timer t;
  return render_cpu(f.b, es, t);
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

options ris_mis_options(const fixture& f, int n, int m) {
  options o = f.o;
  o.meth = method::ris_mis;
  o.vpls = n;
  o.dirs = n;
  o.candidates = m;
  o.candidate_pool = 0;  // each candidate its own draw; the pool's cases set theirs
  return o;
}

}  // namespace

TEST_CASE("ris-mis on the CPU backend: its image mean is mis's, with every candidate source") {
  const fixture& f = shared_fixture();
  // mis at 128 + 128, averaged over two seeds: the estimand, up to about 0.1 % of noise.
  options mis_o = f.o;
  mis_o.meth = method::mis;
  mis_o.vpls = mis_o.dirs = 128;
  const std::vector<int> edges = edge_pixels(f);
  REQUIRE(edges.size() > 20);
  double ref = 0.0, ref_edges = 0.0;
  for (const std::uint32_t seed : {1u, 2u}) {
    mis_o.seed = seed;
    const image_rgb img = render(f, mis_o).image;
    ref += 0.5 * mean_of(img);
    ref_edges += 0.5 * mean_of(img, edges);
  }
  std::printf("ris-mis on cornell 48x32 (patch VPLs): mis mean %.5f, at %zu edge pixels %.5f\n", ref, edges.size(),
              ref_edges);
  for (const ris_source_choice source : {ris_source_choice::global, ris_source_choice::local, ris_source_choice::gbg,
                                        ris_source_choice::flux, ris_source_choice::tiles})
    for (const int spatial : {0, 4}) {
      options o = ris_mis_options(f, 32, 8);
      o.candidate_source = source;
      o.spatial = spatial;
      const image_rgb img = render(f, o).image;
      const double m = mean_of(img), e = mean_of(img, edges);
      std::printf("  %-6s 32 + 32, M = 8, spatial %d: mean %+.2f %%, edge pixels %+.2f %%\n", to_string(source),
                  spatial, 100.0 * (m / ref - 1.0), 100.0 * (e / ref_edges - 1.0));
      INFO(to_string(source) << " spatial " << spatial);
      CHECK(finite_non_negative(img));
      CHECK(std::abs(m / ref - 1.0) < 0.01);
      CHECK(std::abs(e / ref_edges - 1.0) < 0.03);
    }
}

TEST_CASE("ris-mis on the CPU backend: no clamp, no compensation") {
  const fixture& f = shared_fixture();
  options o = ris_mis_options(f, 4, 8);
  o.clamp_compensation = clamp_compensation_choice::on;
  o.dmin_fraction = 0.05;
  const render_result a = render(f, o);
  o.dmin_fraction = 0.0;
  const render_result b = render(f, o);
  // dmin reaches neither the estimate nor a compensation pass: the same image, bit for bit.
  CHECK(mean_of(a.image) > 0.0);
  CHECK(std::memcmp(a.image.rgb.data(), b.image.rgb.data(), a.image.rgb.size() * sizeof(float)) == 0);
  CHECK_FALSE(a.details.contains("clamp_compensation_dirs"));
  // ris, clamped, does change with dmin (the check above can fail).
  options r = o;
  r.meth = method::ris;
  r.dmin_fraction = 0.05;
  r.clamp_compensation = clamp_compensation_choice::off;
  const image_rgb c = render(f, r).image;
  r.dmin_fraction = 0.0;
  const image_rgb d = render(f, r).image;
  CHECK(std::memcmp(c.rgb.data(), d.rgb.data(), c.rgb.size() * sizeof(float)) != 0);
}

TEST_CASE("ris-mis on the CPU backend: thread count and details, with and without spatial reuse") {
  const fixture& f = shared_fixture();
  options o = ris_mis_options(f, 3, 5);
  o.candidate_source = ris_source_choice::local;
  const render_result one = render(f, o, 1), two = render(f, o, 2);
  CHECK(mean_of(one.image) > 0.0);
  CHECK(std::memcmp(one.image.rgb.data(), two.image.rgb.data(), one.image.rgb.size() * sizeof(float)) == 0);
  const nlohmann::json& det = two.details;
  REQUIRE(det.contains("ris"));
  CHECK(det["ris"]["candidates"] == 5);
  CHECK(det["ris"]["candidate_source"] == "local");
  CHECK(det["ris"]["dirs"] == 3);
  CHECK(det["ris"]["spatial"] == 0);
  CHECK(det.contains("lit_test"));
  // With reuse (per-region distributions: each pixel's target uses its own region's pmf).
  o.spatial = 2;
  const render_result r1 = render(f, o, 1), r2 = render(f, o, 2);
  CHECK(mean_of(r1.image) > 0.0);
  CHECK(finite_non_negative(r1.image));
  CHECK(std::memcmp(r1.image.rgb.data(), r2.image.rgb.data(), r1.image.rgb.size() * sizeof(float)) == 0);
  CHECK(std::memcmp(r1.image.rgb.data(), one.image.rgb.data(), r1.image.rgb.size() * sizeof(float)) != 0);
  CHECK(r2.details["ris"]["spatial"] == 2);
  CHECK(r2.details["ris"]["reuse_mis"] == "pairwise");
  CHECK(r2.details["ris"].contains("radius"));
}

TEST_CASE("ris-mis with a candidate pool: its image mean is mis's, per source, with and without reuse") {
  const fixture& f = shared_fixture();
  options mis_o = f.o;
  mis_o.meth = method::mis;
  mis_o.vpls = mis_o.dirs = 128;
  const std::vector<int> edges = edge_pixels(f);
  double ref = 0.0, ref_edges = 0.0;
  for (const std::uint32_t seed : {1u, 2u}) {
    mis_o.seed = seed;
    const image_rgb img = render(f, mis_o).image;
    ref += 0.5 * mean_of(img);
    ref_edges += 0.5 * mean_of(img, edges);
  }
  // A pool of 4096 (one per region with local) against the 32 x 8 candidates of a pixel: its own
  // noise is small, so the means must hold the bounds of the direct draws above.
  for (const ris_source_choice source : {ris_source_choice::local, ris_source_choice::flux, ris_source_choice::tiles})
    for (const int spatial : {0, 4}) {
      options o = ris_mis_options(f, 32, 8);
      o.candidate_source = source;
      o.spatial = spatial;
      o.candidate_pool = 4096;
      // Tiles as local's regions: 4 pools of 4096 (at 64 tiles each pool serves 24 pixels, and the
      // image mean of one frame carries every pool's own noise: +1.1 % at spatial 0, where 12 seeds
      // average +0.3 %, the direct draws' offset from mis above).
      o.tiles = 4;
      const render_result r = render(f, o);
      const double m = mean_of(r.image), e = mean_of(r.image, edges);
      std::printf("  pool 4096, %-6s 32 + 32, M = 8, spatial %d: mean %+.2f %%, edge pixels %+.2f %%\n",
                  to_string(source), spatial, 100.0 * (m / ref - 1.0), 100.0 * (e / ref_edges - 1.0));
      INFO(to_string(source) << " spatial " << spatial);
      CHECK(finite_non_negative(r.image));
      CHECK(std::abs(m / ref - 1.0) < 0.01);
      CHECK(std::abs(e / ref_edges - 1.0) < 0.03);
      CHECK(r.details["ris"]["pool"] == 4096);
    }
}

TEST_CASE("ris-mis with a candidate pool: the thread count changes nothing, the pool changes the draws") {
  const fixture& f = shared_fixture();
  options o = ris_mis_options(f, 3, 5);
  o.candidate_source = ris_source_choice::local;
  o.candidate_pool = 1000;  // not a multiple of the fill's chunk
  const render_result one = render(f, o, 1), two = render(f, o, 2);
  CHECK(mean_of(one.image) > 0.0);
  CHECK(std::memcmp(one.image.rgb.data(), two.image.rgb.data(), one.image.rgb.size() * sizeof(float)) == 0);
  o.candidate_pool = 0;
  const render_result direct = render(f, o, 2);
  CHECK(std::memcmp(direct.image.rgb.data(), two.image.rgb.data(), two.image.rgb.size() * sizeof(float)) != 0);
  CHECK_FALSE(direct.details["ris"].contains("pool"));
}

TEST_CASE("ris-mis with tile candidates: the thread count changes nothing, and the details name the tiles") {
  const fixture& f = shared_fixture();
  options o = ris_mis_options(f, 3, 5);
  o.candidate_source = ris_source_choice::tiles;
  o.tiles = 12;  // 4x3 tiles of 12x10-11 pixels
  o.tile_points = 5;
  o.tile_block = 4;
  o.candidate_pool = 700;
  const render_result one = render(f, o, 1), two = render(f, o, 2);
  CHECK(mean_of(one.image) > 0.0);
  CHECK(finite_non_negative(one.image));
  CHECK(std::memcmp(one.image.rgb.data(), two.image.rgb.data(), one.image.rgb.size() * sizeof(float)) == 0);
  const nlohmann::json& det = two.details;
  REQUIRE(det.contains("tiles"));
  CHECK(det["tiles"]["tiles"] == 12);
  CHECK(det["tiles"]["grid"] == nlohmann::json::array({4, 3}));
  CHECK(det["tiles"]["points"].size() == 12u);
  CHECK(det["tiles"]["block"] == 4);
  CHECK(det["tiles"]["blocks"] == 2 * 8 * 8);  // DPRSM 2x32^2 in blocks of 4x4
  CHECK(det["ris"]["candidate_source"] == "tiles");
  CHECK(det["ris"]["pool"] == 700);
  // The tiles' own distributions, not the flux CDF's: another image than flux's.
  o.candidate_source = ris_source_choice::flux;
  const render_result flux = render(f, o, 2);
  CHECK(std::memcmp(flux.image.rgb.data(), two.image.rgb.data(), two.image.rgb.size() * sizeof(float)) != 0);
  // ris itself has no tiles: refused with a message, not rendered with the flux CDF.
  o.candidate_source = ris_source_choice::tiles;
  o.meth = method::ris;
  CHECK_THROWS_WITH(render(f, o, 2), Catch::Contains("tiles is for --method ris-mis"));
}
