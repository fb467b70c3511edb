// SPDX-License-Identifier: MIT
// docs/math.md sections 10 and 11 for patch-sampled VPLs: grazing planes (cos(alpha) -> 0, where the
// intersection runs off), light rays meeting the plane behind the light or running parallel to it,
// the light on the texel's plane, rim texels whose square leaves the disk, zero / tiny / huge
// normals, non-finite or out-of-range jitter and depth tolerances, invalid texels, and the
// patch-mode estimators at gather points on a patch point, back-facing, at background pixels, with
// denormal pmfs. Float and double; never NaN or Inf, every rejection exactly where the rule says.
#include <synthetic_scene.hpp>

#include <vplkit/distribution/discrete_cdf.hpp>
#include <vplkit/estimators/local_estimator.hpp>
#include <vplkit/estimators/mis_estimator.hpp>
#include <vplkit/estimators/vpl_sampling_estimator.hpp>
#include <vplkit/estimators/vpl_sum.hpp>
#include <vplkit/paraboloid/paraboloid.hpp>
#include <vplkit/paraboloid/texel_grid.hpp>
#include <vplkit/visibility/visibility_callables.hpp>
#include <vplkit/vpl/dprsm_patch.hpp>
#include <vplkit/vpl/luminance.hpp>

#include <catch2/catch.hpp>
#include <special_values.hpp>

#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

using namespace vplkit;
using namespace vplkit_test;

namespace {

template <class T>
bool sample_finite(const dprsm_patch_sample<T>& s) {
  return finite3(s.point.position) && finite3(s.point.normal) && finite3(s.point.flux) && std::isfinite(s.uv.x) &&
         std::isfinite(s.uv.y) && std::isfinite(s.solid_angle) && std::isfinite(s.distance) &&
         std::isfinite(s.cos_alpha);
}

// A DPRSM of resolution R with one lit texel (face 0, x, y) at y_t with normal n; the light at
// `light` with the identity frame (front face along +z).
template <class T>
struct one_texel_view {
  int R, t;
  dprsm_data<T> d;
  one_texel_view(int R_, int x, int y, vec3<T> y_t, vec3<T> n, vec3<T> light_pos = vec3<T>(T(0)))
      : R(R_), t(texel_index(paraboloid_front, x, y, R_)) {
    const std::size_t count = std::size_t(texel_count(R_));
    d.resolution = R_;
    d.light = make_point_light(light_pos, vec3<T>(T(4), T(5), T(6)));
    d.position.assign(count, vec3<T>(T(0)));
    d.normal.assign(count, vec3<T>(T(0)));
    d.albedo.assign(count, vec3<T>(T(0)));
    d.position[std::size_t(t)] = y_t;
    d.normal[std::size_t(t)] = n;
    d.albedo[std::size_t(t)] = vec3<T>(T(0.5), T(0.6), T(0.7));
  }
  dprsm_view<T> view() const { return d.view(); }
  // The centre direction of the texel (light space = world space here).
  vec3<T> centre_dir() const {
    const ivec2 xy = texel_coords(t, R);
    return paraboloid_to_direction(paraboloid_front, texel_center_uv<T>(xy.x, xy.y, R));
  }
};

}  // namespace

