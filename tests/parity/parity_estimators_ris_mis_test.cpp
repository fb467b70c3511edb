// SPDX-License-Identifier: MIT
// CPU/GPU parity of glsl/vplkit/estimators/ris_mis_estimator.glsl (and mis_estimator.glsl's
// vplkit_mis_vpl_unshadowed) against include/vplkit/estimators/ris_mis_estimator.hpp, T = float, on
// the synthetic room of tests/support/synthetic_scene.hpp through parity_ris_mis_support.hpp
// (DPRSM R = 32, 32^3 voxels, a 24 x 24 G-buffer, voxel visibility and the voxel tracer on both
// sides), point and patch VPLs: h without visibility (ris_mis_unshadowed), one candidate's weight,
// a reservoir (kept sample, weight_sum, confidence) and its shade, and the whole estimate_ris_mis
// per gather point, with its range form, and the spatial reuse (ris_mis_spatial_reuse.glsl) over the
// G-buffer with pairwise and balance MIS and a distribution per pixel. Hard cases: n_dirs = 0,
// n_ris = 0, n_candidates = 0, negative counts, candidates whose targets are all 0 (a denormal pmf, an index outside the view),
// one texel for every candidate, patch points moved to the texel centre (h = 0 when n1 > 0),
// gather points on a VPL and next to one, background and NaN points.
//
// What must be exact: the random-number streams (the counter after every call), the candidates'
// texels and jitters, the confidences, and, where no decision lies at a tie, the kept samples, the
// visibility of the kept samples and the gathering rays' texels. The decisions that may flip on a
// GPU (and under the [fma] reference): a reservoir's u S < w where a weight carries the GPU's
// rounding (checked to be a tie: its margin within the weights' error bound); a cosine at 0 or a
// patch point's hidden test; a voxel march or a gathering ray's DDA at a tie (the ray's direction
// goes through the GPU's sin/cos). The estimate test compares a fingerprint of every decision of a
// gather point's steps (kept texels and jitters, their visibility, the rays' texels and lit tests,
// computed on both sides with the same functions) and excludes, counts and bounds the points where
// it differs. Values are compared within per-item forward error bounds (parity_vpl_error_bound.hpp):
// h is conditioned like the VPL contribution it is made of (its MIS weight only damps the
// conditioning: d ln h = (1 - w1)(d ln cos1 + d ln cos2) - w2 d ln d2^2), on top of a base for the
// float chain (the reflected radiance, p2's area and division, the balance heuristic's 16 ulps).
#include "parity_ris_mis_support.hpp"
#include "parity_vpl_error_bound.hpp"

#include <gpu_precision.hpp>

#include <vplkit/builders/flux_weights.hpp>
#include <vplkit/builders/gather_subset.hpp>
#include <vplkit/builders/global_weights.hpp>
#include <vplkit/distribution/weighted_reservoir.hpp>
#include <vplkit/estimators/mis_estimator.hpp>
#include <vplkit/estimators/ris_mis_estimator.hpp>
#include <vplkit/estimators/ris_mis_spatial_reuse.hpp>
#include <vplkit/estimators/ris_params.h>
#include <vplkit/visibility/visibility_callables.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <iostream>
#include <string>
#include <vector>

// Distribution 0 of parity_ris_mis_support.hpp: global weights from 64 gather points plus a flux floor.
std::vector<float> vplkit::parity::rismis::source_weights() {
  const auto& f = fixture();
  const auto gb = f.gbuffer.view();
  const auto view = f.view();
  const auto subset = vplkit::stratified_gather_subset(gb, vplkit::full_image_rect(gb), 64, 3u);
  std::vector<float> w = vplkit::build_global_weights(gb, subset, view, 0.05f);
  const std::vector<float> flux = vplkit::build_flux_weights(view);
  for (std::size_t t = 0; t < w.size(); ++t) w[t] += 0.01f * flux[t];
  return w;
}

namespace {

using namespace vplkit::parity::est;
using namespace vplkit::parity::rismis;
using vplkit::parity::compare_exact;
using vplkit::parity::compare_floats;
using vplkit::parity::input;
using vplkit::parity::within_ulps;

const std::string hooks =
    std::string(distribution_hooks_glsl) + "#include \"vplkit/estimators/ris_mis_estimator.glsl\"\n" + out4_glsl;

// A kernel of the prelude, the hooks and `head`, running `body` for i < items (count outputs).
std::vector<out4> run(const std::string& head, const std::string& body, std::size_t items, std::size_t count,
                      const scene_params& p, const std::vector<named_point>& pts, const distribution_ref& dist,
                      std::vector<vplkit::parity::ssbo> extra, const std::string& name) {
  vplkit::parity::kernel_call call =
      ris_kernel(name, hooks, head, body, "RIS_MIS_ITEMS", p, pts, dist, std::move(extra));
  call.defines = "#define RIS_MIS_ITEMS " + std::to_string(items) + "u\n";
  return vplkit::parity::run_compute<out4>(call, count);
}

// The relative forward error bound of h for the sample s at gp (without base_rel): the VPL
// contribution's conditioning at its point (cosines near 0, a patch point's position error over
// d2), and a patch point's area A(uv) through d1 and cos(alpha). 0 where h is 0 on the C++ side
// for a reason other than a cosine (then the value is compared exactly).
double h_conditioning(const vplkit::gather_point<float>& gp, const vplkit::dprsm_view<float>& view,
                      const vplkit::ris_sample<float>& s, vplkit::vpl_mode mode, float tol) {
  if (s.texel < 0 || s.texel >= view.texel_count() || !vplkit::gather_point_valid(gp)) return 0.0;
  vplkit::vpl<float> v = view.vpl_at(s.texel);
  double dy = 0.0, area = 0.0;
  if (mode == vplkit::vpl_mode::patch) {
    const auto p = vplkit::dprsm_patch_vpl(view, s.texel, s.xi, tol);
    v = p.point;
    dy = vplkit::parity::patch_point_error(view, s.texel, p);
    if (p.distance > 0.0f) area = 2.0 * dy / double(p.distance);
  }
  const vplkit::vec3<float> L = vplkit::vpl_contribution(gp, v, 0.0f);
  const double lum = vplkit::luminance(vplkit::vec3<double>(L));
  const double err = vplkit::luminance(vplkit::vec3<double>(vplkit::parity::vpl_contribution_error(gp, v, dy, 0.0f)));
  if (!(lum > 0.0)) return err > 0.0 ? 1.0 : 0.0;  // a cosine at 0 on this side: a tie
  return std::min(1.0, err / lum) + area;
}

struct sample_item {
  std::int32_t point, texel;
  float xi_x, xi_y, pmf, n1, n2;
  std::int32_t mode;
};

const char* const item_head = R"(
struct sample_item { int point; int texel; float xi_x; float xi_y; float pmf; float n1; float n2; int mode; };
layout(std430, binding = 11) readonly buffer Items { sample_item items[]; };
)";

