// SPDX-License-Identifier: MIT
// Unit checks of the estimators: exact values of single samples, the random-number consumption
// order the GLSL mirror follows, the consistency identities between estimators, and the adaptors.
#include <synthetic_scene.hpp>

#include <vplkit/distribution/discrete_cdf.hpp>
#include <vplkit/distribution/face_roulette.hpp>
#include <vplkit/distribution/flat_face_roulette.hpp>
#include <vplkit/estimators/gathering_estimator.hpp>
#include <vplkit/estimators/local_estimator.hpp>
#include <vplkit/estimators/mis_estimator.hpp>
#include <vplkit/estimators/vpl_sampling_estimator.hpp>
#include <vplkit/estimators/vpl_sum.hpp>
#include <vplkit/visibility/visibility_callables.hpp>
#include <vplkit/vpl/luminance.hpp>
#include <vplkit/vplkit.hpp>

#include <catch2/catch.hpp>

#include <vector>

using namespace vplkit;
using namespace vplkit_test;

namespace {

struct fixture : lit_room<double> {
  std::vector<double> w;
  fixture() : lit_room<double>(32) {
    w.resize(std::size_t(view.texel_count()));
    for (int t = 0; t < view.texel_count(); ++t)
      w[std::size_t(t)] = luminance(view.vpl_at(t).flux) * (1.0 + 0.5 * std::sin(0.1 * t));
  }
};

void check_close(vec3<double> a, vec3<double> b, double rel) {
  for (int c = 0; c < 3; ++c) CHECK(a[c] == Approx(b[c]).epsilon(rel).margin(1e-300));
}

}  // namespace

TEST_CASE("estimators: VPL sampling draws one u per sample and divides by the pmf") {
  const fixture f;
  const discrete_cdf<double> cdf(f.w);
  for (const auto& g : f.gps) {
    counter_rng rng = make_counter_rng(9u, 1u), manual = rng;
    const vec3<double> e = estimate_vpl_sampling(g.gp, f.view, cdf, rng, 3, f.vis, 0.0);
    vec3<double> sum(0.0);
    for (int k = 0; k < 3; ++k) {
      const discrete_sample<double> s = cdf.sample(rng_next_unit<double>(manual));
      const vpl<double> v = f.view.vpl_at(int(s.index));
      vec3<double> c = vpl_contribution(g.gp.position, g.gp.normal, g.gp.albedo, v, 0.0);
      if (!f.scene.visible(g.gp.position, g.gp.normal, v.position, v.normal)) c = vec3<double>(0.0);
      sum += c / s.pmf;
    }
    INFO(g.name);
    CHECK(rng.counter == 3u);
    CHECK(rng.counter == manual.counter);
    check_close(e, sum / 3.0, 1e-14);
  }
}

TEST_CASE("estimators: the exhaustive sum is the plain sum, and occluders only remove light") {
  const fixture f;
  for (const auto& g : f.gps) {
    vec3<double> manual(0.0), open(0.0);
    for (int t = 0; t < f.view.texel_count(); ++t) {
      const vpl<double> v = f.view.vpl_at(t);
      const vec3<double> c = vpl_contribution(g.gp.position, g.gp.normal, g.gp.albedo, v, 0.05);
      open += c;
      if (f.scene.visible(g.gp.position, g.gp.normal, v.position, v.normal)) manual += c;
    }
    INFO(g.name);
    check_close(exhaustive_vpl_sum(g.gp, f.view, f.vis, 0.05), manual, 1e-12);
    check_close(exhaustive_vpl_sum(g.gp, f.view, always_visible{}, 0.05), open, 1e-12);
    CHECK(luminance(manual) <= luminance(open));
  }
  // the floor under the block sees less than half of what the unoccluded sum claims
  const auto& g = f.gps[1];
  CHECK(luminance(exhaustive_vpl_sum(g.gp, f.view, f.vis, 0.0)) <
        0.5 * luminance(exhaustive_vpl_sum(g.gp, f.view, always_visible{}, 0.0)));
}

