// SPDX-License-Identifier: MIT
#include <vplkit/vpl/luminance.hpp>
#include <vplkit/vpl/vpl.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <random>

using vplkit::vec3;

namespace {
const double pi = 3.14159265358979323846;

template <class T>
vec3<T> random_unit(std::mt19937_64& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  const vec3<double> v(n(rng), n(rng), n(rng));
  return vec3<T>(v / glm::length(v));
}

// Two points uniform in [-half, half]^3 and a random unit normal at each, drawn in that order.
template <class T>
struct oriented_pair {
  vec3<T> x, nx, y, ny;
};

template <class T>
oriented_pair<T> random_oriented_pair(std::mt19937_64& rng, double half) {
  std::uniform_real_distribution<double> u(-half, half);
  oriented_pair<T> p;
  for (int k = 0; k < 3; ++k) p.x[k] = T(u(rng));
  for (int k = 0; k < 3; ++k) p.y[k] = T(u(rng));
  p.nx = random_unit<T>(rng);
  p.ny = random_unit<T>(rng);
  return p;
}
}  // namespace

TEMPLATE_TEST_CASE("vpl: luminance uses the eq. 6 weights", "[vpl]", float, double) {
  using T = TestType;
  CHECK(vplkit::luminance(vec3<T>(1, 0, 0)) == Approx(0.299));
  CHECK(vplkit::luminance(vec3<T>(0, 1, 0)) == Approx(0.587));
  CHECK(vplkit::luminance(vec3<T>(0, 0, 1)) == Approx(0.114));
  CHECK(vplkit::luminance(vec3<T>(2, 2, 2)) == Approx(2.0));
  CHECK(vplkit::luminance(vec3<T>(0, 0, 0)) == T(0));
}

TEMPLATE_TEST_CASE("vpl: flux is albedo times intensity times solid angle per channel", "[vpl]",
                   float, double) {
  using T = TestType;
  const vec3<T> phi = vplkit::vpl_flux(vec3<T>(T(0.5), T(0.25), 1), vec3<T>(2, 4, 8), T(0.125));
  CHECK(phi.x == Approx(0.125));
  CHECK(phi.y == Approx(0.125));
  CHECK(phi.z == Approx(1.0));
  CHECK(vplkit::vpl_flux(vec3<T>(0), vec3<T>(1), T(1)) == vec3<T>(0));
}

TEMPLATE_TEST_CASE("vpl: contribution matches a hand-computed configuration", "[vpl]", float,
                   double) {
  using T = TestType;
  // x at the origin facing +z; VPL at (1, 0, 1) facing -x. d2^2 = 2, both cosines 1/sqrt(2):
  // G = (1/2) / (2 pi) = 1 / (4 pi); L = (rho_x / pi) * Phi * G = (1, 1, 8) / (4 pi^2).
  const vplkit::vpl<T> v{vec3<T>(1, 0, 1), vec3<T>(-1, 0, 0), vec3<T>(2, 4, 8)};
  const vec3<T> rho_x(T(0.5), T(0.25), T(1));
  const vec3<T> L = vplkit::vpl_contribution(vec3<T>(0), vec3<T>(0, 0, 1), rho_x, v, T(0));
  CHECK(L.x == Approx(1.0 / (4 * pi * pi)));
  CHECK(L.y == Approx(1.0 / (4 * pi * pi)));
  CHECK(L.z == Approx(8.0 / (4 * pi * pi)));
  CHECK(vplkit::vpl_geometry_term(vec3<T>(0), vec3<T>(0, 0, 1), v.position, v.normal, T(0)) ==
        Approx(1.0 / (4 * pi)));
  // dmin below d2 changes nothing; above it replaces d2: G = (1/2) / (pi * 4)
  CHECK(vplkit::vpl_contribution(vec3<T>(0), vec3<T>(0, 0, 1), rho_x, v, T(1.4)).z ==
        Approx(8.0 / (4 * pi * pi)));
  CHECK(vplkit::vpl_contribution(vec3<T>(0), vec3<T>(0, 0, 1), rho_x, v, T(2)).z ==
        Approx(8.0 * 0.5 / (4 * pi * pi)));
  // a head-on pair at distance 3: G = 1 / (9 pi)
  CHECK(vplkit::vpl_geometry_term(vec3<T>(0), vec3<T>(0, 1, 0), vec3<T>(0, 3, 0), vec3<T>(0, -1, 0),
                                  T(0)) == Approx(1.0 / (9 * pi)));
}

