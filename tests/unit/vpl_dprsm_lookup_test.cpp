// SPDX-License-Identifier: MIT
// dprsm_lookup's lit test (docs/math.md section 4): y is lit when it is not behind the plane of
// the texel it projects into (one-sided, within the caller's tolerance plus the test's own slack),
// and the centre's depth decides only where the light ray does not meet that plane stably. Each
// case below is one the former rule (|d_y - |y_t - c|| <= tolerance, two-sided) got wrong:
//  - a point behind an occluder's plane at the texel centre's depth (a contact shadow): unlit;
//  - a point in front of the floor texel's plane (a wall at a floor/wall crease): lit;
//  - a grazing plane: lit across the whole texel with tolerance 0, and so is its direct light;
//  - the fallback: a zero or turned-away normal, a normal across the ray; a bad tolerance, a point
//    at infinity.
#include <vplkit/paraboloid/paraboloid.hpp>
#include <vplkit/paraboloid/texel_grid.hpp>
#include <vplkit/vpl/direct_light.hpp>
#include <vplkit/vpl/dprsm_lookup.hpp>
#include <vplkit/vpl/dprsm_raycast.hpp>
#include <vplkit/vpl/luminance.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

using namespace vplkit;

namespace {

// The DPRSM of one infinite plane (point p0, unit normal n facing the light) seen from a light at
// c looking along `axis`; owns its arrays.
template <class T>
struct plane_dprsm {
  std::vector<vec3<T>> position, normal, albedo;
  dprsm_view<T> view;
  vec3<T> p0, n;
  plane_dprsm(vec3<T> c, vec3<T> axis, vec3<T> p0_, vec3<T> n_, int R) : p0(p0_), n(glm::normalize(n_)) {
    const point_light<T> light = make_point_light(c, vec3<T>(T(1)), axis);
    const vec3<T> pp = p0, nn = n;
    view = render_dprsm(
        light, R,
        [pp, nn](vec3<T> o, vec3<T> dir) -> std::optional<dprsm_hit<T>> {
          const T den = glm::dot(nn, dir);
          if (den == T(0)) return std::nullopt;
          const T t = glm::dot(nn, pp - o) / den;
          if (!(t > T(0))) return std::nullopt;
          return dprsm_hit<T>{o + t * dir, nn, vec3<T>(T(0.5))};
        },
        position, normal, albedo);
  }
  plane_dprsm(const plane_dprsm&) = delete;
  plane_dprsm& operator=(const plane_dprsm&) = delete;
  // The world direction of texel t's point xi in [0, 1]^2.
  vec3<T> direction(int t, vec2<T> xi) const {
    const int R = view.resolution;
    const ivec2 xy = texel_coords(t, R);
    return view.light.frame.to_world(paraboloid_to_direction(texel_face(t, R), texel_point_uv(xy.x, xy.y, R, xi)));
  }
  // Where the light ray along unit w meets the plane.
  T plane_distance(vec3<T> w) const { return glm::dot(n, p0 - view.light.position) / glm::dot(n, w); }
  T centre_distance(int t) const { return glm::length(view.position[t] - view.light.position); }
};

// The former rule, to show that each case below is one it decided the other way.
template <class T>
bool former_rule_lit(const dprsm_view<T>& view, vec3<T> y, T tolerance) {
  const int t = view.texel_of_direction(y - view.light.position);
  return std::abs(glm::length(y - view.light.position) - glm::length(view.position[t] - view.light.position)) <=
         tolerance;
}

std::vector<vec2<double>> texel_grid_points(double margin) {
  std::vector<vec2<double>> xi;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j) xi.emplace_back(margin + (1 - 2 * margin) * i / 4.0, margin + (1 - 2 * margin) * j / 4.0);
  return xi;
}

}  // namespace