TEST_CASE("estimators: flat_face_roulette has the pmf of one CDF over both faces") {
  const fixture f;
  const std::size_t face = 32 * 32;
  const face_roulette<double> roulette(discrete_cdf<double>(f.w.data(), face),
                                       discrete_cdf<double>(f.w.data() + face, face));
  const flat_face_roulette<double> flat(roulette, 32);
  const discrete_cdf<double> one(f.w);
  REQUIRE(flat.size() == f.w.size());
  for (std::size_t t = 0; t < f.w.size(); ++t) CHECK(flat.pmf(t) == Approx(one.pmf(t)).epsilon(1e-9).margin(1e-300));  // CDF differences
  for (int k = 0; k < 1000; ++k) {
    const double u = (k + 0.5) / 1000.0;
    const discrete_sample<double> s = flat.sample(u);
    CHECK(s.pmf > 0.0);
    CHECK(s.pmf == flat.pmf(s.index));
    CHECK(f.w[s.index] > 0.0);
  }
  // the estimator overload for face_roulette is the adaptor
  const auto& g = f.gps[0];
  counter_rng r1 = make_counter_rng(1u, 1u), r2 = r1;
  CHECK(estimate_vpl_sampling(g.gp, f.view, roulette, r1, 8, f.vis, 0.0) ==
        estimate_vpl_sampling(g.gp, f.view, flat, r2, 8, f.vis, 0.0));
}

TEST_CASE("estimators: local with one CDF is VPL sampling") {
  const fixture f;
  const discrete_cdf<double> cdf(f.w);
  for (const auto& g : f.gps) {
    for (local_combination mode : {local_combination::balance, local_combination::average}) {
      counter_rng r1 = make_counter_rng(2u, 3u), r2 = r1;
      const vec3<double> a = estimate_local(g.gp, f.view, &cdf, 1, r1, 7, f.vis, 0.0, mode);
      const vec3<double> b = estimate_vpl_sampling(g.gp, f.view, cdf, r2, 7, f.vis, 0.0);
      INFO(g.name);
      check_close(a, b, 1e-14);
      CHECK(r1.counter == r2.counter);
    }
  }
  // N CDFs x rounds draws, in the order round-major, CDF-minor
  const discrete_cdf<double> three[3] = {cdf, cdf, cdf};
  counter_rng r = make_counter_rng(2u, 4u);
  (void)estimate_local(f.gps[0].gp, f.view, three, 3, r, 5, f.vis, 0.0);
  CHECK(r.counter == 15u);
}

TEST_CASE("estimators: MIS reduces to each strategy alone") {
  const fixture f;
  const discrete_cdf<double> cdf(f.w);
  for (const auto& g : f.gps) {
    INFO(g.name);
    // no directions: f/p2 = L_t(x)/p(t) unclamped, i.e. VPL sampling with dmin = 0
    counter_rng r1 = make_counter_rng(3u, 1u), r2 = r1;
    const vec3<double> m = estimate_mis(g.gp, f.view, cdf, r1, 0, 9, f.tracer, f.vis, 0.2);
    const vec3<double> v = estimate_vpl_sampling(g.gp, f.view, cdf, r2, 9, f.vis, 0.0);
    check_close(m, v, 1e-9);
    CHECK(r1.counter == 9u);
    // no VPLs: f/p1 = rho_x L_o, i.e. gathering, same two u per direction
    counter_rng r3 = make_counter_rng(3u, 2u), r4 = r3;
    const vec3<double> mg = estimate_mis(g.gp, f.view, cdf, r3, 11, 0, f.tracer, f.vis, 0.2);
    const vec3<double> ga = estimate_gathering(g.gp, f.view, r4, 11, f.tracer, 0.2);
    check_close(mg, ga, 1e-12);
    CHECK(r3.counter == 22u);
    CHECK(r4.counter == 22u);
  }
  // interleaved consumption: per j < max(n_dirs, n_vpls): u for the VPL (j < n_vpls), then two
  counter_rng r = make_counter_rng(3u, 3u);
  (void)estimate_mis(f.gps[0].gp, f.view, cdf, r, 5, 3, f.tracer, f.vis, 0.2);
  CHECK(r.counter == 3u + 10u);
}

