// SPDX-License-Identifier: MIT
// --method ris-mis on the GPU backend (examples/vplrender/shaders/estimate_ris_mis.comp) against the
// library on the CPU: the image of vplkit::estimate_ris_mis per pixel over the same frame, with the
// CPU backend's distributions (build_distributions_cpu, the candidate source's; per region for
// local), tracer and visibility, and its per-pixel stream and finish (cpu_ris_mis_image below, the
// loop the CPU backend runs for ris-mis as it runs estimate_mis for mis); the steps split over
// dispatches give the image of one dispatch; with spatial reuse (--spatial K, rounds of a candidate
// and a reuse dispatch) the image of the CPU backend's rounds (render/cpu/ris_render.hpp); the
// refusal of candidates beyond the loop limit; and the image mean of ris-mis against mis's, which
// estimate the same unclamped integral.
//
// The bound, as renderer_gpu_parity_ris_test's: the GPU builds its candidate sources' weights and
// CDFs itself (float neighbours of the CPU's values) and traces its gathering directions through
// its own sin/cos, so a selection number or a ray at a tie may go the other way in a few pixels:
// >= 97 % of the pixels within 2e-4 relative, every pixel finite and non-negative.
#include "renderer_gl_fixture.hpp"

#include "cli/render_options.hpp"
#include "render/cpu/cpu_backend.hpp"
#include "render/cpu/cpu_builders.hpp"
#include "render/cpu/cpu_frame.hpp"
#include "render/cpu/cpu_visibility.hpp"
#include "render/gpu/gpu_backend.hpp"

#include <vplkit/builders/local_weights.hpp>
#include <vplkit/estimators/ris_mis_estimator.hpp>
#include <vplkit/estimators/vpl_sum.hpp>
#include <vplkit/sampling/rng.hpp>
#include <vplkit/vpl/direct_light.hpp>

#include <catch2/catch.hpp>

#include <glm/common.hpp>
#include <nlohmann/json.hpp>

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
  render_settings es = make_render_settings(o, f.p.s);
  es.threads = 2;
  return es;
}

image_rgb gpu_image(const fixture& f, const render_settings& es) {
  stage_timer t;
  return render_gpu(f.b, es, t).image;
}

// ris-mis on the CPU: per pixel vplkit::estimate_ris_mis from make_counter_rng(seed, pixel), the
// candidate source's distribution (the pixel's region's for local), the direct light with
// --direct, clamped at 0 and made finite, as render_cpu finishes every pixel.
image_rgb cpu_ris_mis_image(const fixture& f, const render_settings& s) {
  const cpu_frame fr = open_cpu_frame(f.b, s);
  stage_timer timer;
  nlohmann::json det;
  const cpu_distributions built = build_distributions_cpu(f.b, s, timer, {}, det);
  REQUIRE(!built.dists.empty());
  const cpu_visibility visibility = make_cpu_visibility(f.b, s.visibility);
  const cpu_tracer tracer = make_cpu_tracer(f.b, s.visibility, s.lit_test);
  const float tol = gathering_depth_tolerance(s, f.b.grid.occupancy().view());
  const vplkit::vpl_mode vmode = library_vpl_mode(s.vpl_mode);
  const bool per_region = s.ris_source == ris_source_choice::local && built.dists.size() > 1;
  const vplkit::image_regions regions(fr.W, fr.H, s.regions_x, s.regions_y);
  image_rgb out(fr.W, fr.H);
  for (int p = 0; p < fr.W * fr.H; ++p) {
    const vplkit::gather_point<float> gp = fr.g.at(p);
    glm::vec3 c(0.0f);
    if (vplkit::gather_point_valid(gp)) {
      const auto& dist = built.dists[per_region ? std::size_t(regions.region_of_pixel(p % fr.W, p / fr.W)) : 0];
      vplkit::counter_rng rng = vplkit::make_counter_rng(s.seed, static_cast<std::uint32_t>(p));
      c = vplkit::estimate_ris_mis(gp, fr.view, dist, rng, s.dirs, s.vpls, s.ris_candidates, tracer, visibility, tol,
                                   vmode);
      if (s.direct) c += vplkit::direct_light(gp, fr.view);
      c = vplkit::estimator_finite_or_zero(glm::max(c, glm::vec3(0.0f)));
    }
    float* o = out.at(p % fr.W, p / fr.W);
    o[0] = c.x;
    o[1] = c.y;
    o[2] = c.z;
  }
  return out;
}

bool finite_non_negative(const image_rgb& a) {
  for (float v : a.rgb)
    if (!std::isfinite(v) || v < 0.0f) return false;
  return true;
}

double mean_of(const image_rgb& a) {
  double s = 0.0;
  for (float v : a.rgb) s += v;
  return s / double(std::max<std::size_t>(1, a.rgb.size()));
}

// The fraction of pixels whose channels agree within rel_bound (plus a floor of 1e-6 of the mean).
double agreeing(const image_rgb& c, const image_rgb& g) {
  const double mean = mean_of(c);
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

}  // namespace

