// SPDX-License-Identifier: MIT
// --method ris on the GPU backend (examples/vplrender/shaders/estimate_ris.comp) against the CPU
// backend (render/cpu/ris_render.hpp): the same image for every candidate source, with and without
// spatial reuse (the reuse pass picks the same neighbours from the same stream and weighs them with
// the same pairwise MIS), M = 1 included; the hard case where every candidate's target is 0; and
// the GPU image's mean against the exhaustive VPL sum (point VPLs), with and without reuse.
// Clamp compensation off on both sides: the GPU backend does not have it (docs/renderer.md).
//
// The bound. The candidate sources' weights and CDFs are built on each side (the GPU's CDF values
// are the C++ ones or float neighbours: renderer_gpu_parity_test's rel_bound_gpu_builders), and
// the GPU may contract a * b + c outside `precise` code. RIS turns such a last-ulp difference into
// a different kept candidate only where a selection number lies within that distance of a
// reservoir's threshold; with reuse the pixel's neighbours inherit it. Such pixels are rare: we
// require >= 97 % of the pixels within the bound and every pixel finite and non-negative.
#include "renderer_gl_fixture.hpp"

#include "cli/render_options.hpp"
#include "render/cpu/cpu_backend.hpp"
#include "render/gpu/gpu_backend.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>

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
  o.clamp_compensation = clamp_compensation_choice::off;
  render_settings es = make_render_settings(o, f.p.s);
  es.threads = 2;
  return es;
}

image_rgb cpu_image(const fixture& f, const render_settings& es) {
  stage_timer t;
  return render_cpu(f.b, es, t).image;
}
image_rgb gpu_image(const fixture& f, const render_settings& es) {
  stage_timer t;
  return render_gpu(f.b, es, t).image;
}

bool finite_non_negative(const image_rgb& a) {
  for (float v : a.rgb)
    if (!std::isfinite(v) || v < 0.0f) return false;
  return true;
}

// The fraction of pixels whose channels agree within rel_bound (plus a floor of 1e-6 of the mean).
double agreeing(const image_rgb& c, const image_rgb& g) {
  double mean = 0.0;
  for (float v : c.rgb) mean += v;
  mean /= double(std::max<std::size_t>(1, c.rgb.size()));
  int ok = 0;
  for (std::size_t p = 0; p < c.rgb.size() / 3; ++p) {
    bool inside = true;
    for (std::size_t k = 0; k < 3; ++k) {
      const double a = c.rgb[3 * p + k], b = g.rgb[3 * p + k];
      inside = inside && std::abs(a - b) <= rel_bound * std::max(std::abs(a), std::abs(b)) + 1e-6 * mean;
    }
    ok += inside ? 1 : 0;
  }
  return double(ok) / double(c.rgb.size() / 3);
}

double mean_of(const image_rgb& a) {
  double s = 0.0;
  for (float v : a.rgb) s += v;
  return s / double(std::max<std::size_t>(1, a.rgb.size()));
}

}  // namespace

TEST_CASE("ris: the GPU image equals the CPU image for every candidate source, with and without reuse") {
  const fixture& f = shared_fixture();
  struct run {
    ris_source_choice source;
    int spatial, candidates;
    vpl_mode_choice mode;
  };
  const run runs[] = {
      {ris_source_choice::global, 0, 8, vpl_mode_choice::patch}, {ris_source_choice::global, 3, 8, vpl_mode_choice::patch},
      {ris_source_choice::local, 0, 8, vpl_mode_choice::patch},  {ris_source_choice::local, 3, 8, vpl_mode_choice::patch},
      {ris_source_choice::gbg, 0, 8, vpl_mode_choice::patch},    {ris_source_choice::gbg, 3, 8, vpl_mode_choice::patch},
      {ris_source_choice::flux, 0, 8, vpl_mode_choice::patch},   {ris_source_choice::flux, 3, 8, vpl_mode_choice::patch},
      {ris_source_choice::flux, 2, 8, vpl_mode_choice::point},   {ris_source_choice::flux, 0, 1, vpl_mode_choice::point},
      {ris_source_choice::global, 2, 1, vpl_mode_choice::patch}};
  for (const run& r : runs) {
    options o = f.o;
    o.meth = method::ris;
    o.candidate_source = r.source;
    o.spatial = r.spatial;
    o.candidates = r.candidates;
    o.vpl_mode = r.mode;
    o.vpls = 3;
    o.regions = 2;
    const render_settings es = settings_of(f, o);
    const image_rgb c = cpu_image(f, es), g = gpu_image(f, es);
    const double within = agreeing(c, g);
    std::printf("ris %-6s --spatial %d --candidates %d --vpl-mode %s: %.1f %% of pixels within %g, means cpu %.6f gpu %.6f\n",
                to_string(r.source), r.spatial, r.candidates, to_string(r.mode), 100.0 * within, rel_bound, mean_of(c),
                mean_of(g));
    INFO(to_string(r.source) << " --spatial " << r.spatial << " --candidates " << r.candidates);
    CHECK(finite_non_negative(c));
    CHECK(finite_non_negative(g));
    CHECK(mean_of(g) > 0.0);
    CHECK(within >= required_fraction);
  }
}