TEMPLATE_TEST_CASE("patch hard case: grazing planes and rays that meet the plane behind the light", "[hardcases]",
                   float, double) {
  using T = TestType;
  const T inf = std::numeric_limits<T>::infinity();
  // Texel (4, 4) of R = 8 near the pole; its plane through y_t = 2 w_c tilted so that cos(alpha)
  // at the centre is 10^-k: the plane's horizon passes through the texel, so part of its rays run
  // parallel to the plane or meet it behind the light.
  for (int k : {1, 2, 3, 5}) {
    const T eps = std::pow(T(10), T(-k));
    const vec3<T> wc = glm::normalize(paraboloid_to_direction(paraboloid_front, texel_center_uv<T>(4, 4, 8)));
    const vec3<T> side = glm::normalize(glm::cross(wc, vec3<T>(T(1), T(0), T(0))));
    const vec3<T> n = glm::normalize(-eps * wc + std::sqrt(T(1) - eps * eps) * side);
    const one_texel_view<T> o(8, 4, 4, T(2) * wc, n);
    const dprsm_view<T> view = o.view();
    int accepted = 0, behind = 0, windowed = 0;
    T farthest = T(0);
    const int m = 48;
    for (int j = 0; j < m; ++j)
      for (int i = 0; i < m; ++i) {
        const vec2<T> xi((T(i) + T(0.5)) / T(m), (T(j) + T(0.5)) / T(m));
        const dprsm_patch_sample<T> s = dprsm_patch_vpl(view, o.t, xi, inf);
        const dprsm_patch_sample<T> w = dprsm_patch_vpl(view, o.t, xi, T(0.5));
        REQUIRE(sample_finite(s));
        REQUIRE(sample_finite(w));
        // the rule, recomputed in double: accepted iff the ray meets the plane in front of the light
        const vec3<double> dir(paraboloid_to_direction(paraboloid_front, vec2<double>(s.uv)));
        const double cos_a = -glm::dot(vec3<double>(glm::normalize(n)), dir);
        INFO("k " << k << " xi " << xi.x << ", " << xi.y << " cos(alpha) " << cos_a);
        if (std::abs(cos_a) > 1e-5) REQUIRE(vpl_has_flux(s.point) == (cos_a > 0.0));
        if (!vpl_has_flux(s.point)) {
          ++behind;
          REQUIRE(s.point.position == view.position[o.t]);  // rejected: y_t, flux 0
          continue;
        }
        ++accepted;
        farthest = std::max(farthest, s.distance);
        // the lit test (tolerance 0.5) keeps every plane point where the ray meets the plane at
        // cos(alpha) > dprsm_plane_min_cos; below it, falling back to the centre's depth 2, those
        // nearer than 2 + 0.5 + its slack d (2/R + 1e-4)
        const double min_cos = double(dprsm_plane_min_cos<T>());
        const double limit = (2.0 + 0.5) / (1.0 - double(dprsm_lookup_slack(T(1), 8)));
        if (cos_a > min_cos * (1 + 1e-3)) REQUIRE(vpl_has_flux(w.point));
        if (cos_a < min_cos * (1 - 1e-3)) {
          if (double(s.distance) > limit * (1 + 1e-4)) REQUIRE(!vpl_has_flux(w.point));
          if (double(s.distance) < limit * (1 - 1e-4)) REQUIRE(vpl_has_flux(w.point));
        }
        if (!vpl_has_flux(w.point)) ++windowed;
        // a gather point in front of the plane sees a finite contribution
        const vec3<T> x = T(1.5) * wc + T(0.3) * n;
        const vec3<T> c = vpl_contribution(x, -n + T(0.2) * wc, vec3<T>(T(0.8)), s.point, T(0));
        REQUIRE(finite3(c));
      }
    std::printf("grazing plane, cos(alpha) at the centre 1e-%d (%s): %d of %d points accepted, %d behind / parallel, "
                "farthest at %.3g (centre 2), %d rejected by the lit test at tolerance 0.5\n",
                k, std::is_same<T, float>::value ? "float" : "double", accepted, m * m, behind, double(farthest),
                windowed);
    CHECK(accepted > 0);
    CHECK(behind > 0);
  }
}