// The kept sample's visibility as ris_mis_shade queries it: 2 where h is 0 (no query).
const char* const kept_visible_glsl = R"(
uint kept_visible(vplkit_gather_point gp, vplkit_dprsm_view view, uint d, vplkit_ris_reservoir r,
                  vplkit_visibility vis, float n1, float n2, int mode, float tol) {
  if (!vplkit_gather_point_valid(gp) || !vplkit_ris_reservoir_has_sample(r) ||
      r.kept.texel >= vplkit_dprsm_view_texel_count(view)) return 2u;
  float pmf = vplkit_estimator_pmf(vplkit_estimator_distribution_pmf(d, uint(r.kept.texel)));
  vplkit_vpl v;
  vec3 h = vplkit_ris_mis_unshadowed(gp, view, r.kept, pmf, n1, n2, mode, tol, v);
  if (!(h.x > 0.0 || h.y > 0.0 || h.z > 0.0)) return 2u;
  return vplkit_visibility_test(vis, gp.position, gp.normal, v.position, v.normal) ? 1u : 0u;
}
)";

template <class Dist>
std::uint32_t kept_visible(const vplkit::gather_point<float>& gp, const vplkit::dprsm_view<float>& view, const Dist& d,
                           const vplkit::ris_reservoir<float>& r, float n1, float n2, vplkit::vpl_mode mode, float tol) {
  if (!vplkit::gather_point_valid(gp) || !vplkit::ris_reservoir_has_sample(r) || r.kept.texel >= view.texel_count())
    return 2u;
  const float pmf = vplkit::estimator_pmf(d.pmf(std::size_t(r.kept.texel)));
  vplkit::vpl<float> v;
  const auto h = vplkit::ris_mis_unshadowed(gp, view, r.kept, pmf, n1, n2, mode, tol, v);
  if (!(h.x > 0.0f || h.y > 0.0f || h.z > 0.0f)) return 2u;
  const vplkit::voxel_visibility<float> vis{fixture().grid.view()};
  return vis(gp.position, gp.normal, v.position, v.normal) ? 1u : 0u;
}

// Is the C++ voxel visibility of x -> y at a tie: does moving either end by 2^-18 of the grid's
// size (the GPU's patch point and march lie within a few ulps of the C++'s; this is 64 of them)
// along an axis change the answer? A flip there is two right answers, not a fault of either side.
float tie_distance() {
  const auto& g = fixture().grid.view();
  const v3f extent = g.bounds_max - g.bounds_min;
  return std::ldexp(std::max(extent.x, std::max(extent.y, extent.z)), -18);
}

bool visibility_at_tie(v3f x, v3f n_x, v3f y, v3f n_y) {
  const vplkit::voxel_visibility<float> vis{fixture().grid.view()};
  const float delta = tie_distance();
  const bool base = vis(x, n_x, y, n_y);
  for (int k = 0; k < 3; ++k)
    for (const float s : {-delta, delta}) {
      v3f e(0.0f);
      e[k] = s;
      if (vis(x + e, n_x, y, n_y) != base || vis(x, n_x, y + e, n_y) != base) return true;
    }
  return false;
}

// The kept sample's visibility at a tie (visibility_at_tie at its VPL).
template <class Dist>
bool kept_visibility_at_tie(const vplkit::gather_point<float>& gp, const vplkit::dprsm_view<float>& view, const Dist& d,
                            const vplkit::ris_reservoir<float>& r, float n1, float n2, vplkit::vpl_mode mode,
                            float tol) {
  if (!vplkit::gather_point_valid(gp) || !vplkit::ris_reservoir_has_sample(r) || r.kept.texel >= view.texel_count())
    return false;
  const float pmf = vplkit::estimator_pmf(d.pmf(std::size_t(r.kept.texel)));
  vplkit::vpl<float> v;
  (void)vplkit::ris_mis_unshadowed(gp, view, r.kept, pmf, n1, n2, mode, tol, v);
  return visibility_at_tie(gp.position, gp.normal, v.position, v.normal);
}

// Patch samples (texel, jitter) whose point dprsm_patch_vpl moves to the texel centre.
std::vector<vplkit::ris_sample<float>> at_centre_samples(float tol, std::size_t want) {
  const auto view = fixture().view();
  std::vector<vplkit::ris_sample<float>> out;
  const float xs[] = {0.01f, 0.2f, 0.5f, 0.8f, 0.99f};
  for (int t = 0; t < view.texel_count() && out.size() < want; ++t)
    for (float a : xs)
      for (float b : xs) {
        if (out.size() >= want) break;
        const vplkit::vec2<float> xi(a, b);
        const auto p = vplkit::dprsm_patch_vpl(view, t, xi, tol);
        if (p.at_centre && vplkit::vpl_has_flux(p.point)) out.push_back({t, xi});
      }
  return out;
}

}  // namespace

