// SPDX-License-Identifier: MIT
// docs/math.md section 10, "ONB: normals near (0,0,-1)", plus degenerate inputs. Tolerance: every
// dot product, |t|^2 - 1, |b|^2 - 1, cross(t, b) - n and n - normalize(input) within 8 epsilon of T
// (measured worst case of the construction: 3 epsilon); no component NaN or infinite.
#include <vplkit/sampling/orthonormal_basis.hpp>

#include <catch2/catch.hpp>
#include <special_values.hpp>

#include <cmath>
#include <limits>

using namespace vplkit;
using vplkit_test::finite3;

namespace {

template <class T> void check_frame(vec3<T> input, vec3<T> expected_n) {
  const orthonormal_basis<T> f = make_orthonormal_basis(input);
  INFO("input (" << input.x << ", " << input.y << ", " << input.z << ")");
  REQUIRE(finite3(f.t));
  REQUIRE(finite3(f.b));
  REQUIRE(finite3(f.n));
  const T tol = T(8) * std::numeric_limits<T>::epsilon();
  CHECK(std::abs(glm::dot(f.t, f.b)) <= tol);
  CHECK(std::abs(glm::dot(f.t, f.n)) <= tol);
  CHECK(std::abs(glm::dot(f.b, f.n)) <= tol);
  CHECK(std::abs(glm::dot(f.t, f.t) - T(1)) <= tol);
  CHECK(std::abs(glm::dot(f.b, f.b) - T(1)) <= tol);
  CHECK(std::abs(glm::dot(f.n, f.n) - T(1)) <= tol);
  const vec3<T> c = glm::cross(f.t, f.b) - f.n;
  CHECK(std::abs(c.x) <= tol);
  CHECK(std::abs(c.y) <= tol);
  CHECK(std::abs(c.z) <= tol);
  const vec3<T> dn = f.n - expected_n;
  CHECK(std::abs(dn.x) <= tol);
  CHECK(std::abs(dn.y) <= tol);
  CHECK(std::abs(dn.z) <= tol);
}

template <class T> void south_pole_ulp_perturbations() {
  const T lo = std::numeric_limits<T>::min();  // the smallest normal: a denormal counts as 0
  const T eps = std::numeric_limits<T>::epsilon();
  const T below1 = std::nextafter(T(1), T(0));  // 1 - eps/2
  for (T dx : {T(0), lo, -lo, eps, -eps})
    for (T dy : {T(0), lo, -lo, eps, -eps}) {
      // x, y the smallest normal or one ulp from a unit-scale value; z = -1 and -1 + 1 ulp
      check_frame(vec3<T>(dx, dy, T(-1)), glm::normalize(vec3<T>(dx, dy, T(-1))));
      check_frame(vec3<T>(dx, dy, -below1), glm::normalize(vec3<T>(dx, dy, -below1)));
    }
}

}  // namespace

TEST_CASE("ONB hard case: n exactly (0,0,-1)") {
  check_frame(vec3<float>(0, 0, -1), vec3<float>(0, 0, -1));
  check_frame(vec3<double>(0, 0, -1), vec3<double>(0, 0, -1));
  const auto f = make_orthonormal_basis(vec3<float>(0, 0, -1));
  CHECK(f.t == vec3<float>(1, 0, 0));
  CHECK(f.b == vec3<float>(0, -1, 0));
}

TEST_CASE("ONB hard case: n exactly (0,0,1)") {
  check_frame(vec3<float>(0, 0, 1), vec3<float>(0, 0, 1));
  check_frame(vec3<double>(0, 0, 1), vec3<double>(0, 0, 1));
}