TEST_CASE("ris on the GPU: candidates whose targets are all 0 leave the direct light alone, not a NaN") {
  // dmin^2 overflows to infinity: every unshadowed contribution, so every target, is 0 and every
  // reservoir empty. The kernel writes the indirect estimate plus --direct's light; a NaN from an
  // empty reservoir (0 / 0) would make the read-back's finite guard zero the whole pixel, direct
  // light included.
  const fixture& f = shared_fixture();
  for (const int spatial : {0, 2}) {
    options o = f.o;
    o.meth = method::ris;
    o.candidates = 4;
    o.vpls = 2;
    o.spatial = spatial;
    o.direct = true;
    render_settings es = settings_of(f, o);
    es.dmin = 1e30f;
    const image_rgb g = gpu_image(f, es), c = cpu_image(f, es);
    INFO("--spatial " << spatial);
    REQUIRE(finite_non_negative(g));
    CHECK(mean_of(g) > 0.0);  // the direct light
    CHECK(agreeing(c, g) >= 0.999);
  }
}

TEST_CASE("ris on the GPU: the image mean converges to the exhaustive VPL sum, with and without reuse") {
  // Point VPLs: the exhaustive VPL sum (--method reference) is the exact estimand. The image mean
  // of 4 seeds, each 48 samples of 16 candidates per pixel, against it: within 4 standard errors
  // (estimated from the 4 seeds' means) plus 0.5 % (the GPU reference's own float rounding and
  // the seeds' small count), so a bias of a few percent fails while noise does not.
  const fixture& f = shared_fixture();
  options ref_o = f.o;
  ref_o.meth = method::reference;
  ref_o.vpl_mode = vpl_mode_choice::point;
  const double ref = mean_of(gpu_image(f, settings_of(f, ref_o)));
  REQUIRE(ref > 0.0);
  for (const ris_source_choice source : {ris_source_choice::flux, ris_source_choice::gbg})
    for (const int spatial : {0, 4}) {
      double sum = 0.0, sum2 = 0.0;
      const int seeds = 4;
      for (int seed = 1; seed <= seeds; ++seed) {
        options o = f.o;
        o.meth = method::ris;
        o.vpl_mode = vpl_mode_choice::point;
        o.candidate_source = source;
        o.spatial = spatial;
        o.candidates = 16;
        o.vpls = 48;
        o.eps = 0.1;
        o.seed = static_cast<std::uint32_t>(seed);
        const double m = mean_of(gpu_image(f, settings_of(f, o))) / ref;
        sum += m;
        sum2 += m * m;
      }
      const double mean = sum / seeds;
      const double se = std::sqrt(std::max(0.0, (sum2 - seeds * mean * mean) / (seeds - 1)) / seeds);
      std::printf("ris on the GPU, %s --spatial %d: mean %+.2f %% of the VPL sum, standard error %.2f %%\n",
                  to_string(source), spatial, 100.0 * (mean - 1.0), 100.0 * se);
      INFO(to_string(source) << " --spatial " << spatial << ": mean/ref " << mean << ", standard error " << se);
      CHECK(std::abs(mean - 1.0) <= 4.0 * se + 0.005);
    }
}