TEST_CASE("ris_mis_unshadowed: GPU vs C++ over gather points and samples, point and patch, every n1 and n2") {
  const scene_fixture& f = fixture();
  const auto view = f.view();
  const auto pts = gather_points();
  const float tol = window();
  const auto centre = at_centre_samples(tol, 12);
  REQUIRE(centre.size() >= 4);  // the scene has hidden patch points (the hard case is exercised)
  struct counts {
    float n1, n2;
  };
  const counts cs[] = {{8, 8}, {0, 4}, {16, 2}, {8, 0}, {0, 0}};
  const float us[] = {0.013f, 0.31f, 0.5f, 0.77f, 0.999f};
  const float xis[][2] = {{0.5f, 0.5f}, {0.03f, 0.97f}, {0.9f, 0.2f}};
  std::vector<sample_item> items;
  std::vector<vplkit::ris_sample<float>> samples;
  for (std::size_t i = 0; i < pts.size(); ++i)
    for (int mode : {0, 1})
      for (std::size_t k = 0; k < std::size(us); ++k) {
        const auto d = source().cdf.sample(us[k]);
        const counts c = cs[(i + k) % std::size(cs)];
        const float* xi = xis[(i + 2 * k) % std::size(xis)];
        items.push_back({std::int32_t(i), std::int32_t(d.index), xi[0], xi[1], d.pmf, c.n1, c.n2, mode});
      }
  // At-centre patch points with and without gathering; a pmf that is 0 or tiny; texels outside. (A
  // denormal pmf is outside the function's contract: the estimators pass estimator_pmf's, which is
  // 0 there; the candidate and estimate tests draw one.)
  std::size_t centre_begin = items.size();
  for (std::size_t i = 0; i < pts.size(); i += 4)
    for (const auto& s : centre)
      for (float n1 : {0.0f, 8.0f}) items.push_back({std::int32_t(i), s.texel, s.xi.x, s.xi.y, 1e-3f, n1, 4.0f, 1});
  const std::size_t centre_end = items.size();
  for (std::size_t i = 0; i < pts.size(); i += 7) {
    const std::int32_t t = items[i * 10].texel;
    items.push_back({std::int32_t(i), t, 0.5f, 0.5f, 0.0f, 8.0f, 8.0f, 0});
    items.push_back({std::int32_t(i), t, 0.5f, 0.5f, 1e-30f, 8.0f, 8.0f, 1});  // h tiny, but normal
    items.push_back({std::int32_t(i), view.texel_count(), 0.5f, 0.5f, 0.5f, 8.0f, 8.0f, 0});
    items.push_back({std::int32_t(i), -1, 0.5f, 0.5f, 0.5f, 8.0f, 8.0f, 1});
  }
  scene_params p = f.params();
  p.fp.y = tol;
  const auto gpu = run(item_head, R"(  sample_item it = items[i];
  vplkit_vpl v;
  vec3 h = vplkit_ris_mis_unshadowed(load_point(uint(it.point)), load_view(), vplkit_ris_sample(it.texel, vec2(it.xi_x, it.xi_y)),
                                     it.pmf, it.n1, it.n2, it.mode, fp.y, v);
  result[i] = out4(vec4(h, 0.0), vec4(v.position, 0.0), ivec4(vplkit_vpl_has_flux(v) ? 1 : 0, 0, 0, 0), uvec4(0u));
)", items.size(), items.size(), p, pts, {}, {input(11, items)}, "ris_mis_unshadowed.comp");
  std::vector<float> g, c;
  std::vector<double> rel;
  vplkit::parity::series<std::int32_t> flux;
  std::size_t centre_zero_with_gathering = 0, centre_lit_without = 0, centre_items = 0;
  for (std::size_t k = 0; k < items.size(); ++k) {
    const sample_item& it = items[k];
    const auto& gp = pts[std::size_t(it.point)].gp;
    const auto mode = it.mode == 1 ? vplkit::vpl_mode::patch : vplkit::vpl_mode::point;
    const vplkit::ris_sample<float> s{it.texel, {it.xi_x, it.xi_y}};
    vplkit::vpl<float> v;
    const auto h = vplkit::ris_mis_unshadowed(gp, view, s, it.pmf, it.n1, it.n2, mode, tol, v);
    const double r = base_rel + 2.0 * h_conditioning(gp, view, s, mode, tol);
    for (int ch = 0; ch < 3; ++ch) {
      g.push_back(gpu[k].a[ch]);
      c.push_back(h[ch]);
      rel.push_back(r);
    }
    flux.add(gpu[k].c.x, vplkit::vpl_has_flux(v) ? 1 : 0);
    if (k >= centre_begin && k < centre_end) {
      ++centre_items;
      if (it.n1 > 0.0f) centre_zero_with_gathering += h.x == 0.0f && h.y == 0.0f && h.z == 0.0f ? 1 : 0;
      else centre_lit_without += h.x > 0.0f ? 1 : 0;
    }
  }
  // The hard case: a point at the centre belongs to gathering when n1 > 0 (h = 0, on both sides:
  // compared above), to the VPL strategy alone when n1 = 0.
  CHECK(2 * centre_zero_with_gathering == centre_items);
  CHECK(centre_lit_without > 0);
  std::size_t flips = 0;
  CHECK(check_rel("ris_mis_unshadowed h", g, c, rel, flips) == 0);
  if (bit_exact_device()) CHECK(flips == 0);
  else CHECK(flips <= g.size() / 100);
  VPLKIT_CHECK_PARITY(compare_exact(flux, [&](std::size_t k) { return pts[std::size_t(items[k].point)].name; },
                                    "ris_mis_unshadowed: v has flux"));
}

namespace {

// The pass_facts (parity_ris_mis_support.hpp) of one ris_mis candidate pass from `dist`.
template <class Dist>
pass_facts candidate_pass(const vplkit::gather_point<float>& gp, const Dist& dist, int m, float n1, float n2,
                          vplkit::vpl_mode mode, float tol, vplkit::counter_rng rng) {
  const auto view = fixture().view();
  pass_facts out;
  if (!vplkit::gather_point_valid(gp) || m <= 0 || !(n2 > 0.0f)) return out;
  double sum = 0.0;
  for (int i = 0; i < m; ++i) {
    vplkit::ris_sample<float> s;
    float target;
    const double w = vplkit::ris_mis_candidate(gp, view, dist, rng, n1, n2, mode, tol, s, target);
    const double u = vplkit::rng_next_unit<float>(rng);
    if (s.texel >= 0 && h_conditioning(gp, view, s, mode, tol) >= 0.5) out.cosine_tie = true;
    if (!vplkit::reservoir_weight_usable(float(w))) continue;
    sum += w;
    out.margin = std::min(out.margin, std::abs(u * sum - w) / w);
    out.weight_rel = std::max(out.weight_rel, base_rel + 2.0 * h_conditioning(gp, view, s, mode, tol));
  }
  return out;
}

}  // namespace