TEMPLATE_TEST_CASE("dprsm_lookup: exact points of the texel's plane are lit with tolerance 0, points behind it not",
                   "[vpl]", float, double) {
  using T = TestType;
  const int R = 32;
  // A floor below the light and a wall beside it (tilted by 30 degrees to the light), one at a time.
  for (int which = 0; which < 2; ++which) {
    const vec3<T> n = which == 0 ? vec3<T>(0, 0, 1) : vec3<T>(T(-0.866), 0, T(0.5));
    const plane_dprsm<T> s(vec3<T>(T(0.3), T(-0.2), T(1.5)), vec3<T>(0, 0, -1), vec3<T>(T(1.1), 0, 0), n, R);
    int on = 0;
    for (int t = 0; t < s.view.texel_count(); t += 7) {
      if (s.view.albedo[t] == vec3<T>(T(0))) continue;
      for (const vec2<double> xi : texel_grid_points(0.05)) {
        const vec3<T> w = s.direction(t, vec2<T>(xi));
        const T d_p = s.plane_distance(w);
        if (!(d_p > T(0)) || -glm::dot(s.n, w) < T(0.05)) continue;  // grazing: the test below
        if (s.view.texel_of_direction(w) != t) continue;  // a rim texel's corner beyond the disk
        const vec3<T> y = s.view.light.position + d_p * w;
        const dprsm_lookup_result r = dprsm_lookup(s.view, y, T(0));
        INFO("plane " << which << " texel " << t << " xi " << xi.x << " " << xi.y);
        REQUIRE(r.texel == t);
        CHECK(r.lit);
        // Behind by twice the slack along the ray: in the plane's shadow.
        const T behind = T(2) * dprsm_lookup_slack(d_p, R);
        CHECK_FALSE(dprsm_lookup(s.view, s.view.light.position + (d_p + behind) * w, T(0)).lit);
        ++on;
      }
    }
    CHECK(on > 500);
  }
}

TEST_CASE("dprsm_lookup: a point behind an occluder's plane at the texel centre's depth (a contact shadow) is unlit") {
  // An occluder tilted by 70 degrees to the light ray below the light: across one texel its depth
  // varies by about a footprint times tan(70), so points of the texel at the centre's depth lie
  // well behind its plane where the plane comes nearer. The former rule called them lit.
  const int R = 16;
  const double a = 70.0 * 3.14159265358979 / 180.0;
  const plane_dprsm<double> s(vec3<double>(0), vec3<double>(0, 0, -1), vec3<double>(0, 0, -1),
                              vec3<double>(std::sin(a), 0, std::cos(a)), R);
  const int t = s.view.texel_of_direction(vec3<double>(0.01, 0.02, -1));
  REQUIRE(s.view.albedo[t] != vec3<double>(0));
  const double d_t = s.centre_distance(t);
  const double tolerance = 0.01;
  int shadowed = 0;
  for (const vec2<double> xi : texel_grid_points(0.05)) {
    const vec3<double> w = s.direction(t, xi);
    const vec3<double> y = s.view.light.position + d_t * w;
    const double behind = d_t - s.plane_distance(w);  // along the ray, behind the occluder's plane
    INFO("xi " << xi.x << " " << xi.y << " behind " << behind);
    REQUIRE(dprsm_lookup(s.view, y, tolerance).texel == t);
    CHECK(former_rule_lit(s.view, y, tolerance));
    if (behind > tolerance + dprsm_lookup_slack(d_t, R)) {
      CHECK_FALSE(dprsm_lookup(s.view, y, tolerance).lit);
      ++shadowed;
    } else if (behind < 0) {
      CHECK(dprsm_lookup(s.view, y, tolerance).lit);  // in front of the occluder
    }
  }
  CHECK(shadowed >= 5);
}

