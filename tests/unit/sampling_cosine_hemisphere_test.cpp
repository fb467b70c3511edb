// SPDX-License-Identifier: MIT
#include <vplkit/sampling/cosine_hemisphere.hpp>
#include <vplkit/sampling/rng.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

using namespace vplkit;

TEST_CASE("cosine_hemisphere_pdf integrates to 1 over the hemisphere") {
  // Midpoint rule in theta (the integrand is independent of phi): 2 pi int pdf(cos) sin dtheta.
  const int n = 200000;
  const double pi = 3.14159265358979323846, h = (pi / 2) / n;
  double sum = 0;
  for (int i = 0; i < n; ++i) {
    const double th = (i + 0.5) * h;
    sum += cosine_hemisphere_pdf(std::cos(th)) * std::sin(th);
  }
  CHECK(2 * pi * sum * h == Approx(1.0).epsilon(1e-9));
  // float instantiation agrees
  CHECK(cosine_hemisphere_pdf(0.5f) == Approx(0.5 / pi));
}

TEST_CASE("cosine_hemisphere_pdf is 0 below the horizon and for NaN") {
  CHECK(cosine_hemisphere_pdf(-0.5) == 0.0);
  CHECK(cosine_hemisphere_pdf(0.0) == 0.0);
  CHECK(cosine_hemisphere_pdf(-0.0f) == 0.0f);
  CHECK(cosine_hemisphere_pdf(std::numeric_limits<double>::quiet_NaN()) == 0.0);
  CHECK(cosine_hemisphere_pdf(1.0) == Approx(1.0 / 3.14159265358979323846));
}

TEST_CASE("sample_cosine_hemisphere: unit, upper hemisphere, disk projection uniform-radius") {
  counter_rng r = make_counter_rng(8u, 0u);
  for (int i = 0; i < 100000; ++i) {
    const vec2<float> u(rng_next_float(r), rng_next_float(r));
    const vec3<float> d = sample_cosine_hemisphere(u);
    REQUIRE(d.z >= 0.0f);
    REQUIRE(std::abs(glm::dot(d, d) - 1.0f) <= 4 * std::numeric_limits<float>::epsilon());
    const vec2<float> p = concentric_disk(u);
    CHECK(p.x == d.x);
    CHECK(p.y == d.y);
  }
}

TEST_CASE("concentric mapping: centre, corners and edge midpoints") {
  const double s = std::sqrt(0.5);
  auto near = [](vec2<double> a, vec2<double> b) { return glm::length(a - b) < 1e-15; };
  CHECK(near(concentric_disk(vec2<double>(0.5, 0.5)), vec2<double>(0, 0)));
  CHECK(near(concentric_disk(vec2<double>(1, 0.5)), vec2<double>(1, 0)));
  CHECK(near(concentric_disk(vec2<double>(0.5, 1)), vec2<double>(0, 1)));
  CHECK(near(concentric_disk(vec2<double>(0, 0.5)), vec2<double>(-1, 0)));
  CHECK(near(concentric_disk(vec2<double>(0.5, 0)), vec2<double>(0, -1)));
  CHECK(near(concentric_disk(vec2<double>(1, 1)), vec2<double>(s, s)));
  CHECK(near(concentric_disk(vec2<double>(0, 0)), vec2<double>(-s, -s)));
  const vec3<double> up = sample_cosine_hemisphere(vec2<double>(0.5, 0.5));
  CHECK(up == vec3<double>(0, 0, 1));
}

TEST_CASE("concentric mapping preserves area: square cells map to equal-area disk cells") {
  // Concentric squares |a|_inf <= k/K map to disks of radius k/K (area fraction (k/K)^2), so
  // the fraction of samples with r <= k/K must be (k/K)^2 exactly for a regular grid of u.
  const int g = 400;
  int inside_half = 0;
  for (int i = 0; i < g; ++i)
    for (int j = 0; j < g; ++j) {
      const vec2<double> p = concentric_disk(vec2<double>((i + 0.5) / g, (j + 0.5) / g));
      inside_half += glm::dot(p, p) <= 0.25 ? 1 : 0;
    }
  CHECK(inside_half == g * g / 4);
}
