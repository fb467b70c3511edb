// SPDX-License-Identifier: MIT
// Physics checks of the paraboloid texel solid angles and the VPL model against closed-form
// answers: the light's whole sphere of directions, energy conservation in closed scenes, the
// surface area seen through the texels, and one-bounce radiance inside a sphere.
// The brief's acceptance bound is 1% for R = 256; the measured errors are ~1e-4 (midpoint rule),
// so the checks below use 0.2% to catch regressions the 1% bound would let through.
#include <vplkit/paraboloid/light_frame.hpp>
#include <vplkit/paraboloid/texel_grid.hpp>
#include <vplkit/vpl/dprsm_raycast.hpp>
#include <vplkit/vpl/dprsm_view.hpp>
#include <vplkit/vpl/vpl.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <optional>
#include <vector>

using vplkit::vec3;

namespace {

const double pi = 3.14159265358979323846;

// Inside of a sphere: the far root of |o + t d - c|^2 = r^2, normal facing inwards.
template <class T>
struct sphere_scene {
  vec3<T> centre;
  T radius;
  vec3<T> albedo;
  std::optional<vplkit::dprsm_hit<T>> operator()(vec3<T> o, vec3<T> d) const {
    const vec3<double> oc = vec3<double>(o - centre), dd = vec3<double>(d);
    const double a = glm::dot(dd, dd), b = glm::dot(dd, oc);
    const double c = glm::dot(oc, oc) - double(radius) * double(radius);
    const double disc = b * b - a * c;
    if (!(disc >= 0.0)) return std::nullopt;
    const double t = (-b + std::sqrt(disc)) / a;
    if (!(t > 0.0)) return std::nullopt;
    const vec3<double> p = vec3<double>(o) + t * dd;
    const vec3<double> n = (vec3<double>(centre) - p) / double(radius);
    return vplkit::dprsm_hit<T>{vec3<T>(p), vec3<T>(n), albedo};
  }
};

// Inside of an axis-aligned box: exit point, normal facing inwards.
template <class T>
struct box_scene {
  vec3<T> lo, hi;
  vec3<T> albedo;
  std::optional<vplkit::dprsm_hit<T>> operator()(vec3<T> o, vec3<T> d) const {
    double t_exit = 1e300;
    int axis = -1;
    for (int k = 0; k < 3; ++k) {
      if (d[k] == T(0)) continue;
      const double bound = d[k] > T(0) ? double(hi[k]) : double(lo[k]);
      const double t = (bound - double(o[k])) / double(d[k]);
      if (t < t_exit) {
        t_exit = t;
        axis = k;
      }
    }
    if (axis < 0 || !(t_exit > 0.0)) return std::nullopt;
    vec3<double> p = vec3<double>(o) + t_exit * vec3<double>(d);
    vec3<T> n(0);
    n[axis] = d[axis] > T(0) ? T(-1) : T(1);
    return vplkit::dprsm_hit<T>{vec3<T>(p), n, albedo};
  }
};

struct dprsm_totals {
  vec3<double> flux{0.0};
  double area = 0.0;
  int valid = 0, hits = 0;
};

template <class T>
dprsm_totals totals(const vplkit::dprsm_view<T>& view) {
  dprsm_totals s;
  for (int i = 0; i < view.texel_count(); ++i) {
    if (!view.texel_valid(i)) continue;
    ++s.valid;
    const vplkit::vpl<T> v = view.vpl_at(i);
    s.flux += vec3<double>(v.flux);
    if (view.albedo[i] == vec3<T>(0)) continue;
    ++s.hits;
    const T d1 = glm::length(v.position - view.light.position);
    const T cos_a = vplkit::vpl_cos_alpha(view.light.position, v.position, v.normal);
    s.area += double(vplkit::vpl_patch_area(view.solid_angle(i), d1, cos_a));
  }
  return s;
}

// Exhaustive VPL sum at x (no visibility: the scenes are convex from the inside).
template <class T>
vec3<double> vpl_sum(const vplkit::dprsm_view<T>& view, vec3<T> x, vec3<T> n_x, vec3<T> rho_x) {
  vec3<double> L(0.0);
  for (int i = 0; i < view.texel_count(); ++i)
    L += vec3<double>(vplkit::vpl_contribution(x, n_x, rho_x, view.vpl_at(i), T(0)));
  return L;
}

// One-bounce radiance at x by deterministic cosine-weighted quadrature over the hemisphere
// (M x M strata, midpoints): the gathering estimator f / p1 = rho_x L_o(y).
template <class T, class Scene>
vec3<double> gather_quadrature(const Scene& scene, const vplkit::point_light<T>& light, vec3<T> x,
                               vec3<T> n_x, vec3<T> rho_x, int M) {
  const vplkit::light_frame<T> frame(x, n_x);
  vec3<double> sum(0.0);
  for (int j = 0; j < M; ++j)
    for (int i = 0; i < M; ++i) {
      const double u1 = (i + 0.5) / M, u2 = (j + 0.5) / M;
      const double r = std::sqrt(u1), phi = 2.0 * pi * u2;
      const vec3<T> local(T(r * std::cos(phi)), T(r * std::sin(phi)), T(std::sqrt(1.0 - u1)));
      const auto hit = scene(x, frame.to_world(local));
      if (!hit) continue;
      sum +=
          vec3<double>(rho_x * vplkit::reflected_radiance(light.position, light.intensity,
                                                          hit->position, hit->normal, hit->albedo));
    }
  return sum / double(M * M);
}

}  // namespace