TEST_CASE("dprsm_lookup: a point in front of the floor texel's plane (a wall at a crease) is lit") {
  // The texel's centre shows the floor; a wall rising from the floor inside the texel's cone lies
  // in front of the floor's plane, nearer to the light than the centre by more than the
  // tolerance. Nothing between the light and that wall point: lit. The former rule, two-sided,
  // shadowed it.
  const int R = 32;
  const plane_dprsm<double> s(vec3<double>(0.2, 0.1, 1.0), vec3<double>(0, 0, -1), vec3<double>(0),
                              vec3<double>(0, 0, 1), R);
  const double tolerance = 0.02;
  int tested = 0;
  for (int t = 3; t < s.view.texel_count(); t += 11) {
    if (s.view.albedo[t] == vec3<double>(0)) continue;
    for (const vec2<double> xi : texel_grid_points(0.1)) {
      const vec3<double> w = s.direction(t, xi);
      const double d_p = s.plane_distance(w);
      if (!(d_p > 0) || -glm::dot(s.n, w) < 0.5 || s.view.texel_of_direction(w) != t) continue;
      const vec3<double> in_front = s.view.light.position + 0.7 * d_p * w;        // a wall point
      const vec3<double> behind = s.view.light.position + (1.1 * d_p + 0.05) * w;  // below the floor
      INFO("texel " << t << " xi " << xi.x << " " << xi.y);
      REQUIRE(dprsm_lookup(s.view, in_front, tolerance).texel == t);
      CHECK(dprsm_lookup(s.view, in_front, tolerance).lit);
      CHECK(dprsm_lookup(s.view, in_front, tolerance).in_front);
      CHECK_FALSE(dprsm_lookup(s.view, s.view.light.position + d_p * w, tolerance).in_front);  // on the floor
      CHECK_FALSE(dprsm_lookup(s.view, behind, tolerance).lit);
      CHECK_FALSE(dprsm_lookup(s.view, behind, tolerance).in_front);
      CHECK_FALSE(former_rule_lit(s.view, in_front, tolerance));
      ++tested;
    }
  }
  CHECK(tested > 500);
}

TEMPLATE_TEST_CASE("dprsm_lookup and direct_light: a grazing plane is lit across the whole texel", "[vpl]", float,
                   double) {
  using T = TestType;
  // A floor 0.03 below a light that looks along it; the texel that sees it at the most grazing
  // angle while all its points still meet it at cos(alpha) > 2e-3 (twice dprsm_plane_min_cos):
  // its depth spans several times the centre's. The former rule's direct-light window (a
  // footprint times 1/2 + tan(alpha), tan capped at 20) shadowed the texel's far and near parts.
  const int R = 128;
  // (The light's axis dips 0.0034 below the horizon, so that a texel row starts just below it.)
  const plane_dprsm<T> s(vec3<T>(0), glm::normalize(vec3<T>(1, 0, T(-0.0034))), vec3<T>(0, 0, T(-0.03)),
                         vec3<T>(0, 0, 1), R);
  int t = -1;
  T deepest = T(0);  // the largest ratio of the far and the near point's depths
  for (int k = 0; k < s.view.texel_count(); ++k) {
    if (s.view.albedo[k] == vec3<T>(T(0))) continue;
    T min_cos = T(1), max_depth = T(0), min_depth = std::numeric_limits<T>::max();
    for (const vec2<double> xi : texel_grid_points(0.02)) {
      const vec3<T> w = s.direction(k, vec2<T>(xi));
      if (s.view.texel_of_direction(w) != k) min_cos = T(0);  // a rim texel's corner beyond the disk
      min_cos = std::min(min_cos, -glm::dot(s.n, w));
      max_depth = std::max(max_depth, s.plane_distance(w));
      min_depth = std::min(min_depth, s.plane_distance(w));
    }
    if (min_cos > T(2e-3) && max_depth / min_depth > deepest) {
      deepest = max_depth / min_depth;
      t = k;
    }
  }
  REQUIRE(t >= 0);
  const T d_t = s.centre_distance(t);
  const T former_window = d_t * (T(4) / T(R)) * T(20.5) + T(1e-4) * d_t;
  int beyond_former = 0;
  for (const vec2<double> xi : texel_grid_points(0.02)) {
    const vec3<T> w = s.direction(t, vec2<T>(xi));
    const T d_p = s.plane_distance(w);
    REQUIRE(d_p > T(0));
    const vec3<T> y = s.view.light.position + d_p * w;
    INFO("xi " << xi.x << " " << xi.y << " depth " << d_p << " centre " << d_t);
    const dprsm_lookup_result r = dprsm_lookup(s.view, y, T(0));
    REQUIRE(r.texel == t);
    CHECK(r.lit);
    const gather_point<T> gp{y, vec3<T>(0, 0, 1), vec3<T>(T(0.7))};
    CHECK(direct_light(gp, s.view).x > T(0));
    if (std::abs(d_p - d_t) > former_window) ++beyond_former;
  }
  INFO("texel " << t << " depth from " << d_t << " times 1 / " << deepest << " to " << deepest);
  CHECK(beyond_former >= 5);
}

