// SPDX-License-Identifier: MIT
#include <vplkit/core/error.hpp>
#include <vplkit/paraboloid/light_frame.hpp>
#include <vplkit/paraboloid/paraboloid.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

using vplkit::vec2;
using vplkit::vec3;

namespace {

template <class T>
std::vector<vec3<T>> test_axes() {
  std::vector<vec3<T>> axes = {{1, 0, 0},
                               {-1, 0, 0},
                               {0, 1, 0},
                               {0, -1, 0},
                               {0, 0, 1},
                               {0, 0, -1},
                               {0, 0, -5},
                               {T(1e-7), 0, -1},
                               {0, T(-1e-20), -1},
                               {T(1e-4), T(1e-4), -1},
                               {1, 1, 1},
                               {0, 0, T(1e-30)},
                               {T(-3e30), T(2e30), T(1e30)}};
  std::mt19937_64 rng(21);
  std::normal_distribution<double> n(0.0, 1.0);
  for (int i = 0; i < 2000; ++i) axes.push_back(vec3<T>(T(n(rng)), T(n(rng)), T(n(rng))));
  return axes;
}

}  // namespace

TEMPLATE_TEST_CASE("light frame: default frame is the identity at the origin", "[paraboloid]",
                   float, double) {
  using T = TestType;
  const vplkit::light_frame<T> f;
  const vec3<T> d(T(0.25), T(-2), T(7));
  CHECK(f.to_light(d) == d);
  CHECK(f.to_world(d) == d);
  CHECK(f.to_light_point(d) == d);
}

TEMPLATE_TEST_CASE("light frame: any front axis gives a right-handed orthonormal frame",
                   "[paraboloid]", float, double) {
  using T = TestType;
  const T tol = T(8) * std::numeric_limits<T>::epsilon();
  for (const vec3<T>& axis : test_axes<T>()) {
    const vplkit::light_frame<T> f(vec3<T>(1, 2, 3), axis);
    INFO("axis " << axis.x << " " << axis.y << " " << axis.z);
    REQUIRE(std::abs(glm::length(f.axis_x) - T(1)) <= tol);
    REQUIRE(std::abs(glm::length(f.axis_y) - T(1)) <= tol);
    REQUIRE(std::abs(glm::length(f.axis_z) - T(1)) <= tol);
    REQUIRE(std::abs(glm::dot(f.axis_x, f.axis_y)) <= tol);
    REQUIRE(std::abs(glm::dot(f.axis_y, f.axis_z)) <= tol);
    REQUIRE(std::abs(glm::dot(f.axis_z, f.axis_x)) <= tol);
    REQUIRE(glm::length(glm::cross(f.axis_x, f.axis_y) - f.axis_z) <= tol);
    // axis_z is the normalised front axis
    const vec3<double> a(axis), expected = a / glm::length(a);
    REQUIRE(glm::length(vec3<double>(f.axis_z) - expected) <= double(tol));
  }
}

TEMPLATE_TEST_CASE("light frame: to_light and to_world are inverse rotations", "[paraboloid]",
                   float, double) {
  using T = TestType;
  const T tol = T(16) * std::numeric_limits<T>::epsilon();
  std::mt19937_64 rng(22);
  std::normal_distribution<double> n(0.0, 1.0);
  for (const vec3<T>& axis : test_axes<T>()) {
    const vec3<T> c(T(n(rng)), T(n(rng)), T(n(rng)));
    const vplkit::light_frame<T> f(c, axis);
    // (unit_or_zero: axes of length 1e-30 or 1e30 overflow glm::length in float)
    REQUIRE(glm::length(vplkit::unit_or_zero(f.to_light(axis)) - vec3<T>(0, 0, 1)) <= tol);
    const vec3<T> d(T(n(rng)), T(n(rng)), T(n(rng)));
    REQUIRE(glm::length(f.to_world(f.to_light(d)) - d) <= tol * glm::length(d));
    REQUIRE(glm::length(f.to_light(f.to_world(d)) - d) <= tol * glm::length(d));
    REQUIRE(std::abs(glm::length(f.to_light(d)) - glm::length(d)) <= tol * glm::length(d));
    const vec3<T> p = c + d;
    REQUIRE(glm::length(f.to_light_point(p) - f.to_light(d)) <= tol * T(8));
    REQUIRE(glm::length(f.to_world_point(f.to_light_point(p)) - p) <= tol * T(8));
  }
}

TEMPLATE_TEST_CASE("light frame: the front paraboloid is centred on the front axis", "[paraboloid]",
                   float, double) {
  using T = TestType;
  for (const vec3<T>& axis : test_axes<T>()) {
    const vplkit::light_frame<T> f(vec3<T>(0), axis);
    const auto front = vplkit::paraboloid_from_direction(f.to_light(axis));
    const auto back = vplkit::paraboloid_from_direction(f.to_light(-axis));
    REQUIRE(front.face == vplkit::paraboloid_front);
    REQUIRE(back.face == vplkit::paraboloid_back);
    REQUIRE(glm::length(front.uv) <= T(1e-5));
    REQUIRE(glm::length(back.uv) <= T(1e-5));
  }
}

TEMPLATE_TEST_CASE("light frame: rejects a zero or non-finite axis and a non-finite position",
                   "[paraboloid]", float, double) {
  using T = TestType;
  const T nan = std::numeric_limits<T>::quiet_NaN(), inf = std::numeric_limits<T>::infinity();
  using F = vplkit::light_frame<T>;
  CHECK_THROWS_AS(F(vec3<T>(0), vec3<T>(0)), vplkit::invalid_input);
  CHECK_THROWS_AS(F(vec3<T>(0), vec3<T>(nan, 0, 1)), vplkit::invalid_input);
  CHECK_THROWS_AS(F(vec3<T>(0), vec3<T>(inf, 0, 0)), vplkit::invalid_input);
  CHECK_THROWS_AS(F(vec3<T>(nan, 0, 0), vec3<T>(0, 0, 1)), vplkit::invalid_input);
  CHECK_THROWS_AS(F(vec3<T>(0, inf, 0), vec3<T>(0, 0, 1)), vplkit::invalid_input);
  CHECK_NOTHROW(F(vec3<T>(0), vec3<T>(0, 0, std::numeric_limits<T>::min())));
  // A denormal axis is zero (docs/math.md, "GPU arithmetic model": a GPU may flush it).
  CHECK_THROWS_AS(F(vec3<T>(0), vec3<T>(0, 0, std::numeric_limits<T>::denorm_min())), vplkit::invalid_input);
}