TEST_CASE("ris_mis candidates, reservoirs and shade: GPU vs C++ (point and patch, M = 1, 8, 32, n1 = 0 and 8)") {
  const scene_fixture& f = fixture();
  const auto view = f.view();
  const auto pts = gather_points();
  const float tol = window();
  const std::string head = std::string(kept_visible_glsl);
  // ip.y = M, ip.z = vpl mode, ip.w = distribution; fp.x = n1, fp.y = window, fp.z = n2.
  const std::string body = R"(  vplkit_gather_point gp = load_point(i);
  vplkit_dprsm_view view = load_view();
  uint d = uint(ip.w);
  vplkit_counter_rng c = vplkit_make_counter_rng(0x817u, i);
  vplkit_ris_sample s;
  float target;
  float w = vplkit_ris_mis_candidate(gp, view, d, c, fp.x, fp.z, ip.z, fp.y, s, target);
  result[2u * i] = out4(vec4(w, target, s.xi), vec4(0.0), ivec4(s.texel, int(c.counter), 0, 0), uvec4(0u));
  vplkit_counter_rng rng = vplkit_make_counter_rng(0x815u, i);
  vplkit_ris_reservoir r = vplkit_ris_mis_resample(gp, view, d, rng, ip.y, fp.x, fp.z, ip.z, fp.y);
  vplkit_visibility vis = vplkit_make_voxel_visibility(load_grid());
  vec3 shade = vplkit_ris_mis_shade(gp, view, d, r, vis, fp.x, fp.z, ip.z, fp.y);
  result[2u * i + 1u] = out4(vec4(shade, r.weight_sum), vec4(r.kept.xi, r.target, r.confidence),
                             ivec4(r.kept.texel, int(rng.counter), 0, 0),
                             uvec4(kept_visible(gp, view, d, r, vis, fp.x, fp.z, ip.z, fp.y), 0u, 0u, 0u));
)";
  struct config {
    int m;
    float n1, n2;
    distribution_ref dist;
    const char* dist_name;
  };
  std::vector<config> configs;
  for (int m : {1, 8, 32}) configs.push_back({m, 8.0f, 8.0f, {}, "cdf"});
  configs.push_back({8, 0.0f, 4.0f, {}, "cdf"});
  configs.push_back({8, 8.0f, 0.0f, {}, "cdf"});  // n2 = 0: no candidates
  configs.push_back({0, 8.0f, 8.0f, {}, "cdf"});  // M = 0: no candidates
  configs.push_back({-3, 8.0f, 8.0f, {}, "cdf"});
  configs.push_back({8, 8.0f, 8.0f, fixed_case(1.0f, lit_texel()), "one lit texel, pmf 1"});
  configs.push_back({8, 8.0f, 8.0f, fixed_case(3e-39f, lit_texel()), "one lit texel, denormal pmf (all targets 0)"});
  configs.push_back({8, 8.0f, 8.0f, fixed_case(0.5f, view.texel_count()), "an index outside the view (all targets 0)"});
  std::size_t flipped = 0, compared = 0, vis_flips = 0;
  for (const vplkit::vpl_mode mode : {vplkit::vpl_mode::point, vplkit::vpl_mode::patch})
    for (const config& cfg : configs) {
      scene_params p = f.params();
      p.ip.y = cfg.m;
      p.ip.z = int(mode);
      p.ip.w = cfg.dist.id;
      p.fp.x = cfg.n1;
      p.fp.y = tol;
      p.fp.z = cfg.n2;
      const std::string what = std::string(mode == vplkit::vpl_mode::patch ? "patch" : "point") + ", M = " +
                               std::to_string(cfg.m) + ", n1 = " + std::to_string(int(cfg.n1)) + ", n2 = " +
                               std::to_string(int(cfg.n2)) + ", " + cfg.dist_name;
      const auto gpu = run(head, body, pts.size(), 2 * pts.size(), p, pts, cfg.dist, {}, "ris_mis_candidates.comp");
      vplkit::parity::series<std::int32_t> texel, counter, cand_texel, visible;
      vplkit::parity::series<float> xi, confidence;
      std::vector<float> wg, wc, tg, tc, sg, sc, vg, vc;
      std::vector<double> wr, tr, sr, vr;
      std::size_t any_sample = 0;
      for (std::size_t i = 0; i < pts.size(); ++i) {
        const auto& gp = pts[i].gp;
        // One candidate.
        vplkit::counter_rng c = vplkit::make_counter_rng(0x817u, std::uint32_t(i));
        vplkit::ris_sample<float> s;
        float target;
        const float w = vplkit::ris_mis_candidate(gp, view, cfg.dist, c, cfg.n1, cfg.n2, mode, tol, s, target);
        const out4& o1 = gpu[2 * i];
        counter.add(o1.c.y, std::int32_t(c.counter));
        cand_texel.add(o1.c.x, s.texel);
        xi.add(o1.a.z, s.xi.x);
        xi.add(o1.a.w, s.xi.y);
        const double cr = base_rel + 2.0 * h_conditioning(gp, view, s, mode, tol);
        wg.push_back(o1.a.x), wc.push_back(w), wr.push_back(cr);
        tg.push_back(o1.a.y), tc.push_back(target), tr.push_back(cr);
        // A reservoir and its shade.
        const vplkit::counter_rng start = vplkit::make_counter_rng(0x815u, std::uint32_t(i));
        vplkit::counter_rng rng = start;
        const auto r = vplkit::ris_mis_resample(gp, view, cfg.dist, rng, cfg.m, cfg.n1, cfg.n2, mode, tol);
        const vplkit::voxel_visibility<float> vis{f.grid.view()};
        const auto shade = vplkit::ris_mis_shade(gp, view, cfg.dist, r, vis, cfg.n1, cfg.n2, mode, tol);
        const out4& o = gpu[2 * i + 1];
        counter.add(o.c.y, std::int32_t(rng.counter));
        confidence.add(o.b.w, r.confidence);
        any_sample += vplkit::ris_reservoir_has_sample(r) ? 1 : 0;
        if (o.c.x != r.kept.texel || o.b.x != r.kept.xi.x || o.b.y != r.kept.xi.y) {
          ++flipped;
          const pass_facts pf = candidate_pass(gp, cfg.dist, cfg.m, cfg.n1, cfg.n2, mode, tol, start);
          INFO(what << ", " << pts[i].name << ": kept samples differ, smallest decision margin " << pf.margin
                    << ", weights' error bound " << pf.weight_rel << (pf.cosine_tie ? ", a cosine at a tie" : ""));
          CHECK((pf.margin <= 2.0 * pf.weight_rel || pf.cosine_tie));  // a tie
          continue;
        }
        ++compared;
        texel.add(o.c.x, r.kept.texel);
        const std::uint32_t vis_cpu = kept_visible(gp, view, cfg.dist, r, cfg.n1, cfg.n2, mode, tol);
        if (o.d[0] != vis_cpu) {
          ++vis_flips;  // a voxel march or a cosine at a tie: the shade differs by the whole value
          continue;
        }
        visible.add(std::int32_t(o.d[0]), std::int32_t(vis_cpu));
        const pass_facts pf = candidate_pass(gp, cfg.dist, cfg.m, cfg.n1, cfg.n2, mode, tol, start);
        // weight_sum: the mean of M weights (each within its bound) and M roundings of the sum.
        const double ws_rel = pf.weight_rel + double(std::max(cfg.m, 1)) * vplkit_test::spec::ulp_rel;
        vg.push_back(o.a.w), vc.push_back(r.weight_sum), vr.push_back(ws_rel);
        tg.push_back(o.b.z), tc.push_back(r.target), tr.push_back(base_rel + 2.0 * h_conditioning(gp, view, r.kept, mode, tol));
        // h W = h weight_sum / target: h and the target share the kept sample's error.
        const double h_rel = tr.back();
        for (int ch = 0; ch < 3; ++ch) {
          sg.push_back(o.a[ch]);
          sc.push_back(shade[ch]);
          sr.push_back(2.0 * h_rel + ws_rel);
        }
      }
      const auto describe = [&](std::size_t) { return what; };
      VPLKIT_CHECK_PARITY(compare_exact(counter, describe, "ris_mis " + what + ": stream counters"));
      VPLKIT_CHECK_PARITY(compare_exact(cand_texel, describe, "ris_mis " + what + ": candidate texels"));
      VPLKIT_CHECK_PARITY(compare_exact(texel, describe, "ris_mis " + what + ": kept texels"));
      VPLKIT_CHECK_PARITY(compare_exact(visible, describe, "ris_mis " + what + ": kept samples' visibility"));
      VPLKIT_CHECK_PARITY(compare_floats(xi, within_ulps(0), describe, "ris_mis " + what + ": jitter"));
      VPLKIT_CHECK_PARITY(compare_floats(confidence, within_ulps(0), describe, "ris_mis " + what + ": confidence"));
      std::size_t zf = 0;
      CHECK(check_rel("ris_mis " + what + ": candidate weight", wg, wc, wr, zf) == 0);
      CHECK(check_rel("ris_mis " + what + ": targets", tg, tc, tr, zf) == 0);
      CHECK(check_rel("ris_mis " + what + ": weight_sum", vg, vc, vr, zf) == 0);
      CHECK(check_rel("ris_mis " + what + ": shade h V W", sg, sc, sr, zf) == 0);
      if (bit_exact_device()) CHECK(zf == 0);
      // The hard cases: no sample without candidates, none when every target is 0; the CDF gives
      // samples at most points.
      const bool none = cfg.m <= 0 || !(cfg.n2 > 0.0f) || (cfg.dist.id == 1 && cfg.dist.fixed.p < 1.0f);
      if (none) CHECK(any_sample == 0);
      else if (cfg.dist.id == 1) CHECK(any_sample > 0);
      else CHECK(any_sample > pts.size() / 2);
    }
  std::cout << "  ris_mis: " << compared << " reservoirs compared, " << flipped << " with a kept sample that differs "
            << "(each at a tie), " << vis_flips << " with a kept sample's visibility that differs\n";
  CHECK(flipped <= compared / 100);
  if (bit_exact_device()) CHECK(vis_flips == 0);
  else CHECK(vis_flips <= compared / 100);
}