TEMPLATE_TEST_CASE("patch hard case: the light on the texel's plane, zero and extreme normals", "[hardcases]", float,
                   double) {
  using T = TestType;
  const T inf = std::numeric_limits<T>::infinity();
  const vec3<T> wc = glm::normalize(paraboloid_to_direction(paraboloid_front, texel_center_uv<T>(3, 4, 8)));
  // The light on the plane (x = 0, exactly): no direction meets it in front of the light.
  {
    const one_texel_view<T> o(8, 3, 4, vec3<T>(T(0), T(0.25), T(2)), vec3<T>(T(1), T(0), T(0)));
    for (T u : {T(0), T(0.25), T(0.5), T(1)}) {
      const dprsm_patch_sample<T> s = dprsm_patch_vpl(o.view(), o.t, vec2<T>(u, T(1) - u), inf);
      CHECK(sample_finite(s));
      CHECK(!vpl_has_flux(s.point));
    }
  }
  // Zero normal: no plane, no VPL. Unnormalised normals: the unit normal's point.
  const one_texel_view<T> zero(8, 3, 4, T(2) * wc, vec3<T>(T(0)));
  const one_texel_view<T> unit(8, 3, 4, T(2) * wc, -wc);
  const vec2<T> xi(T(0.3), T(0.8));
  const dprsm_patch_sample<T> ref = dprsm_patch_vpl(unit.view(), unit.t, xi, inf);
  REQUIRE(vpl_has_flux(ref.point));
  CHECK(!vpl_has_flux(dprsm_patch_vpl(zero.view(), zero.t, xi, inf).point));
  // (Denormal scales lose the normal's own digits; unit_or_zero keeps every normal-range scale.)
  for (T scale : {T(1e-30), T(1e-20), T(7), T(1e20), T(1e30)}) {
    const one_texel_view<T> o(8, 3, 4, T(2) * wc, -wc * scale);
    const dprsm_patch_sample<T> s = dprsm_patch_vpl(o.view(), o.t, xi, inf);
    INFO("normal scale " << scale);
    REQUIRE(sample_finite(s));
    REQUIRE(vpl_has_flux(s.point));
    CHECK(glm::length(s.point.position - ref.point.position) <= T(64) * std::numeric_limits<T>::epsilon() * T(2));
    CHECK(s.point.flux == ref.point.flux);
  }
  // The texel recorded the light's own position: no VPL.
  const one_texel_view<T> at_light(8, 3, 4, vec3<T>(T(0)), -wc);
  CHECK(!vpl_has_flux(dprsm_patch_vpl(at_light.view(), at_light.t, xi, inf).point));
}

TEMPLATE_TEST_CASE("patch hard case: rim texels keep only their part inside the disk", "[hardcases]", float, double) {
  using T = TestType;
  const T inf = std::numeric_limits<T>::infinity();
  const int R = 8, x = 7, y = 3;  // centre (0.875, -0.125): valid; its outer corners have r2 > 1
  REQUIRE(texel_is_valid(x, y, R));
  const vec3<T> wc = glm::normalize(paraboloid_to_direction(paraboloid_front, texel_center_uv<T>(x, y, R)));
  const one_texel_view<T> o(R, x, y, T(3) * wc, -wc);
  int inside = 0, outside = 0;
  const int m = 40;
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < m; ++i) {
      const vec2<T> xi((T(i) + T(0.5)) / T(m), (T(j) + T(0.5)) / T(m));
      const dprsm_patch_sample<T> s = dprsm_patch_vpl(o.view(), o.t, xi, inf);
      REQUIRE(sample_finite(s));
      const T r2 = glm::dot(s.uv, s.uv);
      INFO("uv " << s.uv.x << ", " << s.uv.y);
      REQUIRE(vpl_has_flux(s.point) == (r2 <= T(1)));
      (r2 <= T(1) ? inside : outside) += 1;
      if (r2 <= T(1)) REQUIRE(s.solid_angle == texel_point_solid_angle(s.uv, R));
    }
  std::printf("rim texel (7, 3) of R = 8: %d of %d jitter points inside the disk\n", inside, m * m);
  CHECK(inside > 0);
  CHECK(outside > 0);
  // Invalid texels (centre outside the disk) have no patch, whatever their data.
  const one_texel_view<T> invalid(R, 7, 0, T(3) * wc, -wc);
  REQUIRE(!texel_is_valid(7, 0, R));
  CHECK(!vpl_has_flux(dprsm_patch_vpl(invalid.view(), invalid.t, vec2<T>(T(0.1), T(0.9)), inf).point));
}

