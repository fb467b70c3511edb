// SPDX-License-Identifier: MIT
// --sampler share-tree (render/share_tree_mixture.hpp, estimate_distributions.glsl's
// VR_SAMPLER_SHARE_TREE; docs/math.md, "Image parity at large DPRSMs"): the CPU and GPU images agree
// at the small sizes of renderer_gpu_parity_test; a split GPU render resumes the tree stream where it
// stopped; the estimate is unbiased (the exhaustive VPL sum within the statistical bound); the
// estimators that do not draw the tree are refused. The image parity at 2 x 512^2 is
// renderer_gpu_parity_share_tree_test_slow.cpp (label slow: ~1 minute).
#include "renderer_gl_fixture.hpp"
#include "renderer_image_parity.hpp"

#include "cli/render_options.hpp"
#include "render/cpu/cpu_backend.hpp"
#include "render/gpu/gpu_backend.hpp"
#include "render/method_traits.hpp"

#include <vplkit/core/error.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <vector>

using namespace vplrender;
using vplrender_test::compare;
using vplrender_test::parity;

namespace {

double image_sum(const image_rgb& im) {
  double s = 0.0;
  for (float v : im.rgb) s += v;
  return s;
}

}  // namespace

TEST_CASE("The share-tree sampler: the GPU image is the CPU's, and a split render resumes the tree stream") {
  for (const char* scene : {"cornell", "open"}) {
    const vplrender_test::gl_fixture f = vplrender_test::make_gl_fixture(vplrender_test::small_options(scene));
    options o = f.o;
    o.visibility = visibility_choice::voxels;
    for (method m : {method::global, method::gbg, method::local, method::mis})
      for (vpl_mode_choice vm : {vpl_mode_choice::point, vpl_mode_choice::patch}) {
        o.meth = m;
        o.vpl_mode = vm;
        render_settings es = make_render_settings(o, f.p.s);
        es.threads = 2;
        es.sampler = sampler_choice::share_tree;
        stage_timer tc, tg, ts, tf;
        const render_result cr = render_cpu(f.b, es, tc);
        const render_result gr = render_gpu(f.b, es, tg);
        CHECK(cr.details["sampler"] == "share-tree");
        CHECK(gr.details["sampler"] == "share-tree");
        CHECK(gr.details.contains("share_tree"));
        // The builders' bound of renderer_gpu_parity_test (each side builds its own weights).
        const parity r = compare(cr.image, gr.image, 2e-4);
        std::cout << scene << " " << to_string(m) << " --vpl-mode " << to_string(vm) << " --sampler share-tree: "
                  << 100.0 * r.within << "% of pixels within 2e-4 relative; worst " << r.worst << "\n";
        INFO(scene << " " << to_string(m) << " --vpl-mode " << to_string(vm));
        CHECK(r.within >= 0.99);
        // One sample per dispatch (the clamp compensation's directions after them): draw k's tree
        // numbers start at k log2(L), so the split image is the one-dispatch image bit for bit.
        render_settings split = es;
        split.max_units_per_pass = 1;
        const render_result sr = render_gpu(f.b, split, ts);
        REQUIRE(sr.details["gpu"]["passes"].get<int>() > 1);
        CHECK(sr.image.rgb == gr.image.rgb);
        // The tree is really drawn: the flat CDF's image is another one (same pmf, other texels).
        render_settings flat = es;
        flat.sampler = sampler_choice::cdf;
        CHECK(compare(render_cpu(f.b, flat, tf).image, cr.image, 1e-3).within < 0.5);
      }
  }
}

TEST_CASE("The share-tree sampler is unbiased: the exhaustive VPL sum within the statistical bound") {
  // Point VPLs without the clamp's compensation: the expectations of estimate_vpl_sampling (global)
  // and of estimate_local (balance, one tree per region) are then exactly the reference's exhaustive
  // sum. Independent seeds give independent image sums X_s; their mean must lie within 4 standard
  // errors of the reference's sum (and the flat CDF's does too, the control). CPU only: the GPU
  // draws the same numbers (case above).
  const vplrender_test::gl_fixture f = vplrender_test::make_gl_fixture(vplrender_test::small_options("cornell"));
  options o = f.o;
  o.visibility = visibility_choice::voxels;
  o.vpl_mode = vpl_mode_choice::point;
  o.clamp_compensation = clamp_compensation_choice::off;
  o.meth = method::reference;
  render_settings ref = make_render_settings(o, f.p.s);
  ref.threads = 2;
  stage_timer t0;
  const double expected = image_sum(render_cpu(f.b, ref, t0).image);
  REQUIRE(expected > 0.0);
  for (method m : {method::global, method::local})
  for (sampler_choice sc : {sampler_choice::share_tree, sampler_choice::cdf}) {
    o.meth = m;
    o.vpls = 32;
    render_settings es = make_render_settings(o, f.p.s);
    es.threads = 2;
    es.sampler = sc;
    const int seeds = 24;
    std::vector<double> x;
    for (int s = 0; s < seeds; ++s) {
      es.seed = 1000u + static_cast<std::uint32_t>(s);
      stage_timer t;
      x.push_back(image_sum(render_cpu(f.b, es, t).image));
    }
    double mean = 0.0, var = 0.0;
    for (double v : x) mean += v;
    mean /= seeds;
    for (double v : x) var += (v - mean) * (v - mean);
    var /= seeds - 1;
    const double se = std::sqrt(var / seeds);
    std::cout << to_string(m) << " --sampler " << to_string(sc) << ": mean image sum " << mean << " vs the exhaustive sum " << expected
              << " (" << (mean - expected) / se << " standard errors; se " << se / expected << " relative)\n";
    INFO(to_string(m) << " --sampler " << to_string(sc));
    CHECK(se > 0.0);
    CHECK(std::abs(mean - expected) <= 4.0 * se);
  }
}

TEST_CASE("The share-tree sampler: the backends refuse the estimators that do not draw the tree") {
  const vplrender_test::gl_fixture f = vplrender_test::make_gl_fixture(vplrender_test::small_options("cornell"));
  for (method m : {method::ris, method::ris_mis}) {
    options o = f.o;
    o.meth = m;
    render_settings es = make_render_settings(o, f.p.s);
    es.threads = 2;
    es.sampler = sampler_choice::share_tree;
    stage_timer t;
    INFO(to_string(m));
    CHECK_THROWS_WITH(render_cpu(f.b, es, t), Catch::Contains("--sampler share-tree: not supported with --method"));
    CHECK_THROWS_WITH(render_gpu(f.b, es, t), Catch::Contains("--sampler share-tree: not supported with --method"));
  }
}
