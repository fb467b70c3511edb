// SPDX-License-Identifier: MIT
#include <vplkit/paraboloid/paraboloid.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <random>

using vplkit::paraboloid_back;
using vplkit::paraboloid_front;
using vplkit::vec2;
using vplkit::vec3;

namespace {

template <class T>
vec3<T> random_direction(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double z = 1.0 - 2.0 * u(rng), phi = 2.0 * 3.14159265358979323846 * u(rng);
  const double s = std::sqrt(std::max(0.0, 1.0 - z * z));
  return vec3<T>(T(s * std::cos(phi)), T(s * std::sin(phi)), T(z));
}

template <class T>
vec2<T> random_uv_in_disk(std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (;;) {
    const vec2<T> p(T(u(rng)), T(u(rng)));
    if (glm::dot(p, p) <= T(1)) return p;
  }
}

template <class T>
T max_abs_diff(vec3<T> a, vec3<T> b) {
  return std::max(std::abs(a.x - b.x), std::max(std::abs(a.y - b.y), std::abs(a.z - b.z)));
}

}  // namespace

TEMPLATE_TEST_CASE("paraboloid: the poles map to the centres of their faces", "[paraboloid]", float,
                   double) {
  using T = TestType;
  const auto f = vplkit::paraboloid_from_direction(vec3<T>(0, 0, 1));
  CHECK(f.face == paraboloid_front);
  CHECK(f.uv == vec2<T>(0, 0));
  const auto b = vplkit::paraboloid_from_direction(vec3<T>(0, 0, -1));
  CHECK(b.face == paraboloid_back);
  CHECK(b.uv == vec2<T>(0, 0));
  CHECK(vplkit::paraboloid_to_direction(paraboloid_front, vec2<T>(0, 0)) == vec3<T>(0, 0, 1));
  CHECK(vplkit::paraboloid_to_direction(paraboloid_back, vec2<T>(0, 0)) == vec3<T>(0, 0, -1));
}

TEMPLATE_TEST_CASE("paraboloid: front covers z >= 0 and back z < 0", "[paraboloid]", float,
                   double) {
  using T = TestType;
  std::mt19937_64 rng(11);
  for (int i = 0; i < 20000; ++i) {
    const vec3<T> d = random_direction<T>(rng);
    const auto p = vplkit::paraboloid_from_direction(d);
    REQUIRE(p.face == (d.z >= T(0) ? paraboloid_front : paraboloid_back));
    REQUIRE(glm::dot(p.uv, p.uv) <= T(1));
  }
}

TEMPLATE_TEST_CASE("paraboloid: direction -> uv -> direction round trip", "[paraboloid]", float,
                   double) {
  using T = TestType;
  const T eps = std::numeric_limits<T>::epsilon();
  std::mt19937_64 rng(12);
  T worst = 0;
  for (int i = 0; i < 200000; ++i) {
    const vec3<T> d = random_direction<T>(rng);
    const auto p = vplkit::paraboloid_from_direction(d);
    const vec3<T> back = vplkit::paraboloid_to_direction(p.face, p.uv);
    worst = std::max(worst, max_abs_diff(back, glm::normalize(d)));
  }
  INFO("worst component error " << worst << " = " << worst / eps << " eps");
  CHECK(worst <= T(8) * eps);
}

TEMPLATE_TEST_CASE("paraboloid: uv -> direction -> uv round trip on both faces", "[paraboloid]",
                   float, double) {
  using T = TestType;
  const T eps = std::numeric_limits<T>::epsilon();
  std::mt19937_64 rng(13);
  T worst = 0;
  for (int face = 0; face < 2; ++face)
    for (int i = 0; i < 100000; ++i) {
      const vec2<T> uv = random_uv_in_disk<T>(rng);
      const vec3<T> d = vplkit::paraboloid_to_direction(face, uv);
      const auto p = vplkit::paraboloid_from_direction(d);
      // Only a direction exactly on the rim (z == 0) may switch face; the uv is then the same.
      if (d.z != T(0)) REQUIRE(p.face == face);
      worst = std::max(worst, std::max(std::abs(p.uv.x - uv.x), std::abs(p.uv.y - uv.y)));
    }
  INFO("worst uv error " << worst / eps << " eps");
  CHECK(worst <= T(8) * eps);
}

TEMPLATE_TEST_CASE("paraboloid: to_direction returns unit vectors", "[paraboloid]", float, double) {
  using T = TestType;
  const T eps = std::numeric_limits<T>::epsilon();
  std::mt19937_64 rng(14);
  for (int face = 0; face < 2; ++face)
    for (int i = 0; i < 50000; ++i) {
      const vec3<T> d = vplkit::paraboloid_to_direction(face, random_uv_in_disk<T>(rng));
      REQUIRE(std::abs(glm::length(d) - T(1)) <= T(4) * eps);
    }
}

TEMPLATE_TEST_CASE("paraboloid: a direction of any length maps like its normalisation",
                   "[paraboloid]", float, double) {
  using T = TestType;
  std::mt19937_64 rng(15);
  for (int i = 0; i < 2000; ++i) {
    const vec3<T> d = random_direction<T>(rng);
    const auto ref = vplkit::paraboloid_from_direction(d);
    for (T scale : {T(1e-30), T(1e-3), T(3.7), T(1e30)}) {
      const auto p = vplkit::paraboloid_from_direction(d * scale);
      REQUIRE(p.face == ref.face);
      REQUIRE(p.uv.x == Approx(ref.uv.x).margin(1e-6));
      REQUIRE(p.uv.y == Approx(ref.uv.y).margin(1e-6));
    }
  }
}