TEST_CASE("physics: the valid texels of one face subtend 2 pi", "[vpl][physics]") {
  // Midpoint rule plus the jagged rim of the valid set; the bound is 0.5%.
  for (int R : {64, 256, 512}) {
    double front = 0.0, back = 0.0;
    for (int y = 0; y < R; ++y)
      for (int x = 0; x < R; ++x) {
        front += double(vplkit::texel_solid_angle<float>(x, y, R));
        back += vplkit::texel_solid_angle<double>(x, y, R);
      }
    const double rel_f = std::abs(front - 2 * pi) / (2 * pi);
    const double rel_b = std::abs(back - 2 * pi) / (2 * pi);
    INFO("R " << R << ": float sum " << front << " (rel. error " << rel_f << "), double sum "
              << back << " (rel. error " << rel_b << ")");
    CHECK(rel_f < 0.005);
    CHECK(rel_b < 0.005);
  }
}

TEMPLATE_TEST_CASE("physics: closed sphere around the light reflects rho times 4 pi I",
                   "[vpl][physics]", float, double) {
  using T = TestType;
  const sphere_scene<T> scene{vec3<T>(T(0.1), T(0.2), T(-0.3)), T(2),
                              vec3<T>(T(0.8), T(0.5), T(0.2))};
  // off-centre light, arbitrary front axis
  const auto light = vplkit::make_point_light(vec3<T>(T(0.6), T(-0.4), T(0.5)), vec3<T>(3, 2, 1),
                                              vec3<T>(T(0.3), 1, T(-0.2)));
  std::vector<vec3<T>> P, N, A;
  const auto view = vplkit::render_dprsm(light, 256, scene, P, N, A);
  const dprsm_totals s = totals(view);
  REQUIRE(s.hits == s.valid);  // every valid texel sees the sphere
  for (int k = 0; k < 3; ++k) {
    const double expected = 4 * pi * double(light.intensity[k]) * double(scene.albedo[k]);
    INFO("channel " << k << ": total flux " << s.flux[k] << ", expected " << expected);
    CHECK(s.flux[k] == Approx(expected).epsilon(0.002));
  }
  const double r = double(scene.radius);
  INFO("sum of patch areas " << s.area << ", sphere area " << 4 * pi * r * r);
  CHECK(s.area == Approx(4 * pi * r * r).epsilon(0.002));
}

