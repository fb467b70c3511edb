// SPDX-License-Identifier: MIT
// The distribution of sample_cosine_hemisphere is cos(theta)/pi per steradian: cos^2(theta) and
// phi are then independent and uniform on [0,1] and [0, 2 pi).
#include <vplkit/sampling/cosine_hemisphere.hpp>
#include <vplkit/sampling/rng.hpp>
#include <vplkit_test_support.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

using namespace vplkit;

namespace {

const double pi = 3.14159265358979323846;

template <class T> void check_distribution(std::uint32_t seed) {
  const int bins = 50, n = 1000000;
  std::vector<std::uint64_t> c_cos2(bins, 0), c_phi(bins, 0), c_joint(bins * bins, 0);
  double sum_cos = 0, sum_cos2 = 0;
  counter_rng r = make_counter_rng(seed, 0u);
  for (int i = 0; i < n; ++i) {
    const vec2<T> u(rng_next_unit<T>(r), rng_next_unit<T>(r));
    const vec3<T> d = sample_cosine_hemisphere(u);
    const double c = double(d.z), c2 = c * c;
    double phi = std::atan2(double(d.y), double(d.x));
    if (phi < 0) phi += 2 * pi;
    const int bc = std::min(bins - 1, int(c2 * bins));
    const int bp = std::min(bins - 1, int(phi / (2 * pi) * bins));
    ++c_cos2[bc];
    ++c_phi[bp];
    ++c_joint[bc * bins + bp];
    sum_cos += c;
    sum_cos2 += c2;
  }
  const std::vector<double> p1(bins, 1.0 / bins), p2(bins * bins, 1.0 / (bins * bins));
  int dof = 0;
  double stat = vplkit_test::chi_square(c_cos2, p1, n, &dof);
  INFO("cos^2 theta: chi2 " << stat << " dof " << dof);
  CHECK(stat < vplkit_test::chi_square_critical(dof));
  stat = vplkit_test::chi_square(c_phi, p1, n, &dof);
  INFO("phi: chi2 " << stat << " dof " << dof);
  CHECK(stat < vplkit_test::chi_square_critical(dof));
  stat = vplkit_test::chi_square(c_joint, p2, n, &dof);
  INFO("joint (cos^2, phi): chi2 " << stat << " dof " << dof);
  CHECK(stat < vplkit_test::chi_square_critical(dof));

  // E[cos] = 2/3, Var[cos] = E[cos^2] - 4/9 = 1/2 - 4/9 = 1/18.
  const double mean = sum_cos / n, sigma = std::sqrt(1.0 / 18.0 / n);
  INFO("E[cos] = " << mean << " (2/3 expected, sigma " << sigma << ")");
  CHECK(std::abs(mean - 2.0 / 3.0) < 4 * sigma);
  CHECK(std::abs(sum_cos2 / n - 0.5) < 4 * std::sqrt(1.0 / 12.0 / n));
}

}  // namespace

TEST_CASE("cosine hemisphere: cos^2 theta and phi uniform and independent, E[cos] = 2/3 (float)") {
  check_distribution<float>(21u);
}

TEST_CASE("cosine hemisphere: cos^2 theta and phi uniform and independent, E[cos] = 2/3 (double)") {
  check_distribution<double>(22u);
}

TEST_CASE("cosine hemisphere: Monte Carlo integral of the pdf over the sphere with uniform "
          "directions is 1") {
  // Independent check of the normalisation: uniform sphere directions, estimate 4 pi E[pdf].
  const int n = 1000000;
  counter_rng r = make_counter_rng(23u, 0u);
  double sum = 0, sum2 = 0;
  for (int i = 0; i < n; ++i) {
    const double z = 2 * rng_next_double(r) - 1;  // uniform on the sphere: z uniform
    const double v = 4 * pi * cosine_hemisphere_pdf(z);
    sum += v;
    sum2 += v * v;
  }
  const double mean = sum / n, sigma = std::sqrt((sum2 / n - mean * mean) / n);
  CHECK(std::abs(mean - 1.0) < 4 * sigma);
}