namespace {

// The fingerprint (parity_ris_mis_support.hpp) of estimate_ris_mis's steps: a RIS step is
// ris_mis_resample from distribution d.
const std::string fingerprint_ris_mis = fingerprint_glsl("uint d", R"(
      vplkit_ris_reservoir r = vplkit_ris_mis_resample(gp, view, d, rng, m, n1, n2, mode, tol);
      uint visible = kept_visible(gp, view, d, r, vis, n1, n2, mode, tol);)");

point_facts replay_point(const vplkit::gather_point<float>& gp, const distribution_ref& dist, vplkit::counter_rng rng,
                         int nd, int nr, int m, vplkit::vpl_mode mode, float tol) {
  const auto view = fixture().view();
  return replay_steps(gp, rng, nd, nr, m, mode, tol, [&](vplkit::counter_rng& step_rng, float n1, float n2) {
    const pass_facts pf = candidate_pass(gp, dist, m, n1, n2, mode, tol, step_rng);
    const auto r = vplkit::ris_mis_resample(gp, view, dist, step_rng, m, n1, n2, mode, tol);
    return ris_step_facts{r, kept_visible(gp, view, dist, r, n1, n2, mode, tol), pf.weight_rel};
  });
}

}  // namespace

TEST_CASE("estimate_ris_mis: GPU vs C++ per gather point, point and patch, hard counts, range form") {
  const scene_fixture& f = fixture();
  const auto view = f.view();
  const auto pts = gather_points();
  const float tol = window();
  const std::string head = std::string(kept_visible_glsl) + fingerprint_ris_mis;
  // ip.y = M, ip.z = vpl mode, ip.w = distribution; ip2 = n_dirs, n_ris, and the range splits a, b.
  const std::string body = R"(  vplkit_gather_point gp = load_point(i);
  vplkit_dprsm_view view = load_view();
  uint d = uint(ip.w);
  vplkit_voxel_tracer tracer = vplkit_make_voxel_tracer(load_grid());
  vplkit_visibility vis = vplkit_make_voxel_visibility(load_grid());
  int nd = ip2.x, nr = ip2.y, m = ip.y;
  vplkit_counter_rng rng = vplkit_make_counter_rng(0x5eedu, i);
  uint h = fingerprint(gp, view, d, rng, nd, nr, m, tracer, vis, fp.y, ip.z);
  vec3 e = vplkit_estimate_ris_mis(gp, view, d, rng, nd, nr, m, tracer, vis, fp.y, ip.z);
  vplkit_estimator_state s = vplkit_make_estimator_state(vplkit_make_counter_rng(0x5eedu, i));
  int n = max(max(nd, 0), m > 0 ? max(nr, 0) : 0);
  int a = min(ip2.z, n), b = min(ip2.w, n);
  vplkit_estimate_ris_mis_range(gp, view, d, s, 0, a, nd, nr, m, tracer, vis, fp.y, ip.z);
  vplkit_estimate_ris_mis_range(gp, view, d, s, a, b, nd, nr, m, tracer, vis, fp.y, ip.z);
  vplkit_estimate_ris_mis_range(gp, view, d, s, b, n, nd, nr, m, tracer, vis, fp.y, ip.z);
  vec3 e2 = vplkit_estimate_ris_mis_finish(s);
  // n_ris = 0 (or M = 0) is estimate_mis's gathering with n_vpls = 0, number for number.
  vec3 e3 = vec3(0.0);
  vplkit_counter_rng r3 = vplkit_make_counter_rng(0x5eedu, i);
  if (nr <= 0 || m <= 0) e3 = vplkit_estimate_mis(gp, view, d, r3, nd, 0, tracer, vis, fp.y, vplkit_mis_solid_angle, ip.z);
  result[i] = out4(vec4(e, 0.0), vec4(e2, 0.0), ivec4(int(rng.counter), int(s.rng.counter), int(r3.counter), 0),
                   uvec4(h, floatBitsToUint(e3)));
)";
  struct config {
    int nd, nr, m;
    distribution_ref dist;
    const char* dist_name;
  };
  const std::vector<config> configs = {
      {8, 8, 8, {}, "cdf"},
      {4, 12, 4, {}, "cdf"},
      {0, 8, 8, {}, "cdf"},  // n_dirs = 0: RIS of the unclamped contribution
      {8, 0, 8, {}, "cdf"},  // n_ris = 0: gathering alone
      {8, 8, 0, {}, "cdf"},  // n_candidates = 0: n_ris counts as 0
      {0, 0, 8, {}, "cdf"},
      {-1, 5, 4, {}, "cdf"},
      {6, -2, 4, {}, "cdf"},
      {8, 8, 8, fixed_case(3e-39f, lit_texel()), "one lit texel, denormal pmf (all targets 0)"},
      {8, 8, 8, fixed_case(1.0f, lit_texel()), "one lit texel, pmf 1"}};
  std::size_t flipped_total = 0, compared_total = 0;
  for (const vplkit::vpl_mode mode : {vplkit::vpl_mode::point, vplkit::vpl_mode::patch})
    for (const config& cfg : configs) {
      scene_params p = f.params();
      p.ip.y = cfg.m;
      p.ip.z = int(mode);
      p.ip.w = cfg.dist.id;
      p.fp.y = tol;
      p.ip2 = {cfg.nd, cfg.nr, 3, 5};
      const std::string what = std::string(mode == vplkit::vpl_mode::patch ? "patch" : "point") + ", n_dirs " +
                               std::to_string(cfg.nd) + ", n_ris " + std::to_string(cfg.nr) + ", M " +
                               std::to_string(cfg.m) + ", " + cfg.dist_name;
      const auto gpu = run(head, body, pts.size(), pts.size(), p, pts, cfg.dist, {}, "estimate_ris_mis.comp");
      vplkit::parity::series<std::int32_t> counter;
      std::vector<float> g, c;
      std::vector<double> rel;
      std::size_t flipped = 0, range_differs = 0, mis_differs = 0, non_zero = 0, bad = 0;
      for (std::size_t i = 0; i < pts.size(); ++i) {
        const auto& gp = pts[i].gp;
        const out4& o = gpu[i];
        vplkit::counter_rng rng = vplkit::make_counter_rng(0x5eedu, std::uint32_t(i));
        const point_facts pf = replay_point(gp, cfg.dist, rng, cfg.nd, cfg.nr, cfg.m, mode, tol);
        const vplkit::voxel_tracer<float> tracer{f.grid.view()};
        const vplkit::voxel_visibility<float> vis{f.grid.view()};
        const auto e = vplkit::estimate_ris_mis(gp, view, cfg.dist, rng, cfg.nd, cfg.nr, cfg.m, tracer, vis, tol, mode);
        counter.add(o.c.x, std::int32_t(rng.counter));
        counter.add(o.c.y, std::int32_t(rng.counter));
        // The range form and (n_ris = 0) estimate_mis are the same arithmetic on one device: bit for bit.
        for (int ch = 0; ch < 3; ++ch) range_differs += bits(o.a[ch]) != bits(o.b[ch]) ? 1 : 0;
        if (cfg.nr <= 0 || cfg.m <= 0) {
          counter.add(o.c.z, std::int32_t(rng.counter));
          for (int ch = 0; ch < 3; ++ch) mis_differs += o.d[1 + ch] != bits(o.a[ch]) ? 1 : 0;
        }
        for (int ch = 0; ch < 3; ++ch) bad += std::isfinite(o.a[ch]) && o.a[ch] >= 0.0f ? 0 : 1;
        if (o.d[0] != pf.fingerprint) {
          ++flipped;
          continue;
        }
        non_zero += e.x > 0.0f ? 1 : 0;
        for (int ch = 0; ch < 3; ++ch) {
          g.push_back(o.a[ch]);
          c.push_back(e[ch]);
          rel.push_back(base_rel + pf.rel);
        }
      }
      const auto describe = [&](std::size_t k) { return pts[k / 2].name; };
      VPLKIT_CHECK_PARITY(compare_exact(counter, describe, "estimate_ris_mis " + what + ": rng counters"));
      std::size_t zf = 0;
      CHECK(check_rel("estimate_ris_mis " + what + ": estimate", g, c, rel, zf) == 0);
      if (bit_exact_device()) CHECK(zf == 0);
      INFO(what);
      CHECK(range_differs == 0);
      CHECK(mis_differs == 0);
      CHECK(bad == 0);
      std::cout << "  estimate_ris_mis " << what << ": " << pts.size() << " gather points, " << flipped
                << " with a decision that differs (excluded), " << non_zero << " non-zero estimates compared\n";
      CHECK(flipped <= std::max<std::size_t>(2, pts.size() / 50));
      const bool empty = (std::max(cfg.nd, 0) == 0 && (cfg.nr <= 0 || cfg.m <= 0));
      if (empty) CHECK(non_zero == 0);
      else CHECK(non_zero > pts.size() / 4);
      flipped_total += flipped;
      compared_total += pts.size() - flipped;
    }
  std::cout << "  estimate_ris_mis: " << compared_total << " estimates compared, " << flipped_total << " flipped\n";
}