TEST_CASE("dprsm_lookup: where the plane cannot decide, the centre's depth does (one-sided)") {
  const int R = 32;
  const plane_dprsm<double> s(vec3<double>(0.2, 0.1, 1.0), vec3<double>(0, 0, -1), vec3<double>(0),
                              vec3<double>(0, 0, 1), R);
  const int t = s.view.texel_of_direction(vec3<double>(0.3, -0.2, -1));
  REQUIRE(s.view.albedo[t] != vec3<double>(0));
  const vec3<double> c = s.view.light.position;
  const double d_t = s.centre_distance(t);
  const vec3<double> w_t = (s.view.position[t] - c) / d_t;
  const double tolerance = 0.01;
  // d_y <= d_t + tolerance + slack(d_y), the slack proportional to d_y: the limit along w_t.
  const double limit = (d_t + tolerance) / (1 - dprsm_lookup_slack(1.0, R));
  // A zero normal; one turned away from the light (the plane meets the ray behind it); one across
  // the ray (cos(alpha) = 0); one within 0.05 degrees of it (below dprsm_plane_min_cos).
  const vec3<double> across = glm::normalize(glm::cross(w_t, vec3<double>(0, 1, 0)));
  const vec3<double> near_across = glm::normalize(across - 5e-4 * w_t);
  REQUIRE(-glm::dot(near_across, w_t) < dprsm_plane_min_cos<double>());
  REQUIRE(-glm::dot(near_across, w_t) > 0);
  const vec3<double> normals[] = {vec3<double>(0), -s.view.normal[t], across, near_across};
  for (int k = 0; k < 4; ++k) {
    std::vector<vec3<double>> normal = s.normal;
    normal[std::size_t(t)] = normals[k];
    dprsm_view<double> v = s.view;
    v.normal = normal.data();
    INFO("normal " << k);
    CHECK(dprsm_lookup(v, c + (d_t - 0.5) * w_t, tolerance).lit);  // in front: lit, however far
    CHECK(dprsm_lookup(v, c + d_t * w_t, tolerance).lit);
    CHECK(dprsm_lookup(v, c + (d_t + 0.99 * (limit - d_t)) * w_t, tolerance).lit);
    CHECK_FALSE(dprsm_lookup(v, c + (d_t + 1.01 * (limit - d_t)) * w_t, tolerance).lit);
  }
  // A NaN or negative tolerance: nothing is lit, not even the texel's own point.
  CHECK(dprsm_lookup(s.view, s.view.position[t], 0.0).lit);
  CHECK_FALSE(dprsm_lookup(s.view, s.view.position[t], std::numeric_limits<double>::quiet_NaN()).lit);
  CHECK_FALSE(dprsm_lookup(s.view, s.view.position[t], -1e-3).lit);
  // A point at infinity: its slack would be infinite too; unlit whatever the tolerance.
  const double inf = std::numeric_limits<double>::infinity();
  for (double tol : {0.0, 1.0, inf}) CHECK_FALSE(dprsm_lookup(s.view, vec3<double>(inf, 0, 0), tol).lit);
}