TEST_CASE("ris-mis: the GPU image equals estimate_ris_mis's on the CPU for every candidate source") {
  const fixture& f = shared_fixture();
  struct run {
    ris_source_choice source;
    int candidates, vpls, dirs;
    vpl_mode_choice mode;
    bool direct;
  };
  const run runs[] = {{ris_source_choice::global, 8, 3, 4, vpl_mode_choice::patch, false},
                      {ris_source_choice::local, 8, 3, 4, vpl_mode_choice::patch, false},
                      {ris_source_choice::gbg, 8, 3, 4, vpl_mode_choice::patch, true},
                      {ris_source_choice::flux, 8, 3, 4, vpl_mode_choice::patch, false},
                      {ris_source_choice::flux, 1, 4, 2, vpl_mode_choice::point, false},
                      {ris_source_choice::flux, 4, 2, 0, vpl_mode_choice::point, false},  // no gathering
                      {ris_source_choice::global, 4, 0, 3, vpl_mode_choice::patch, false}};  // no RIS
  for (const run& r : runs) {
    options o = f.o;
    o.meth = method::ris_mis;
    o.candidate_pool = 0;  // each candidate its own draw (the pool: renderer_gpu_parity_ris_pool_test)
    o.candidate_source = r.source;
    o.candidates = r.candidates;
    o.vpl_mode = r.mode;
    o.vpls = r.vpls;
    o.dirs = r.dirs;
    o.regions = 2;
    o.direct = r.direct;
    const render_settings es = settings_of(f, o);
    const image_rgb c = cpu_ris_mis_image(f, es), g = gpu_image(f, es);
    const double within = agreeing(c, g);
    std::printf("ris-mis %-6s --candidates %d --vpls %d --dirs %d --vpl-mode %s%s: %.1f %% of pixels within %g, means "
                "cpu %.6f gpu %.6f\n",
                to_string(r.source), r.candidates, r.vpls, r.dirs, to_string(r.mode), r.direct ? " --direct" : "",
                100.0 * within, rel_bound, mean_of(c), mean_of(g));
    INFO(to_string(r.source) << " --candidates " << r.candidates << " --vpls " << r.vpls << " --dirs " << r.dirs);
    CHECK(finite_non_negative(c));
    CHECK(finite_non_negative(g));
    CHECK(mean_of(g) > 0.0);
    CHECK(within >= required_fraction);
    // The CPU backend (render/cpu/ris_render.hpp) renders the same image as the loop above.
    stage_timer tc;
    CHECK(render_cpu(f.b, es, tc).image.rgb == c.rgb);
  }
}

TEST_CASE("ris-mis on the GPU: the image mean agrees with mis's (the same unclamped integral)") {
  // Both weigh cosine gathering against VPL sampling from the GBG CDF with estimate_mis's balance
  // weights; ris-mis's VPL samples are RIS samples instead. Patch VPLs: both strategies sample one
  // integral (docs/math.md section 11). The image means of 6 seeds each (32 samples of each strategy
  // per pixel) agree within 4 standard errors of their difference plus 0.5 %, so a bias of a few
  // percent (a wrong weight, a missing 1 / n2, W without its 1 / M) fails while the noise does not.
  const fixture& f = shared_fixture();
  double sum[2] = {0.0, 0.0}, sum2[2] = {0.0, 0.0};
  const int seeds = 6;
  for (int seed = 1; seed <= seeds; ++seed)
    for (int k = 0; k < 2; ++k) {
      options o = f.o;
      o.meth = k == 0 ? method::mis : method::ris_mis;
      o.candidate_source = ris_source_choice::gbg;
      o.vpl_mode = vpl_mode_choice::patch;
      o.candidates = 8;
      o.vpls = 32;
      o.dirs = 32;
      o.eps = 0.1;
      o.seed = static_cast<std::uint32_t>(seed);
      const double m = mean_of(gpu_image(f, settings_of(f, o)));
      sum[k] += m;
      sum2[k] += m * m;
    }
  double mean[2], var[2];
  for (int k = 0; k < 2; ++k) {
    mean[k] = sum[k] / seeds;
    var[k] = std::max(0.0, (sum2[k] - seeds * mean[k] * mean[k]) / (seeds - 1)) / seeds;
  }
  REQUIRE(mean[0] > 0.0);
  const double ratio = mean[1] / mean[0];
  const double se = std::sqrt(var[0] + var[1]) / mean[0];
  std::printf("ris-mis vs mis on the GPU: image mean ratio %.4f, standard error %.4f\n", ratio, se);
  CHECK(std::abs(ratio - 1.0) <= 4.0 * se + 0.005);
}