TEST_CASE("visibility_at_tie: true where the answer changes within its distance, false away from it") {
  // The judge of the spatial reuse test's visibility flips, checked on the C++ alone: between a
  // visible and a hidden DPRSM texel seen from one gather point, bisection finds where the answer
  // changes; there the judge must say "tie", and at most texel pairs it must not.
  const auto view = fixture().view();
  const vplkit::voxel_visibility<float> vis{fixture().grid.view()};
  const auto pts = gather_points();
  std::size_t pairs = 0, ties_found = 0, plain = 0, plain_ties = 0;
  for (std::size_t i = 0; i < pts.size() && pairs < 40; i += 3) {
    const auto& gp = pts[i].gp;
    if (!vplkit::gather_point_valid(gp)) continue;
    int seen = -1, hidden = -1;
    for (int t = 0; t < view.texel_count() && (seen < 0 || hidden < 0); t += 7) {
      if (!(glm::dot(view.normal[t], view.normal[t]) > 0.0f)) continue;
      const bool v = vis(gp.position, gp.normal, view.position[t], view.normal[t]);
      ++plain;
      plain_ties += visibility_at_tie(gp.position, gp.normal, view.position[t], view.normal[t]) ? 1 : 0;
      (v ? seen : hidden) = t;
    }
    if (seen < 0 || hidden < 0) continue;
    ++pairs;
    v3f a = view.position[seen], b = view.position[hidden];  // vis(a) true, vis(b) false
    const v3f n = view.normal[seen];
    for (int k = 0; k < 60 && glm::length(b - a) > tie_distance() / 4; ++k) {
      const v3f m = (a + b) * 0.5f;
      (vis(gp.position, gp.normal, m, n) ? a : b) = m;
    }
    ties_found += visibility_at_tie(gp.position, gp.normal, a, n) || visibility_at_tie(gp.position, gp.normal, b, n) ? 1 : 0;
  }
  std::cout << "  visibility_at_tie: " << ties_found << " of " << pairs << " bisected transitions judged ties; "
            << plain_ties << " of " << plain << " texel pairs\n";
  REQUIRE(pairs >= 10);
  CHECK(ties_found == pairs);
  CHECK(plain_ties * 20 <= plain);  // ties are the exception
}

