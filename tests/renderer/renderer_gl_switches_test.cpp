// SPDX-License-Identifier: MIT
// The estimator switches on the CPU backend: --cdf-search binary draws exactly the
// indices of the guide table (the guided search returns the binary search's index by
// construction), so the image is bit-identical; --local-combination average is a different
// estimator from balance (different image) with finite values; --gbg-accumulator paper builds
// other GBG weights (different image). Small images, DPRSM 2x16x16, 32^3 voxels.
#include "renderer_gl_fixture.hpp"

#include "cli/render_options.hpp"
#include "app/report.hpp"
#include "cli/scene_setup.hpp"
#include "raster/gl_raster.hpp"
#include "raster/tessellate.hpp"
#include "raster/voxels.hpp"
#include "render/cpu/cpu_backend.hpp"
#include "render/cpu/cpu_builders.hpp"
#include "render/mixture_components.hpp"
#include "scene/builtin_scenes.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>

using namespace vplrender;

namespace {

using fixture = vplrender_test::gl_fixture;

fixture make_fixture() { return vplrender_test::make_gl_fixture(vplrender_test::small_options("cornell")); }

image_rgb render(const fixture& f, const options& o) {
  render_settings es = make_render_settings(o, f.p.s);
  es.threads = 2;
  stage_timer t;
  return render_cpu(f.b, es, t).image;
}

bool bit_identical(const image_rgb& a, const image_rgb& b) {
  return a.rgb.size() == b.rgb.size() && std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)) == 0;
}

double mean_of(const image_rgb& a) {
  double s = 0.0;
  for (float v : a.rgb) s += v;
  return s / static_cast<double>(a.rgb.size());
}

bool finite_non_negative(const image_rgb& a) {
  for (float v : a.rgb)
    if (!std::isfinite(v) || v < 0.0f) return false;
  return true;
}

}  // namespace

TEST_CASE("cdf-search binary gives the bit-identical image of the guide table on the CPU backend") {
  const fixture f = make_fixture();
  for (method m : {method::global, method::local, method::gbg, method::mis, method::mis_as_published}) {
    options o = f.o;
    o.meth = m;
    o.eps = 0.1;
    o.sampler = sampler_choice::cdf;  // the search concerns the CDF sampler (the default draws share trees)
    const image_rgb guide = render(f, o);
    o.cdf_search = cdf_search_choice::binary;
    const image_rgb binary = render(f, o);
    INFO(to_string(m));
    CHECK(mean_of(guide) > 0.0);
    CHECK(bit_identical(guide, binary));
  }
}

TEST_CASE("sampler alias and face-selection roulette: the joint CDF's pmf, other draws, finite images") {
  const fixture f = make_fixture();
  for (method m : {method::global, method::local, method::gbg}) {
    options o = f.o;
    o.meth = m;
    o.eps = 0.1;
    const image_rgb joint = render(f, o);
    render_settings s = make_render_settings(o, f.p.s);
    stage_timer t;
    nlohmann::json det;
    const cpu_distributions built = build_distributions_cpu(f.b, s, t, {}, det);
    for (int k = 0; k < 2; ++k) {
      INFO(to_string(m) << (k == 0 ? " alias" : " roulette"));
      options ok = o;
      if (k == 0) ok.sampler = sampler_choice::alias;
      else ok.face_selection = face_selection_choice::roulette;
      s = make_render_settings(ok, f.p.s);
      const mixture_components c =
          build_mixture_components(built.weights.data(), static_cast<int>(built.dists.size()), f.b.dprsm.view(), s);
      // Every texel's pmf equals the joint mixture's up to float rounding (w_t / sum w either way):
      // the joint pmf is a difference of float prefix sums <= 1, each within half an ulp of 1
      // (2^-25), so it is off by up to 2^-24 absolute; the roulette's face pmf likewise, times b_F.
      double worst = -1.0;  // largest excess over the bound
      int positive = 0;
      const auto alias = k == 0 ? component_mixtures(built.dists, c.alias)
                                : std::vector<vplkit::defensive_mixture<float, vplkit::alias_table<float>>>();
      const auto flat = k == 1 ? component_mixtures(built.dists, c.flat)
                               : std::vector<vplkit::defensive_mixture<float, vplkit::flat_face_roulette<float>>>();
      for (std::size_t d = 0; d < built.dists.size(); ++d) {
        const auto& joint_d = built.dists[d];
        for (std::size_t i = 0; i < joint_d.size(); ++i) {
          const float pj = joint_d.pmf(i);
          const float pk = k == 0 ? alias[d].pmf(i) : flat[d].pmf(i);
          REQUIRE((pj == 0.0f) == (pk == 0.0f));
          if (pj > 0.0f) {
            ++positive;
            worst = std::max(worst, std::abs(double(pk) - pj) - (4e-7 * pj + 0x1p-23));
          }
        }
      }
      CHECK(positive > 100);
      CHECK(worst <= 0.0);
      const image_rgb other = render(f, ok);
      CHECK(finite_non_negative(other));
      CHECK(mean_of(other) > 0.0);
      CHECK_FALSE(bit_identical(joint, other));  // another texel for some u
    }
  }
}

TEST_CASE("local-combination average differs from balance and both are finite") {
  const fixture f = make_fixture();
  options o = f.o;
  o.meth = method::local;
  o.vpls = 16;
  const image_rgb balance = render(f, o);
  o.local_combination = local_combination_choice::average;
  const image_rgb average = render(f, o);
  CHECK(finite_non_negative(balance));
  CHECK(finite_non_negative(average));
  CHECK(mean_of(balance) > 0.0);
  CHECK(mean_of(average) > 0.0);
  // Same random numbers and the same draws, divided differently: many pixels change.
  int changed = 0;
  for (std::size_t i = 0; i < balance.rgb.size(); ++i)
    if (balance.rgb[i] != average.rgb[i]) ++changed;
  CHECK(changed > static_cast<int>(balance.rgb.size() / 4));
}

TEST_CASE("gbg-accumulator paper builds other weights than gathering and gives a finite image") {
  const fixture f = make_fixture();
  options o = f.o;
  o.meth = method::gbg;
  const image_rgb gathering = render(f, o);
  o.gbg_accumulator = gbg_accumulator_choice::paper;
  const image_rgb paper = render(f, o);
  CHECK(finite_non_negative(paper));
  CHECK(mean_of(paper) > 0.0);
  CHECK_FALSE(bit_identical(gathering, paper));
}

TEST_CASE("the JSON report records the chosen switches") {
  const fixture f = make_fixture();
  options o = f.o;
  o.back = backend::cpu;
  o.meth = method::local;
  o.local_combination = local_combination_choice::average;
  o.gbg_accumulator = gbg_accumulator_choice::paper;
  o.cdf_search = cdf_search_choice::binary;
  const nlohmann::json params = options_to_json(o);
  CHECK(params["local_combination"] == "average");
  CHECK(params["gbg_accumulator"] == "paper");
  CHECK(params["cdf_search"] == "binary");
  CHECK(options_to_json(f.o)["cdf_search"] == "guide");
  stage_timer t;
  nlohmann::json det;
  frame_buffers b = prepare_buffers(o, f.p, t, det);
  run_estimator(o, f.p, b, t, {}, det);
  CHECK(det["estimator"]["local_combination"] == "average");
  CHECK(det["estimator"]["cdf_search"] == "binary");
  o.meth = method::gbg;
  nlohmann::json det2;
  run_estimator(o, f.p, b, t, {}, det2);
  CHECK(det2["estimator"]["gbg"]["accumulator"] == "paper");
  CHECK(det2["estimator"]["cdf_search"] == "binary");
}