TEMPLATE_TEST_CASE("patch hard case: non-finite and out-of-range jitter and depth tolerances", "[hardcases]", float,
                   double) {
  using T = TestType;
  const T inf = std::numeric_limits<T>::infinity(), nan = std::numeric_limits<T>::quiet_NaN();
  const vec3<T> wc = glm::normalize(paraboloid_to_direction(paraboloid_front, texel_center_uv<T>(4, 3, 8)));
  const one_texel_view<T> o(8, 4, 3, T(2) * wc, -wc);
  const dprsm_view<T> view = o.view();
  auto at = [&](T a, T b, T tol) { return dprsm_patch_vpl(view, o.t, vec2<T>(a, b), tol); };
  // xi clamps into [0, 1] (NaN -> 0): the point stays in the texel's closed square.
  CHECK(at(nan, T(0.5), inf).uv == at(T(0), T(0.5), inf).uv);
  CHECK(at(-inf, T(0.5), inf).uv == at(T(0), T(0.5), inf).uv);
  CHECK(at(T(-3), T(0.5), inf).uv == at(T(0), T(0.5), inf).uv);
  CHECK(at(T(0.5), inf, inf).uv == at(T(0.5), T(1), inf).uv);
  CHECK(at(T(0.5), T(7), inf).uv == at(T(0.5), T(1), inf).uv);
  for (T a : {nan, -inf, T(-1), T(0), T(1), T(2), inf})
    for (T b : {nan, T(0.5), inf}) {
      const dprsm_patch_sample<T> s = at(a, b, inf);
      INFO("xi " << a << ", " << b);
      CHECK(sample_finite(s));
      CHECK(vpl_has_flux(s.point));
      // xi clamped to 1 is the edge shared with the next texel, which owns it
      if (!(a >= T(1)) && !(b >= T(1))) CHECK(view.texel_of_point(s.point.position) == o.t);
    }
  // Depth tolerance: NaN or negative rejects everything; 0 keeps the plane's points; inf all.
  CHECK(!vpl_has_flux(at(T(0.2), T(0.7), nan).point));
  CHECK(!vpl_has_flux(at(T(0.2), T(0.7), T(-1)).point));
  CHECK(vpl_has_flux(at(T(0.2), T(0.7), inf).point));
  CHECK(sample_finite(at(T(0.2), T(0.7), T(0))));
  CHECK(vpl_has_flux(at(T(0.2), T(0.7), T(0)).point));
}