TEST_CASE("ris_mis spatial reuse: GPU vs C++ over a G-buffer (pairwise and balance, per-pixel distributions)") {
  const scene_fixture& f = fixture();
  const auto view = f.view();
  const auto g = f.gbuffer.view();
  const float tol = window();
  const float n1 = 8.0f, n2 = 4.0f;
  const distribution_ref cdf{}, one_texel = fixed_case(1.0f, lit_texel());
  const std::string head = std::string(kept_visible_glsl) + R"(
#include "vplkit/estimators/ris_params.h"
#include "vplkit/estimators/ris_mis_spatial_reuse.glsl"
layout(std430, binding = 11) readonly buffer Records { vplkit_ris_reservoir_record records[]; };
vplkit_ris_reservoir vplkit_load_ris_reservoir(int pixel) { return vplkit_ris_reservoir_from_record(records[pixel]); }
uint vplkit_ris_reuse_distribution(int pixel) { return (ip2.x != 0 && pixel % 7 == 0) ? 1u : 0u; }
)";
  // ip.y = K, ip.z = vpl mode, ip.w = radius; ip2.x = mixed distributions, ip2.y = mis, ip2.z =
  // reject; fp.x = n1, fp.y = window, fp.z = n2.
  const std::string body = R"(  int pixel = int(i);
  vplkit_gather_point gp = vplkit_load_gather_point(pixel);
  vplkit_dprsm_view view = load_view();
  vplkit_ris_spatial_settings s = vplkit_make_ris_spatial_settings();
  s.neighbours = ip.y;
  s.radius = ip.w;
  s.mis = ip2.y;
  if (ip2.z == 0) { s.min_normal_cos = -2.0; s.max_plane_slope = uintBitsToFloat(0x7F800000u); }
  vplkit_counter_rng rng = vplkit_make_counter_rng(0x915u, i);
  vplkit_ris_reservoir r = vplkit_ris_mis_spatial_reuse(gp, pixel, 24, 24, view, vplkit_load_ris_reservoir(pixel), s,
                                                        rng, fp.x, fp.z, ip.z, fp.y);
  uint d = vplkit_ris_reuse_distribution(pixel);
  vplkit_visibility vis = vplkit_make_voxel_visibility(load_grid());
  vec3 shade = vplkit_ris_mis_shade(gp, view, d, r, vis, fp.x, fp.z, ip.z, fp.y);
  result[i] = out4(vec4(shade, r.weight_sum), vec4(r.kept.xi, r.target, r.confidence),
                   ivec4(r.kept.texel, int(rng.counter), VPLKIT_RIS_MAX_NEIGHBOURS, 0),
                   uvec4(kept_visible(gp, view, d, r, vis, fp.x, fp.z, ip.z, fp.y), 0u, 0u, 0u));
)";
  struct config {
    vplkit::ris_reuse_mis mis;
    bool reject, mixed;
    const char* name;
  };
  const config configs[] = {{vplkit::ris_reuse_mis::pairwise, true, false, "pairwise, rejecting, one distribution"},
                            {vplkit::ris_reuse_mis::pairwise, false, true, "pairwise, no rejection, per-pixel"},
                            {vplkit::ris_reuse_mis::balance, false, true, "balance, no rejection, per-pixel"}};
  std::size_t flipped = 0, compared = 0, vis_flips = 0, vis_ties = 0, with_sample = 0;
  for (const vplkit::vpl_mode mode : {vplkit::vpl_mode::point, vplkit::vpl_mode::patch})
    for (const config& cfg : configs) {
      // The pixel's distribution, as vplkit_ris_reuse_distribution picks it.
      const auto dist_of = [&](int p) -> const distribution_ref& { return cfg.mixed && p % 7 == 0 ? one_texel : cdf; };
      std::vector<vplkit::gpu::ris_reservoir_record> records;
      for (int p = 0; p < g.pixel_count(); ++p) {
        vplkit::counter_rng rng = vplkit::make_counter_rng(0x733u, std::uint32_t(p));
        records.push_back(vplkit::gpu::make_ris_reservoir_record(
            vplkit::ris_mis_resample(g.at(p), view, dist_of(p), rng, 8, n1, n2, mode, tol)));
      }
      vplkit::ris_spatial_settings<float> s;
      s.neighbours = 6;
      s.radius = 4;
      s.mis = cfg.mis;
      if (!cfg.reject) {
        s.min_normal_cos = -2.0f;
        s.max_plane_slope = inf;
      }
      scene_params p = f.params();
      p.ip.y = s.neighbours;
      p.ip.z = int(mode);
      p.ip.w = s.radius;
      p.ip2.x = cfg.mixed ? 1 : 0;
      p.ip2.y = int(cfg.mis);
      p.ip2.z = cfg.reject ? 1 : 0;
      p.fp.x = n1;
      p.fp.y = tol;
      p.fp.z = n2;
      const std::string what = std::string(mode == vplkit::vpl_mode::patch ? "patch, " : "point, ") + cfg.name;
      const auto gpu = run(head, body, std::size_t(g.pixel_count()), std::size_t(g.pixel_count()), p, {}, one_texel,
                           {input(11, records)}, "ris_mis_spatial_reuse.comp");
      const auto load = [&](int q) {
        return vplkit::ris_neighbour<float>{g.at(q), vplkit::gpu::ris_reservoir_from_record(records[std::size_t(q)])};
      };
      vplkit::parity::series<std::int32_t> texel, counter, constant, visible;
      vplkit::parity::series<float> confidence;
      std::vector<float> tg, tc, wg, wc, sg, sc;
      std::vector<double> tr, wr, sr;
      for (int q = 0; q < g.pixel_count(); ++q) {
        vplkit::counter_rng rng = vplkit::make_counter_rng(0x915u, std::uint32_t(q));
        const vplkit::ris_reservoir<float> r = vplkit::ris_mis_spatial_reuse(
            g.at(q), q, g.width, g.height, view, vplkit::gpu::ris_reservoir_from_record(records[std::size_t(q)]), load,
            s, rng, dist_of, n1, n2, mode, tol);
        const out4& o = gpu[std::size_t(q)];
        counter.add(o.c.y, std::int32_t(rng.counter));
        constant.add(o.c.z, vplkit::ris_max_neighbours);
        confidence.add(o.b.w, r.confidence);
        if (o.c.x != r.kept.texel || o.b.x != r.kept.xi.x || o.b.y != r.kept.xi.y) {
          // A neighbour's rejection (a normalised dot against a threshold) or a selection (weights
          // carrying the GPU's rounding of the targets) at a tie.
          ++flipped;
          continue;
        }
        ++compared;
        with_sample += vplkit::ris_reservoir_has_sample(r) ? 1 : 0;
        texel.add(o.c.x, r.kept.texel);
        const std::uint32_t vis_cpu = kept_visible(g.at(q), view, dist_of(q), r, n1, n2, mode, tol);
        if (o.d[0] != vis_cpu) {
          // Reuse without rejection brings neighbours' samples that graze q's surface, where the
          // voxel march decides at a tie (the H200 read 44 flips in 3422 pixels here, 0 in 4940
          // reservoirs without reuse). Ties are two right answers; the others are counted.
          if (kept_visibility_at_tie(g.at(q), view, dist_of(q), r, n1, n2, mode, tol))
            ++vis_ties;
          else
            ++vis_flips;
          continue;
        }
        visible.add(std::int32_t(o.d[0]), std::int32_t(vis_cpu));
        // The target: h's float chain and conditioning at q. The weight sum: K + 1 MIS weights, each
        // a quotient of sums of confidence-weighted targets (each within the same kind of bound),
        // times a target and a stored W: a few targets' errors over the pairwise shares.
        const double h_rel = base_rel + 2.0 * h_conditioning(g.at(q), view, r.kept, mode, tol);
        tg.push_back(o.b.z), tc.push_back(r.target), tr.push_back(h_rel);
        const double w_rel = 8.0 * base_rel + 4.0 * h_rel;
        wg.push_back(o.a.w), wc.push_back(r.weight_sum), wr.push_back(w_rel);
        const auto v = vplkit::ris_mis_shade(g.at(q), view, dist_of(q), r,
                                             vplkit::voxel_visibility<float>{f.grid.view()}, n1, n2, mode, tol);
        for (int c = 0; c < 3; ++c) sg.push_back(o.a[c]), sc.push_back(v[c]), sr.push_back(2.0 * h_rel + w_rel);
      }
      const auto describe = [&](std::size_t) { return what; };
      VPLKIT_CHECK_PARITY(compare_exact(counter, describe, "ris_mis reuse " + what + ": stream counters"));
      VPLKIT_CHECK_PARITY(compare_exact(constant, describe, "VPLKIT_RIS_MAX_NEIGHBOURS"));
      VPLKIT_CHECK_PARITY(compare_exact(texel, describe, "ris_mis reuse " + what + ": kept texels"));
      VPLKIT_CHECK_PARITY(compare_exact(visible, describe, "ris_mis reuse " + what + ": kept samples' visibility"));
      // Sums of a few confidences, exact in float.
      VPLKIT_CHECK_PARITY(compare_floats(confidence, within_ulps(0), describe, "ris_mis reuse " + what + ": confidence"));
      std::size_t zf = 0;
      CHECK(check_rel("ris_mis reuse " + what + ": target", tg, tc, tr, zf) == 0);
      CHECK(check_rel("ris_mis reuse " + what + ": weight sum", wg, wc, wr, zf) == 0);
      CHECK(check_rel("ris_mis reuse " + what + ": shade h V W", sg, sc, sr, zf) == 0);
      if (bit_exact_device()) CHECK(zf == 0);
    }
  std::cout << "  ris_mis reuse: " << compared << " pixels compared (" << with_sample << " with a sample), " << flipped
            << " with a kept sample that differs, " << vis_ties + vis_flips
            << " with a kept sample's visibility that differs (" << vis_ties << " at a tie)\n";
  CHECK(with_sample > compared / 2);
  CHECK(flipped <= compared / 100);
  if (bit_exact_device()) CHECK(vis_flips + vis_ties == 0);
  else CHECK(vis_flips <= compared / 100);
}
