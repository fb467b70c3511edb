// SPDX-License-Identifier: MIT
// Extreme u for sample_cosine_hemisphere: the result must be a finite unit vector (within 4 eps of
// length 1) with z >= 0 for u = 0, the largest float below 1, exactly 1, and their mixtures.
#include <vplkit/sampling/cosine_hemisphere.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

using namespace vplkit;

namespace {

template <class T> void check_direction(T ux, T uy) {
  const vec3<T> d = sample_cosine_hemisphere(vec2<T>(ux, uy));
  INFO("u = (" << ux << ", " << uy << ") -> (" << d.x << ", " << d.y << ", " << d.z << ")");
  REQUIRE(std::isfinite(d.x));
  REQUIRE(std::isfinite(d.y));
  REQUIRE(std::isfinite(d.z));
  CHECK(d.z >= T(0));
  CHECK(std::abs(glm::dot(d, d) - T(1)) <= T(4) * std::numeric_limits<T>::epsilon());
  CHECK(cosine_hemisphere_pdf(d.z) >= T(0));
}

template <class T> void all_pairs() {
  const T below1 = std::nextafter(T(1), T(0));
  const T above0 = std::numeric_limits<T>::denorm_min();
  const T half = T(0.5), half_minus = std::nextafter(T(0.5), T(0));
  for (T a : {T(0), above0, half_minus, half, below1, T(1)})
    for (T b : {T(0), above0, half_minus, half, below1, T(1)}) check_direction(a, b);
}

}  // namespace

TEST_CASE("cosine hemisphere hard case: u = (0, 0)") {
  check_direction(0.0f, 0.0f);
  check_direction(0.0, 0.0);
}

TEST_CASE("cosine hemisphere hard case: u = (1 - ulp, 1 - ulp)") {
  check_direction(std::nextafter(1.0f, 0.0f), std::nextafter(1.0f, 0.0f));
  check_direction(std::nextafter(1.0, 0.0), std::nextafter(1.0, 0.0));
  // the largest value rng_next_float can return
  check_direction(1.0f - std::ldexp(1.0f, -24), 1.0f - std::ldexp(1.0f, -24));
}

TEST_CASE("cosine hemisphere hard case: u exactly 1") {
  check_direction(1.0f, 1.0f);
  check_direction(1.0, 1.0);
  check_direction(1.0f, 0.0f);
  check_direction(0.0, 1.0);
}

TEST_CASE("cosine hemisphere hard case: every mixture of extreme and centre coordinates") {
  all_pairs<float>();
  all_pairs<double>();
}

TEST_CASE("cosine hemisphere hard case: u slightly outside [0,1] is clamped to the rim") {
  check_direction(1.0f + std::numeric_limits<float>::epsilon(), 0.5f);
  check_direction(-1e-7f, -1e-7f);
}