TEMPLATE_TEST_CASE("dprsm_hit_radiance: a hit whose surface the tracer knows reflects as that surface", "[vpl]", float,
                   double) {
  // A floor texel's cone holding a wall (the wall point lies in front of the floor's plane). Shaded
  // as the wall, L_o d1^2 / cos(alpha_wall) = rho I / pi for every wall point: the light of the
  // texel's solid angle, rho I Omega, is what its area reflects, as the texel's VPL carries. With
  // the floor's normal it would be cos(alpha_floor) / cos(alpha_wall) times that.
  using T = TestType;
  const int R = 32;
  const plane_dprsm<T> s(vec3<T>(T(0.2), T(0.1), T(1.0)), vec3<T>(0, 0, -1), vec3<T>(0), vec3<T>(0, 0, 1), R);
  const vec3<T> c = s.view.light.position;
  const T rho_i_over_pi = T(0.5) * T(1) / vplkit::vpl_pi<T>;  // the plane's albedo 0.5, I = 1
  int tested = 0;
  for (int t = 5; t < s.view.texel_count(); t += 13) {
    if (s.view.albedo[t] == vec3<T>(T(0))) continue;
    const vec3<T> w = s.direction(t, vec2<T>(T(0.4), T(0.6)));
    const T d_p = s.plane_distance(w);
    if (!(d_p > T(0)) || -glm::dot(s.n, w) < T(0.3) || s.view.texel_of_direction(w) != t) continue;
    const vec3<T> y = c + T(0.6) * d_p * w;  // in front of the floor
    // A wall through y whose normal leans 60 degrees from the ray (either winding).
    const vec3<T> side = glm::normalize(glm::cross(w, vec3<T>(0, 0, 1)));
    const vec3<T> n_wall = glm::normalize(T(-0.5) * w + T(0.866) * side);
    const dprsm_lookup_result lk = dprsm_lookup(s.view, y, T(0));
    INFO("texel " << t);
    REQUIRE((lk.texel == t && lk.lit && lk.in_front));
    for (const T sign : {T(1), T(-1)}) {
      ray_hit<T> h;
      h.hit = true;
      h.position = y;
      h.normal = sign * n_wall;
      const vec3<T> x = y + T(0.3) * n_wall + T(0.1) * side;  // on the wall's lit side
      const vec3<T> L = dprsm_hit_radiance(s.view, lk, x, h, T(0));
      const T d2 = glm::dot(y - c, y - c), cos_wall = glm::dot(n_wall, glm::normalize(c - y));
      CHECK(L.x * d2 / cos_wall == Approx(rho_i_over_pi).epsilon(1e-4));
      // from the wall's unlit side: nothing
      CHECK(dprsm_hit_radiance(s.view, lk, y - T(0.3) * n_wall, h, T(0)) == vec3<T>(T(0)));
      // the shading normal gives the cosine (turned to the geometric normal's lit side)
      h.shading_normal = -sign * glm::normalize(n_wall + T(0.2) * side);
      const T cos_s = glm::dot(glm::normalize(n_wall + T(0.2) * side), glm::normalize(c - y));
      CHECK(dprsm_hit_radiance(s.view, lk, x, h, T(0)).x * d2 / cos_s == Approx(rho_i_over_pi).epsilon(1e-4));
      // a tracer that cannot say (no normal): the texel's (the floor's) normal
      ray_hit<T> blind = h;
      blind.normal = blind.shading_normal = vec3<T>(T(0));
      const T cos_floor = glm::dot(s.n, glm::normalize(c - y));
      CHECK(dprsm_hit_radiance(s.view, lk, x, blind, T(0)).x * d2 / cos_floor == Approx(rho_i_over_pi).epsilon(1e-4));
    }
    ++tested;
  }
  CHECK(tested > 20);
}

TEST_CASE("dprsm_hit_radiance: a known surface on its texel's plane is lit from its own side, behind the plane too") {
  // The far face of a convex edge lies within the test's slack behind the near face's plane near
  // the edge, and a receiver below the near face's plane sees it: it reflects as its own surface.
  const int R = 32;
  const plane_dprsm<double> s(vec3<double>(0.2, 0.1, 1.0), vec3<double>(0, 0, -1), vec3<double>(0),
                              vec3<double>(0, 0, 1), R);
  const int t = s.view.texel_of_direction(vec3<double>(0.1, 0.05, -1));
  const vec3<double> w = glm::normalize(s.direction(t, vec2<double>(0.5, 0.5)));
  const vec3<double> y = s.view.light.position + s.plane_distance(w) * w;
  const dprsm_lookup_result lk = dprsm_lookup(s.view, y, 0.0);
  REQUIRE((lk.lit && !lk.in_front));
  ray_hit<double> h;
  h.hit = true;
  h.position = y;
  h.normal = vec3<double>(1, 0, 0);  // a wall through y, its lit side towards the light (-x)
  const vec3<double> c = s.view.light.position;
  const vec3<double> expected = reflected_radiance(c, s.view.light.intensity, y, vec3<double>(-1, 0, 0),
                                                   s.view.albedo[lk.texel]);
  REQUIRE(luminance(expected) > 0.0);
  CHECK(dprsm_hit_radiance(s.view, lk, y + vec3<double>(-0.2, 0, 0.2), h, 0.0) == expected);
  CHECK(dprsm_hit_radiance(s.view, lk, y + vec3<double>(-0.2, 0, -0.2), h, 0.0) == expected);  // below the floor
  CHECK(dprsm_hit_radiance(s.view, lk, y + vec3<double>(0.2, 0, 0.2), h, 0.0) == vec3<double>(0.0));  // unlit side
}