TEMPLATE_TEST_CASE("vpl: geometry term is symmetric in the two points", "[vpl]", float, double) {
  using T = TestType;
  std::mt19937_64 rng(31);
  int nonzero = 0;
  for (int i = 0; i < 20000; ++i) {
    const auto [x, nx, y, ny] = random_oriented_pair<T>(rng, 2.0);
    const T dmin = T(i % 2 == 0 ? 0.0 : 0.3);
    const T a = vplkit::vpl_geometry_term(x, nx, y, ny, dmin);
    const T b = vplkit::vpl_geometry_term(y, ny, x, nx, dmin);
    REQUIRE(a == Approx(b).epsilon(1e-5).margin(1e-30));
    REQUIRE(a >= T(0));
    nonzero += a > T(0) ? 1 : 0;
  }
  CHECK(nonzero > 4000);  // about a quarter of random pairs face each other
}

TEMPLATE_TEST_CASE("vpl: back-facing pairs contribute nothing", "[vpl]", float, double) {
  using T = TestType;
  const vec3<T> x(0), nx(0, 0, 1), rho(1);
  // VPL above x but facing up (away from x)
  CHECK(vplkit::vpl_contribution(x, nx, rho, vplkit::vpl<T>{{0, 0, 1}, {0, 0, 1}, {1, 1, 1}},
                                 T(0)) == vec3<T>(0));
  // VPL below x's tangent plane, facing x
  CHECK(vplkit::vpl_contribution(x, nx, rho, vplkit::vpl<T>{{0, 0, -1}, {0, 0, 1}, {1, 1, 1}},
                                 T(0)) == vec3<T>(0));
  // grazing: VPL in x's tangent plane
  CHECK(vplkit::vpl_contribution(x, nx, rho, vplkit::vpl<T>{{1, 0, 0}, {-1, 0, 0}, {1, 1, 1}},
                                 T(0)) == vec3<T>(0));
}

TEMPLATE_TEST_CASE("vpl: normals of any length give the same contribution", "[vpl]", float,
                   double) {
  using T = TestType;
  std::mt19937_64 rng(32);
  for (int i = 0; i < 2000; ++i) {
    const auto [x, nx, y, ny] = random_oriented_pair<T>(rng, 2.0);
    const vplkit::vpl<T> v{y, ny, vec3<T>(1, 2, 3)};
    const vec3<T> ref = vplkit::vpl_contribution(x, nx, vec3<T>(T(0.7)), v, T(0.1));
    for (T s : {T(1e-20), T(0.3), T(7), T(1e20)}) {
      const vplkit::vpl<T> vs{y, ny * s, vec3<T>(1, 2, 3)};
      const vec3<T> L = vplkit::vpl_contribution(x, nx / s, vec3<T>(T(0.7)), vs, T(0.1));
      // relative 1e-5, plus an absolute margin for cosines near 0 (a few ulp of cos times the
      // largest possible value rho Phi / (pi^2 dmin^2) ~ 21)
      const double margin = 100.0 * double(std::numeric_limits<T>::epsilon());
      REQUIRE(L.x == Approx(ref.x).epsilon(1e-5).margin(margin));
      REQUIRE(L.z == Approx(ref.z).epsilon(1e-5).margin(margin));
    }
  }
}

TEMPLATE_TEST_CASE("vpl: patch area is solid angle times d1^2 over cos(alpha)", "[vpl]", float,
                   double) {
  using T = TestType;
  CHECK(vplkit::vpl_patch_area(T(0.01), T(3), T(1)) == Approx(0.09));
  CHECK(vplkit::vpl_patch_area(T(0.01), T(3), T(0.5)) == Approx(0.18));
  // grazing / back-facing: cos(alpha) raised to vpl_min_cos_alpha, finite
  CHECK(vplkit::vpl_patch_area(T(0.01), T(3), T(0)) == Approx(0.09 / 1e-6));
  CHECK(vplkit::vpl_patch_area(T(0.01), T(3), T(-0.5)) == Approx(0.09 / 1e-6));
  CHECK(vplkit::vpl_cos_alpha(vec3<T>(0, 0, 2), vec3<T>(0), vec3<T>(0, 0, 5)) == Approx(1.0));
  CHECK(vplkit::vpl_cos_alpha(vec3<T>(2, 0, 2), vec3<T>(0), vec3<T>(0, 0, 1)) ==
        Approx(std::sqrt(0.5)));
  CHECK(vplkit::vpl_cos_alpha(vec3<T>(0, 0, -2), vec3<T>(0), vec3<T>(0, 0, 1)) == T(0));
}