TEST_CASE("ris on the GPU: the samples split over dispatches give the image of one dispatch") {
  // Without reuse the samples are the kernel's units (VR_SPLIT 1: sum and stream in the state
  // buffer between dispatches); with reuse every round is its own pair of dispatches whatever the
  // budget. Either way the image is the one of a single dispatch, bit for bit.
  // With the clamp's compensation inline its directions (ceil(5 / 4) = 2 here) are further units
  // (the compacted passes split theirs on their own: renderer_gpu_clamp_compensation_pass_test).
  const fixture& f = shared_fixture();
  for (const int spatial : {0, 2})
  for (const bool compensated : {false, true}) {
    options o = f.o;
    o.meth = method::ris;
    o.candidates = 4;
    o.vpls = 5;
    o.spatial = spatial;
    render_settings es = settings_of(f, o);
    if (compensated) {
      es.clamp_compensation = clamp_compensation_choice::on;
      es.clamp_compensation_pass = clamp_compensation_pass_choice::inline_pass;
      es.clamp_compensation_dirs_rule = {clamp_compensation_dirs_choice::rule::per_vpls, 4};  // 2 directions
      es.dmin *= 5.0f;
    }
    es.loop_budget = loop_budget_choice::never;
    stage_timer t1, t2;
    const render_result one = render_gpu(f.b, es, t1);
    es.loop_budget = loop_budget_choice::always;
    es.max_units_per_pass = 2;
    const render_result split = render_gpu(f.b, es, t2);
    INFO("--spatial " << spatial << (compensated ? " --clamp-compensation on" : ""));
    CHECK(split.details["gpu"]["passes"] == (spatial > 0 ? 10 : compensated ? 4 : 3));
    CHECK(mean_of(one.image) > 0.0);
    CHECK(one.image.rgb == split.image.rgb);
  }
}

TEST_CASE("ris on the GPU: candidates beyond the software driver's loop limit are refused with a message") {
  // Under llvmpipe's loop budget a sample's M candidates cannot be split over dispatches; a
  // silently shortened loop would bias the image, so the backend refuses, naming the flag.
  const fixture& f = shared_fixture();
  for (const int spatial : {0, 2}) {
    options o = f.o;
    o.meth = method::ris;
    o.candidates = 60000;
    o.vpls = 1;
    o.spatial = spatial;
    render_settings es = settings_of(f, o);
    es.loop_budget = loop_budget_choice::always;
    stage_timer t;
    INFO("--spatial " << spatial);
    CHECK_THROWS_WITH(render_gpu(f.b, es, t), Catch::Contains("--candidates 60000") &&
                                                  Catch::Contains("exceed the software GL driver's loop limit"));
  }
}

// The clamp's compensation in estimate_ris.comp: without reuse its directions are units after the
// samples (split like them), with reuse the last round adds all of it. The GPU image is the CPU's
// and the term (image on - image off) is the CPU's: the same directions from the same stream, so
// the image sums agree within 1e-3 relative. dmin is 5 % of the diagonal so the term is large
// enough to tell a wrong one (at the default it is ~1e-4 of a 24x16 image).
TEST_CASE("ris on the GPU: the clamp compensation is the CPU's, with and without reuse") {
  const fixture& f = shared_fixture();
  for (int spatial : {0, 3}) {
    options o = f.o;
    o.meth = method::ris;
    o.candidate_source = ris_source_choice::global;
    o.spatial = spatial;
    o.candidates = 8;
    o.vpls = 3;
    render_settings off = settings_of(f, o);
    off.dmin *= 5.0f;
    render_settings on = off;
    on.clamp_compensation = clamp_compensation_choice::on;
    REQUIRE(uses_clamp_compensation(on));
    const image_rgb c_on = cpu_image(f, on), g_on = gpu_image(f, on);
    const image_rgb c_off = cpu_image(f, off), g_off = gpu_image(f, off);
    const double term_cpu = mean_of(c_on) - mean_of(c_off), term_gpu = mean_of(g_on) - mean_of(g_off);
    const double within = agreeing(c_on, g_on);
    std::printf("ris --spatial %d --clamp-compensation on: %.1f %% of pixels within %g; the term cpu %.6g gpu %.6g "
                "(%.3g of the clamped image)\n",
                spatial, 100.0 * within, rel_bound, term_cpu, term_gpu, term_cpu / std::max(mean_of(c_off), 1e-30));
    INFO("--spatial " << spatial);
    CHECK(finite_non_negative(g_on));
    CHECK(term_cpu > 1e-3 * mean_of(c_off));  // the clamp is active near the box's junctions
    CHECK(std::abs(term_gpu - term_cpu) <= 1e-3 * std::abs(term_cpu));
    CHECK(within >= required_fraction);
  }
}

TEST_CASE("GPU backend: ris with tile candidates is refused with a message, not rendered with flux's") {
  const fixture& f = shared_fixture();
  options o = f.o;
  o.meth = method::ris;
  o.candidate_source = ris_source_choice::tiles;
  const render_settings es = settings_of(f, o);
  stage_timer t;
  CHECK_THROWS_WITH(render_gpu(f.b, es, t), Catch::Contains("tiles is for --method ris-mis"));
}