TEMPLATE_TEST_CASE("paraboloid: seam convention - the back face is not mirrored", "[paraboloid]",
                   float, double) {
  using T = TestType;
  std::mt19937_64 rng(16);
  for (int i = 0; i < 5000; ++i) {
    vec3<T> d = random_direction<T>(rng);
    d.z = std::abs(d.z);
    if (d.z == T(0)) continue;
    // The mirror image through the rim plane has the same uv on the other face.
    const auto f = vplkit::paraboloid_from_direction(d);
    const auto b = vplkit::paraboloid_from_direction(vec3<T>(d.x, d.y, -d.z));
    REQUIRE(f.face == paraboloid_front);
    REQUIRE(b.face == paraboloid_back);
    REQUIRE(f.uv == b.uv);
  }
  // On the rim both inverse maps give the same direction: the maps join continuously.
  for (int i = 0; i < 1000; ++i) {
    const double a = 2.0 * 3.14159265358979323846 * double(i) / 1000.0;
    const vec2<T> uv(T(std::cos(a)), T(std::sin(a)));
    const vec2<T> rim = vplkit::paraboloid_clamp_to_disk(uv);
    const vec3<T> df = vplkit::paraboloid_to_direction(paraboloid_front, rim);
    const vec3<T> db = vplkit::paraboloid_to_direction(paraboloid_back, rim);
    REQUIRE(max_abs_diff(df, db) <= T(8) * std::numeric_limits<T>::epsilon());
  }
}

TEMPLATE_TEST_CASE("paraboloid: the map is continuous across the seam", "[paraboloid]", float,
                   double) {
  using T = TestType;
  for (int i = 0; i < 5000; ++i) {
    const double a = 2.0 * 3.14159265358979323846 * double(i) / 5000.0;
    const T x = T(std::cos(a)), y = T(std::sin(a));
    const auto rim = vplkit::paraboloid_from_direction(vec3<T>(x, y, T(0)));
    for (T delta : {T(1e-2), T(1e-4), T(1e-6)}) {
      const auto above = vplkit::paraboloid_from_direction(vec3<T>(x, y, delta));
      const auto below = vplkit::paraboloid_from_direction(vec3<T>(x, y, -delta));
      REQUIRE(above.face == paraboloid_front);
      REQUIRE(below.face == paraboloid_back);
      // Equal uv on both sides (the convention), and within O(delta) of the rim point.
      REQUIRE(std::abs(above.uv.x - below.uv.x) <= T(4) * std::numeric_limits<T>::epsilon());
      REQUIRE(std::abs(above.uv.y - below.uv.y) <= T(4) * std::numeric_limits<T>::epsilon());
      REQUIRE(glm::length(above.uv - rim.uv) <=
              T(1.01) * delta + T(4) * std::numeric_limits<T>::epsilon());
      const T r2 = glm::dot(above.uv, above.uv);
      REQUIRE(r2 <= T(1));
      REQUIRE(r2 >= T(1) - T(2.01) * delta - T(4) * std::numeric_limits<T>::epsilon());
    }
  }
}

TEST_CASE("paraboloid: Jacobian 4 / (1 + r2)^2 matches the mapping", "[paraboloid]") {
  std::mt19937_64 rng(18);
  const double h = 1e-6;
  for (int face = 0; face < 2; ++face)
    for (int i = 0; i < 2000; ++i) {
      vec2<double> uv = random_uv_in_disk<double>(rng) * 0.999;
      const vec3<double> du = (vplkit::paraboloid_to_direction(face, uv + vec2<double>(h, 0)) -
                               vplkit::paraboloid_to_direction(face, uv - vec2<double>(h, 0))) /
                              (2 * h);
      const vec3<double> dv = (vplkit::paraboloid_to_direction(face, uv + vec2<double>(0, h)) -
                               vplkit::paraboloid_to_direction(face, uv - vec2<double>(0, h))) /
                              (2 * h);
      const double numeric = glm::length(glm::cross(du, dv));
      REQUIRE(numeric == Approx(vplkit::paraboloid_jacobian(uv)).epsilon(1e-6));
    }
}

TEMPLATE_TEST_CASE("paraboloid: clamp_to_disk leaves points inside the disk untouched",
                   "[paraboloid]", float, double) {
  using T = TestType;
  std::mt19937_64 rng(19);
  for (int i = 0; i < 10000; ++i) {
    const vec2<T> uv = random_uv_in_disk<T>(rng);
    REQUIRE(vplkit::paraboloid_clamp_to_disk(uv) == uv);
  }
  CHECK(vplkit::paraboloid_clamp_to_disk(vec2<T>(1, 0)) == vec2<T>(1, 0));
  const vec2<T> out = vplkit::paraboloid_clamp_to_disk(vec2<T>(3, 4));
  CHECK(glm::dot(out, out) <= T(1));
  CHECK(out.x == Approx(0.6));
  CHECK(out.y == Approx(0.8));
}