TEMPLATE_TEST_CASE("physics: closed box around the light reflects rho times 4 pi I",
                   "[vpl][physics]", float, double) {
  using T = TestType;
  const box_scene<T> scene{vec3<T>(-1, -2, T(-0.5)), vec3<T>(3, 1, T(2.5)),
                           vec3<T>(T(0.7), T(0.4), T(0.9))};
  const auto light = vplkit::make_point_light(vec3<T>(T(0.2), T(0.1), T(0.4)), vec3<T>(5, 1, 2),
                                              vec3<T>(-1, T(0.5), T(0.25)));
  std::vector<vec3<T>> P, N, A;
  const auto view = vplkit::render_dprsm(light, 256, scene, P, N, A);
  const dprsm_totals s = totals(view);
  REQUIRE(s.hits == s.valid);
  for (int k = 0; k < 3; ++k) {
    const double expected = 4 * pi * double(light.intensity[k]) * double(scene.albedo[k]);
    INFO("channel " << k << ": total flux " << s.flux[k] << ", expected " << expected);
    CHECK(s.flux[k] == Approx(expected).epsilon(0.002));
  }
  const double area = 2.0 * (4.0 * 3.0 + 3.0 * 3.0 + 3.0 * 4.0);
  INFO("sum of patch areas " << s.area << ", box area " << area);
  CHECK(s.area == Approx(area).epsilon(0.002));
}

TEMPLATE_TEST_CASE("physics: one bounce inside a sphere is rho^2 I / (pi r^2) everywhere",
                   "[vpl][physics]", float, double) {
  using T = TestType;
  // Between two points of a sphere cos(theta1) = cos(theta2) = d / 2r, so the geometry term is
  // the constant 1 / (4 pi r^2): wherever the light is, every x on the sphere receives
  // L = (rho / pi) * sum(Phi) / (4 pi r^2) = rho^2 I / (pi r^2) from the exhaustive VPL sum,
  // and the gathering integral of reflected_radiance gives the same.
  const sphere_scene<T> scene{vec3<T>(0), T(1.5), vec3<T>(T(0.6))};
  const auto light =
      vplkit::make_point_light(vec3<T>(T(-0.3), T(0.5), T(0.2)), vec3<T>(2), vec3<T>(0, 0, -1));
  std::vector<vec3<T>> P, N, A;
  const auto view = vplkit::render_dprsm(light, 256, scene, P, N, A);
  const double r = 1.5, rho = 0.6;
  const double expected = rho * rho * 2.0 / (pi * r * r);
  const vec3<double> dirs[] = {{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {0.48, -0.6, 0.64}};
  for (const vec3<double>& u : dirs) {
    const vec3<T> x = vec3<T>(u * r), n_x = vec3<T>(-u);
    const vec3<double> L_vpl = vpl_sum(view, x, n_x, scene.albedo);
    const vec3<double> L_gather = gather_quadrature(scene, light, x, n_x, scene.albedo, 256);
    INFO("x " << u.x << " " << u.y << " " << u.z << ": VPL sum " << L_vpl.x << ", gathering "
              << L_gather.x << ", expected " << expected);
    CHECK(L_vpl.x == Approx(expected).epsilon(0.002));
    CHECK(L_gather.x == Approx(expected).epsilon(0.002));
  }
}

TEST_CASE("physics: VPL sum and gathering integral agree at a box floor", "[vpl][physics]") {
  // No closed form here: the two estimands of docs/math.md section 8 (VPL sum vs continuous
  // one-bounce integral) must agree to discretisation error at a point far from the box edges.
  using T = double;
  const box_scene<T> scene{vec3<T>(-1, -2, -0.5), vec3<T>(3, 1, 2.5), vec3<T>(0.7, 0.4, 0.9)};
  const auto light =
      vplkit::make_point_light(vec3<T>(0.2, 0.1, 0.4), vec3<T>(5, 1, 2), vec3<T>(-1, 0.5, 0.25));
  std::vector<vec3<T>> P, N, A;
  const auto view = vplkit::render_dprsm(light, 256, scene, P, N, A);
  const vec3<T> x(1.0, -0.5, -0.5), n_x(0, 0, 1);  // centre of the floor
  const vec3<double> L_vpl = vpl_sum(view, x, n_x, scene.albedo);
  const vec3<double> L_gather = gather_quadrature(scene, light, x, n_x, scene.albedo, 512);
  for (int k = 0; k < 3; ++k) {
    INFO("channel " << k << ": VPL sum " << L_vpl[k] << ", gathering " << L_gather[k]);
    CHECK(L_vpl[k] == Approx(L_gather[k]).epsilon(0.002));
  }
}