TEST_CASE("ris-mis on the GPU: the steps split over dispatches give the image of one dispatch") {
  // A step (one RIS sample and one direction) is the unit (VR_SPLIT 1: sum and stream in the
  // state buffer between dispatches): max(5, 3) = 5 steps at 2 per dispatch are 3 dispatches.
  const fixture& f = shared_fixture();
  options o = f.o;
  o.meth = method::ris_mis;
  o.candidates = 4;
  o.vpls = 5;
  o.dirs = 3;
  render_settings es = settings_of(f, o);
  es.loop_budget = loop_budget_choice::never;
  stage_timer t1, t2;
  const render_result one = render_gpu(f.b, es, t1);
  es.loop_budget = loop_budget_choice::always;
  es.max_units_per_pass = 2;
  const render_result split = render_gpu(f.b, es, t2);
  CHECK(one.details["gpu"]["passes"] == 1);
  CHECK(split.details["gpu"]["passes"] == 3);
  CHECK(split.details["gpu"]["kernel"] == "examples/vplrender/shaders/estimate_ris_mis.comp");
  CHECK(split.details["ris"]["dirs"] == 3);
  CHECK(!split.details.contains("clamp_compensation_dirs"));  // unclamped: nothing to compensate
  CHECK(mean_of(one.image) > 0.0);
  CHECK(one.image.rgb == split.image.rgb);
}

TEST_CASE("ris-mis with spatial reuse: the GPU image equals the CPU backend's for every candidate source") {
  // Rounds of a candidate and a reuse dispatch (estimate_ris_mis.comp's VR_RIS_PASS) against
  // render/cpu/ris_render.hpp's rounds: the same streams, neighbours, targets (each pixel's own
  // distribution: per region for local) and gathering directions.
  const fixture& f = shared_fixture();
  struct run {
    ris_source_choice source;
    int spatial, candidates, vpls, dirs;
    vpl_mode_choice mode;
  };
  // gbg's mixture is drawn as global's (one mixture for every pixel): global stands for both, to
  // keep the number of kernel variants (each compiled on llvmpipe) down.
  const run runs[] = {{ris_source_choice::global, 3, 8, 3, 4, vpl_mode_choice::patch},
                      {ris_source_choice::local, 3, 8, 3, 4, vpl_mode_choice::patch},  // a pmf per region
                      {ris_source_choice::flux, 3, 8, 4, 2, vpl_mode_choice::patch},  // more RIS rounds than dirs
                      {ris_source_choice::flux, 2, 1, 2, 0, vpl_mode_choice::point}};  // no gathering
  bool first = true;
  for (const run& r : runs) {
    options o = f.o;
    o.meth = method::ris_mis;
    o.candidate_pool = 0;  // each candidate its own draw (the pool: renderer_gpu_parity_ris_pool_test)
    o.candidate_source = r.source;
    o.spatial = r.spatial;
    o.candidates = r.candidates;
    o.vpl_mode = r.mode;
    o.vpls = r.vpls;
    o.dirs = r.dirs;
    o.regions = 2;
    const render_settings es = settings_of(f, o);
    stage_timer tc, tg;
    const render_result c = render_cpu(f.b, es, tc), g = render_gpu(f.b, es, tg);
    const double within = agreeing(c.image, g.image);
    std::printf("ris-mis %-6s --spatial %d --candidates %d --vpls %d --dirs %d --vpl-mode %s: %.1f %% of pixels "
                "within %g, means cpu %.6f gpu %.6f\n",
                to_string(r.source), r.spatial, r.candidates, r.vpls, r.dirs, to_string(r.mode), 100.0 * within,
                rel_bound, mean_of(c.image), mean_of(g.image));
    INFO(to_string(r.source) << " --spatial " << r.spatial << " --vpls " << r.vpls << " --dirs " << r.dirs);
    CHECK(finite_non_negative(c.image));
    CHECK(finite_non_negative(g.image));
    CHECK(mean_of(g.image) > 0.0);
    CHECK(within >= required_fraction);
    // Reuse changes the image (the check above compares two reusing renders).
    if (first) {
      options o0 = o;
      o0.spatial = 0;
      stage_timer t0;
      CHECK(render_gpu(f.b, settings_of(f, o0), t0).image.rgb != g.image.rgb);
      first = false;
    }
    const int rounds = std::max(r.vpls, r.dirs);
    CHECK(g.details["gpu"]["passes"] == 2 * rounds);
    CHECK(g.details["ris"]["spatial"] == r.spatial);
    CHECK(g.details["ris"]["reuse_mis"] == "pairwise");
    CHECK(g.details["ris"]["mis"] == "balance");
  }
}

TEST_CASE("ris-mis on the GPU: candidates beyond the software driver's loop limit are refused") {
  const fixture& f = shared_fixture();
  options o = f.o;
  o.meth = method::ris_mis;
  stage_timer t;
  // Under llvmpipe's loop budget a step's M candidates cannot be split over dispatches, with or
  // without reuse.
  for (const int spatial : {0, 2}) {
    o.spatial = spatial;
    o.candidates = 60000;
    o.vpls = 1;
    render_settings es = settings_of(f, o);
    es.loop_budget = loop_budget_choice::always;
    INFO("spatial " << spatial);
    CHECK_THROWS_WITH(render_gpu(f.b, es, t), Catch::Contains("--method ris-mis") &&
                                                  Catch::Contains("--candidates 60000") &&
                                                  Catch::Contains("exceed the software GL driver's loop limit"));
  }
}