TEMPLATE_TEST_CASE("vpl: reflected radiance of a lit diffuse point", "[vpl]", float, double) {
  using T = TestType;
  // light 2 above y, head-on: L_o = rho I / (pi * 4)
  const vec3<T> L = vplkit::reflected_radiance(vec3<T>(0, 0, 2), vec3<T>(8, 4, 2), vec3<T>(0),
                                               vec3<T>(0, 0, 1), vec3<T>(T(0.5)));
  CHECK(L.x == Approx(1.0 / pi));
  CHECK(L.y == Approx(0.5 / pi));
  CHECK(L.z == Approx(0.25 / pi));
  // 45 degrees at distance sqrt(8): cos = 1/sqrt(2), d1^2 = 8
  const vec3<T> L45 = vplkit::reflected_radiance(vec3<T>(2, 0, 2), vec3<T>(8), vec3<T>(0),
                                                 vec3<T>(0, 0, 3), vec3<T>(1));
  CHECK(L45.x == Approx(std::sqrt(0.5) / pi));
  // light behind the surface
  CHECK(vplkit::reflected_radiance(vec3<T>(0, 0, -2), vec3<T>(8), vec3<T>(0), vec3<T>(0, 0, 1),
                                   vec3<T>(1)) == vec3<T>(0));
}

TEMPLATE_TEST_CASE("vpl: flux equals pi times exitant radiance times patch area", "[vpl]", float,
                   double) {
  using T = TestType;
  // Lambertian patch: Phi = pi L_o A. Ties vpl_flux, reflected_radiance and vpl_patch_area
  // together (the MIS pdf conversion relies on this identity).
  std::mt19937_64 rng(33);
  std::uniform_real_distribution<double> u(-3.0, 3.0);
  for (int i = 0; i < 5000; ++i) {
    const vec3<T> c(T(u(rng)), T(u(rng)), T(u(rng))), y(T(u(rng)), T(u(rng)), T(u(rng)));
    vec3<T> n = random_unit<T>(rng);
    if (glm::dot(n, c - y) < T(0)) n = -n;
    const T cos_a = vplkit::vpl_cos_alpha(c, y, n);
    if (cos_a < T(0.01)) continue;
    const vec3<T> I(1, 2, 3), rho(T(0.2), T(0.5), T(0.9));
    const T omega = T(1e-4);
    const vec3<T> phi = vplkit::vpl_flux(rho, I, omega);
    const T area = vplkit::vpl_patch_area(omega, glm::length(c - y), cos_a);
    const vec3<T> from_radiance = T(pi) * vplkit::reflected_radiance(c, I, y, n, rho) * area;
    REQUIRE(from_radiance.x == Approx(phi.x).epsilon(1e-4));
    REQUIRE(from_radiance.z == Approx(phi.z).epsilon(1e-4));
  }
}

TEMPLATE_TEST_CASE("vpl: at a gather point with two normals, the shading cosine above the geometric surface",
                   "[vpl]", float, double) {
  using T = TestType;
  std::mt19937_64 rng(41);
  int above_both = 0, below_geometric = 0, below_shading = 0;
  for (int i = 0; i < 2000; ++i) {
    const vec3<T> x = random_unit<T>(rng), n = random_unit<T>(rng);
    vec3<T> ns = random_unit<T>(rng);
    if (glm::dot(ns, n) < T(0)) ns = -ns;  // the G-buffer's convention: n_s on n's side
    const vplkit::vpl<T> v{x + T(2) * random_unit<T>(rng), random_unit<T>(rng), vec3<T>(1, 2, 3)};
    const vplkit::gather_point<T> gp{x, n, vec3<T>(T(0.5)), ns};
    const vec3<T> w = v.position - x;
    const vec3<T> c = vplkit::vpl_contribution(gp, v, T(0.1));
    if (glm::dot(n, w) <= T(0)) {
      ++below_geometric;
      CHECK(c == vec3<T>(0));  // even where n_s faces y
    } else {
      CHECK(c == vplkit::vpl_contribution(x, ns, gp.albedo, v, T(0.1)));
      if (glm::dot(ns, w) <= T(0)) {
        ++below_shading;
        CHECK(c == vec3<T>(0));
      } else if (c.x > T(0)) {
        ++above_both;
      }
    }
    // No shading normal (or the geometric one again): the one-normal contribution, bit for bit.
    const vplkit::gather_point<T> one{x, n, vec3<T>(T(0.5))};
    const vplkit::gather_point<T> same{x, n, vec3<T>(T(0.5)), n};
    const vec3<T> c1 = vplkit::vpl_contribution(x, n, one.albedo, v, T(0.1));
    CHECK(vplkit::vpl_contribution(one, v, T(0.1)) == c1);
    CHECK(vplkit::vpl_contribution(same, v, T(0.1)) == c1);
  }
  CHECK(above_both > 200);
  CHECK(below_geometric > 200);
  CHECK(below_shading > 50);
}