TEST_CASE("estimators: MIS samples carry the solid-angle and the paper eq. 8-15 values") {
  const fixture f;
  const discrete_cdf<double> cdf(f.w);
  const auto& g = f.gps[0];
  const double n1 = 4, n2 = 6;
  for (int k = 0; k < 50; ++k) {
    const double u = (k + 0.5) / 50.0;
    const discrete_sample<double> s = cdf.sample(u);
    const int t = int(s.index);
    const vpl<double> v = f.view.vpl_at(t);
    const vec3<double> L = vpl_visible_contribution(g.gp, f.view, t, f.vis, 0.0);
    const vec3<double> wd = glm::normalize(v.position - g.gp.position);
    const double cos2 = glm::dot(glm::normalize(g.gp.normal), wd);
    const double cos1 = -glm::dot(glm::normalize(v.normal), wd);
    const double d2sq = glm::dot(v.position - g.gp.position, v.position - g.gp.position);
    const double d1 = glm::length(v.position - f.view.light.position);
    const double cos_a = glm::dot(glm::normalize(v.normal), glm::normalize(f.view.light.position - v.position));
    const double area = f.view.solid_angle(t) * d1 * d1 / cos_a;
    const double p1 = cos2 / 3.14159265358979323846;
    const double p2 = s.pmf * d2sq / (area * cos1);
    // solid angle: (L/pmf) * n2 p2 / (n1 p1 + n2 p2) / n2 = L/pmf * p2 / (n1 p1 + n2 p2)
    const vec3<double> sa = mis_vpl_sample(g.gp, f.view, cdf, u, f.vis, n1, n2, mis_mode::solid_angle);
    INFO("texel " << t);
    if (luminance(L) > 0.0) check_close(sa, (L / s.pmf) * (p2 / (n1 * p1 + n2 * p2)), 1e-9);
    else CHECK(sa == vec3<double>(0.0));
    // as published: w2 L / alpha with w2 = alpha / (cos sin / pi + alpha)
    const vec3<double> pub = mis_vpl_sample(g.gp, f.view, cdf, u, f.vis, n1, n2, mis_mode::as_published);
    const double pp = cos2 * std::sqrt(1.0 - cos2 * cos2) / 3.14159265358979323846;
    if (luminance(L) > 0.0) check_close(pub, L * ((s.pmf / (pp + s.pmf)) / s.pmf), 1e-9);
  }
}

TEST_CASE("estimators: gathering rays see the block's shadow through the DPRSM") {
  const fixture f;
  const auto& shadow = f.gps[1].gp;  // floor under the block
  const auto up = trace_gathering_ray(f.view, shadow.position, shadow.normal, vec3<double>(0, 1, 0), f.tracer, 0.2);
  CHECK(up.texel >= 0);
  CHECK(up.hit.y == Approx(0.8));
  CHECK_FALSE(up.lit);  // the block's bottom is not seen by the light
  CHECK(up.radiance == vec3<double>(0.0));
  const auto& open = f.gps[0].gp;
  const auto r = trace_gathering_ray(f.view, open.position, open.normal, vec3<double>(0, 1, 0), f.tracer, 0.2);
  REQUIRE(r.lit);
  CHECK(r.hit.y == Approx(3.0));
  check_close(r.radiance,
              reflected_radiance(f.view.light.position, f.view.light.intensity, r.hit, vec3<double>(0, -1, 0),
                                 vec3<double>(0.8)),
              1e-9);
  // a gathering sample is rho_x L_o
  const orthonormal_basis<double> frame = make_orthonormal_basis(open.normal);
  check_close(gathering_sample(open, f.view, frame, vec3<double>(0, 0, 1), f.tracer, 0.2), open.albedo * r.radiance,
              1e-12);
}

TEST_CASE("estimators: voxel callables are the visibility functions") {
  const fixture f;
  const voxel_grid<double> grid = f.scene.make_voxel_grid(32);
  const voxel_visibility<double> two{grid.view()};
  const voxel_visibility_one_sided<double> one{grid.view()};
  const voxel_tracer<double> tr{grid.view()};
  int visible = 0, hidden = 0;
  for (const auto& g : f.gps)
    for (int t = 0; t < f.view.texel_count(); t += 37) {
      const vec3<double> y = f.d.position[std::size_t(t)], ny = f.d.normal[std::size_t(t)];
      const bool b2 = two(g.gp.position, g.gp.normal, y, ny);
      CHECK(b2 == voxel_visible_two_sided(grid.view(), g.gp.position, g.gp.normal, y, ny));
      CHECK(one(g.gp.position, g.gp.normal, y, ny) == voxel_visible(grid.view(), g.gp.position, g.gp.normal, y));
      (b2 ? visible : hidden) += 1;
      const ray_hit<double> h = tr(g.gp.position, g.gp.normal, y - g.gp.position);
      const dda_trace_result<double> ref = dda_trace_hit_point(
          grid.view(), surface_ray_origin(grid.view(), g.gp.position, g.gp.normal), y - g.gp.position);
      CHECK(h.hit == ref.hit);
      if (h.hit) CHECK(h.position == ref.point);
    }
  CHECK(visible > 0);
  CHECK(hidden > 0);
  CHECK(voxel_tracer_depth_tolerance(grid.view()) == Approx(std::sqrt(3.0) * grid.voxel_length()));
}
