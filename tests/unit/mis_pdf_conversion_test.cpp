// SPDX-License-Identifier: MIT
#include <vplkit/mis/heuristics.hpp>
#include <vplkit/mis/pdf_conversion.hpp>

#include <catch2/catch.hpp>

#include <cmath>

using namespace vplkit;

namespace {

const double pi = 3.14159265358979323846;

// Exact solid angle of the triangle (a, b, c) seen from the origin (Van Oosterom & Strackee 1983).
double triangle_solid_angle(vec3<double> a, vec3<double> b, vec3<double> c) {
  const double la = glm::length(a), lb = glm::length(b), lc = glm::length(c);
  const double num = glm::dot(a, glm::cross(b, c));
  const double den = la * lb * lc + glm::dot(a, b) * lc + glm::dot(a, c) * lb + glm::dot(b, c) * la;
  return 2.0 * std::abs(std::atan2(num, den));
}

}  // namespace

TEST_CASE("cosine_pdf_solid_angle is cos/pi, 0 behind") {
  CHECK(cosine_pdf_solid_angle(0.5) == Approx(0.5 / pi));
  CHECK(cosine_pdf_solid_angle(1.0f) == Approx(1.0 / pi));
  CHECK(cosine_pdf_solid_angle(-0.2) == 0.0);
}

TEST_CASE("vpl_pdf_solid_angle is pmf d2^2 / (A cos theta1)") {
  CHECK(vpl_pdf_solid_angle(0.25, 4.0, 0.5, 0.5) == Approx(0.25 * 4.0 / (0.5 * 0.5)));
  CHECK(vpl_pdf_solid_angle(1e-6f, 9.0f, 1e-4f, 1.0f) == Approx(1e-6 * 9.0 / 1e-4));
}

TEST_CASE("vpl_pdf_solid_angle is pmf over the solid angle the patch subtends (small patches)") {
  // A square patch of side s centred at y, tilted by theta1 against the direction to x = origin.
  // Sampling it uniformly after picking it with probability pmf has mean solid-angle density
  // pmf / Omega(patch); the small-patch formula must agree to O((s/d)^2).
  const double pmf = 0.01;
  for (double d : {0.5, 2.0, 10.0})
    for (double theta1 : {0.0, 0.5, 1.2}) {
      const double s = 1e-3 * d;
      const vec3<double> y(0, 0, d);            // patch centre, direction from x is +z
      const vec3<double> nrm(std::sin(theta1), 0, -std::cos(theta1));  // faces x, tilted
      const vec3<double> e1(std::cos(theta1), 0, std::sin(theta1));    // in-plane axes
      const vec3<double> e2(0, 1, 0);
      const vec3<double> c00 = y - 0.5 * s * e1 - 0.5 * s * e2, c10 = c00 + s * e1,
                         c11 = c10 + s * e2, c01 = c00 + s * e2;
      const double omega = triangle_solid_angle(c00, c10, c11) + triangle_solid_angle(c00, c11, c01);
      const double cos_theta1 = glm::dot(nrm, -glm::normalize(y));
      const double p2 = vpl_pdf_solid_angle(pmf, d * d, s * s, cos_theta1);
      INFO("d " << d << " theta1 " << theta1);
      CHECK(p2 == Approx(pmf / omega).epsilon(1e-5));
    }
}

TEST_CASE("cosine_pdf_as_published is the (theta, phi) density: cos/pi times the Jacobian sin") {
  // integrates to 1 over [0, pi/2] x [0, 2 pi] in d(theta) d(phi)
  const int n = 100000;
  const double h = (pi / 2) / n;
  double sum = 0;
  for (int i = 0; i < n; ++i) {
    const double th = (i + 0.5) * h;
    sum += cosine_pdf_as_published(std::cos(th), std::sin(th));
  }
  CHECK(2 * pi * sum * h == Approx(1.0).epsilon(1e-9));
  for (double th : {0.1, 0.7, 1.4})
    CHECK(cosine_pdf_as_published(std::cos(th), std::sin(th)) ==
          Approx(cosine_pdf_solid_angle(std::cos(th)) * std::sin(th)));
  CHECK(cosine_pdf_as_published(1.0, 0.0) == 0.0);  // vanishes at the pole, unlike cos/pi
  CHECK(cosine_pdf_as_published(-0.5, 0.8) == 0.0);
}

TEST_CASE("mis_weights_as_published follows eq. 8 and 9 and sums to 1") {
  const double th = 0.6, alpha = 0.05;
  const double p1 = std::cos(th) * std::sin(th) / pi;
  const mis_weight_pair<double> w = mis_weights_as_published(std::cos(th), std::sin(th), alpha);
  CHECK(w.gathering == Approx(p1 / (p1 + alpha)));
  CHECK(w.vpl == Approx(alpha / (p1 + alpha)));
  CHECK(w.gathering + w.vpl == Approx(1.0).epsilon(1e-15));
  const mis_weight_pair<float> z = mis_weights_as_published(0.0f, 1.0f, 0.0f);
  CHECK(z.gathering == 0.0f);
  CHECK(z.vpl == 0.0f);
  const mis_weight_pair<float> pole = mis_weights_as_published(1.0f, 0.0f, 1e-6f);
  CHECK(pole.vpl == 1.0f);  // p1 = 0 at theta = 0: the VPL strategy takes the whole weight
}

TEST_CASE("solid-angle weights are invariant when texels are subdivided, as-published are not") {
  // Splitting a texel into 4 quarters: pmf / 4 and area / 4 for each. The solid-angle density of
  // a point does not change, so neither does its balance weight. alpha changes by 4x, and so do
  // the paper's weights: they depend on the DPRSM resolution, not on the sampled point.
  const double pmf = 1e-4, d2 = 2.0, area = 1e-3, c1 = 0.8, cos2 = 0.6, sin2 = 0.8;
  const double w_coarse =
      balance_heuristic(1.0, vpl_pdf_solid_angle(pmf, d2, area, c1), 1.0, cosine_pdf_solid_angle(cos2));
  const double w_fine = balance_heuristic(1.0, vpl_pdf_solid_angle(pmf / 4, d2, area / 4, c1), 1.0,
                                          cosine_pdf_solid_angle(cos2));
  CHECK(w_fine == Approx(w_coarse).epsilon(1e-14));
  const double a_coarse = mis_weights_as_published(cos2, sin2, pmf).vpl;
  const double a_fine = mis_weights_as_published(cos2, sin2, pmf / 4).vpl;
  CHECK(a_fine < 0.3 * a_coarse);
}