TEST_CASE("ONB hard case: n.z = -1 + tiny") {
  for (float tiny : {std::ldexp(1.0f, -24), 1e-7f, 1e-5f, 1e-3f}) {
    const float z = -1.0f + tiny;
    const float s = std::sqrt((1.0f - z) * (1.0f + z));  // the rest in x and y
    check_frame(vec3<float>(s * 0.6f, s * 0.8f, z), glm::normalize(vec3<float>(s * 0.6f, s * 0.8f, z)));
  }
  for (double tiny : {std::ldexp(1.0, -53), 1e-15, 1e-9, 1e-4}) {
    const double z = -1.0 + tiny;
    const double s = std::sqrt((1.0 - z) * (1.0 + z));
    check_frame(vec3<double>(-s * 0.8, s * 0.6, z),
                glm::normalize(vec3<double>(-s * 0.8, s * 0.6, z)));
  }
}

TEST_CASE("ONB hard case: (0,0,-1) with +-1 ulp perturbations in x and y") {
  south_pole_ulp_perturbations<float>();
  south_pole_ulp_perturbations<double>();
}

TEST_CASE("ONB hard case: n.z = -0.0 and +0.0 (the sign switch)") {
  check_frame(vec3<float>(1, 0, -0.0f), vec3<float>(1, 0, 0));
  check_frame(vec3<float>(0, 1, 0.0f), vec3<float>(0, 1, 0));
  check_frame(vec3<float>(0.6f, 0.8f, -1e-30f), vec3<float>(0.6f, 0.8f, -1e-30f));
}

TEST_CASE("ONB hard case: denormal components count as 0, tiny normal ones keep their direction") {
  // The normal-range contract (docs/math.md, "GPU arithmetic model"): a component below the smallest normal T
  // is 0 (a GPU may flush it), so all-denormal input has no direction: the canonical frame.
  const float d = std::numeric_limits<float>::denorm_min();
  check_frame(vec3<float>(0, 0, -d), vec3<float>(0, 0, 1));
  check_frame(vec3<float>(d, 0, 0), vec3<float>(0, 0, 1));
  check_frame(vec3<float>(3 * d, 0, -4 * d), vec3<float>(0, 0, 1));
  check_frame(vec3<float>(1e-39f, -1e-39f, -1e-39f), vec3<float>(0, 0, 1));
  check_frame(vec3<float>(1, 1e-39f, -1e-39f), vec3<float>(1, 0, 0));
  const double dd = std::numeric_limits<double>::denorm_min();
  check_frame(vec3<double>(dd, dd, -dd), vec3<double>(0, 0, 1));
  // All length in components at the bottom of the normal range.
  const float m = std::numeric_limits<float>::min();
  check_frame(vec3<float>(0, 0, -m), vec3<float>(0, 0, -1));
  check_frame(vec3<float>(3 * m, 0, -4 * m), vec3<float>(0.6f, 0, -0.8f));
  const double md = std::numeric_limits<double>::min();
  check_frame(vec3<double>(md, md, -md), glm::normalize(vec3<double>(1, 1, -1)));
}

TEST_CASE("ONB hard case: unnormalised input") {
  check_frame(vec3<float>(0, 0, -1e30f), vec3<float>(0, 0, -1));
  check_frame(vec3<float>(3e38f, 3e38f, -3e38f), glm::normalize(vec3<float>(1, 1, -1)));  // |n|^2 overflows
  check_frame(vec3<float>(0.3f, -0.4f, -12.0f), glm::normalize(vec3<float>(0.3f, -0.4f, -12.0f)));
  check_frame(vec3<double>(1e-200, 0, -1e-200), glm::normalize(vec3<double>(1, 0, -1)));  // |n|^2 underflows
  check_frame(vec3<double>(0, 0, -1.0000001), vec3<double>(0, 0, -1));
}

TEST_CASE("ONB hard case: zero, NaN and infinite input give the canonical frame, not NaN") {
  const float inf = std::numeric_limits<float>::infinity();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (vec3<float> n : {vec3<float>(0, 0, 0), vec3<float>(0, 0, -0.0f), vec3<float>(nan, 0, -1),
                        vec3<float>(0, inf, 0), vec3<float>(-inf, -inf, -inf)}) {
    check_frame(n, vec3<float>(0, 0, 1));
  }
}