TEMPLATE_TEST_CASE("patch hard case: the estimators at gather points on, behind and off the patches", "[hardcases]",
                   float, double) {
  using T = TestType;
  const synthetic_scene<T> s;
  const dprsm_data<T> d = s.make_dprsm(16);
  const dprsm_view<T> view = d.view();
  const exact_visibility<T> vis{&s};
  const exact_tracer<T> tracer{&s};
  std::vector<T> w(std::size_t(view.texel_count()));
  for (int t = 0; t < view.texel_count(); ++t) w[std::size_t(t)] = luminance(view.vpl_at(t).flux);
  const discrete_cdf<T> cdf(w);
  const discrete_cdf<T> two[2] = {cdf, cdf};
  const T tol = T(0.2), inf = std::numeric_limits<T>::infinity(), nan = std::numeric_limits<T>::quiet_NaN();
  auto all = [&](const gather_point<T>& gp) {
    std::vector<vec3<T>> r;
    counter_rng rng = make_counter_rng(5u, 1u);
    r.push_back(exhaustive_vpl_patch_sum(gp, view, rng, 2, vis, T(0), tol));
    r.push_back(estimate_vpl_sampling(gp, view, cdf, rng, 64, vis, T(0), vpl_mode::patch, tol));
    r.push_back(estimate_vpl_sampling(gp, view, cdf, rng, 64, vis, T(0), vpl_mode::patch, inf));
    r.push_back(estimate_local(gp, view, two, 2, rng, 16, vis, T(0), local_combination::balance, vpl_mode::patch, tol));
    r.push_back(estimate_local(gp, view, two, 2, rng, 16, vis, T(0), local_combination::average, vpl_mode::patch, tol));
    r.push_back(estimate_mis(gp, view, cdf, rng, 32, 32, tracer, vis, tol, mis_mode::solid_angle, vpl_mode::patch));
    r.push_back(estimate_mis(gp, view, cdf, rng, 32, 32, tracer, vis, tol, mis_mode::as_published, vpl_mode::patch));
    return r;
  };
  // Gather points exactly on a patch point (d2 = 0), 8 eps from it, and on it facing away.
  // (A texel off the rim: a rim texel's block point may lie outside its domain.)
  int t = 0;
  while (!vpl_has_flux(view.vpl_at(t)) || texel_is_rim(texel_coords(t, 16).x, texel_coords(t, 16).y, 16)) ++t;
  const dprsm_patch_sample<T> p = dprsm_patch_vpl(view, t, vec2<T>(T(0.3), T(0.6)), tol);
  REQUIRE(vpl_has_flux(p.point));
  const vec3<T> y = p.point.position, n = glm::normalize(p.point.normal);
  const T e = T(8) * std::numeric_limits<T>::epsilon() * max_abs_component(y);
  const std::vector<gather_point<T>> points = {
      {y, n, vec3<T>(T(0.6))},
      {y + vec3<T>(e, T(0), e), n, vec3<T>(T(0.6))},
      {y, -n, vec3<T>(T(0.6))},
      {s.gather_points()[0].gp.position, -s.gather_points()[0].gp.normal, vec3<T>(T(0.6))},  // floor, facing down
      {s.gather_points()[0].gp.position, s.gather_points()[0].gp.normal * T(1e-30), vec3<T>(T(0.6))},
  };
  for (std::size_t i = 0; i < points.size(); ++i)
    for (const vec3<T>& v : all(points[i])) {
      INFO("gather point " << i);
      CHECK(finite3(v));
      CHECK((v.x >= T(0) && v.y >= T(0) && v.z >= T(0)));
    }
  // Background and non-finite gather points: 0, no draws.
  for (const gather_point<T>& gp : {gather_point<T>{y, vec3<T>(T(0)), vec3<T>(T(1))},
                                    gather_point<T>{vec3<T>(nan, T(0), T(0)), n, vec3<T>(T(1))},
                                    gather_point<T>{vec3<T>(T(0), inf, T(0)), n, vec3<T>(T(1))}}) {
    counter_rng rng = make_counter_rng(5u, 2u);
    CHECK(estimate_vpl_sampling(gp, view, cdf, rng, 8, vis, T(0), vpl_mode::patch, tol) == vec3<T>(T(0)));
    CHECK(estimate_mis(gp, view, cdf, rng, 8, 8, tracer, vis, tol, mis_mode::solid_angle, vpl_mode::patch) ==
          vec3<T>(T(0)));
    CHECK(exhaustive_vpl_patch_sum(gp, view, rng, 1, vis, T(0), tol) == vec3<T>(T(0)));
    CHECK(rng.counter == 0u);
  }
  // A lit texel drawn with a denormal pmf: the quotient may overflow; it adds 0, never Inf.
  struct fixed {
    std::size_t index;
    T p;
    discrete_sample<T> sample(T) const { return {index, p}; }
    T pmf(std::size_t i) const { return i == index ? p : T(0); }
  };
  const fixed denormal{std::size_t(t), std::numeric_limits<T>::denorm_min()};
  const gather_point<T> open = s.gather_points()[0].gp;
  counter_rng rng = make_counter_rng(5u, 3u);
  CHECK(finite3(estimate_vpl_sampling(open, view, denormal, rng, 8, vis, T(0), vpl_mode::patch, tol)));
  CHECK(finite3(estimate_mis(open, view, denormal, rng, 8, 8, tracer, vis, tol, mis_mode::solid_angle, vpl_mode::patch)));
  // The pointwise MIS density at special points: never NaN; +inf only at the light itself, where
  // the patch has zero area (vpl_pdf_solid_angle's rule; the lookup never calls such a hit lit).
  for (const vec3<T>& q : {open.position, y, y + T(1e-3) * n})
    CHECK(std::isfinite(mis_patch_vpl_pdf(view, t, T(0.01), open.position, q)));
  CHECK(mis_patch_vpl_pdf(view, t, T(0.01), open.position, view.light.position) == inf);
  CHECK(mis_patch_vpl_pdf(view, t, T(0.01), y, y) == T(0));
  CHECK(mis_patch_vpl_pdf(view, t, T(0), open.position, y) == T(0));
}
