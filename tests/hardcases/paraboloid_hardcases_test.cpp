// SPDX-License-Identifier: MIT
// docs/math.md section 10, paraboloid: d = (0,0,+-1), rim directions (z = 0 and +-1 ulp), r2
// slightly above 1 from rounding; plus degenerate inputs. Nothing may come out NaN or Inf.
#include <vplkit/paraboloid/light_frame.hpp>
#include <vplkit/paraboloid/paraboloid.hpp>
#include <vplkit/paraboloid/texel_grid.hpp>

#include <catch2/catch.hpp>
#include <special_values.hpp>
#include <fp_mode.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

using namespace vplkit;
using vplkit_test::finite3;

namespace {
template <class T>
bool finite2(vec2<T> v) {
  return std::isfinite(v.x) && std::isfinite(v.y);
}
template <class T>
void require_valid_point(const vplkit::paraboloid_point<T>& p) {
  REQUIRE((p.face == paraboloid_front || p.face == paraboloid_back));
  REQUIRE(finite2(p.uv));
  REQUIRE(glm::dot(p.uv, p.uv) <= T(1));
}
}  // namespace

TEMPLATE_TEST_CASE("hard case: d = (0,0,+1) is the front pole", "[paraboloid][hardcase]", float,
                   double) {
  using T = TestType;
  for (T s : {T(1), T(1e-30), T(1e30), std::numeric_limits<T>::denorm_min(),
              std::numeric_limits<T>::max()}) {
    const auto p = vplkit::paraboloid_from_direction(vec3<T>(0, 0, s));
    require_valid_point(p);
    REQUIRE(p.face == paraboloid_front);
    REQUIRE(p.uv == vec2<T>(0, 0));
  }
  REQUIRE(vplkit::paraboloid_to_direction(paraboloid_front, vec2<T>(0)) == vec3<T>(0, 0, 1));
  // the texel nearest the pole maps back to the same texel, for odd and even R
  for (int R : {1, 2, 63, 64}) {
    const auto p = vplkit::paraboloid_from_direction(vec3<T>(0, 0, 1));
    const vplkit::ivec2 t = vplkit::texel_from_uv(p.uv, R);
    REQUIRE(vplkit::texel_is_valid(t.x, t.y, R));
    REQUIRE(vplkit::texel_solid_angle<T>(t.x, t.y, R) > T(0));
  }
}

TEMPLATE_TEST_CASE("hard case: d = (0,0,-1) is the back pole without cancellation",
                   "[paraboloid][hardcase]", float, double) {
  using T = TestType;
  for (T s : {T(1), T(1e-30), T(1e30), std::numeric_limits<T>::min(), std::numeric_limits<T>::max()}) {
    const auto p = vplkit::paraboloid_from_direction(vec3<T>(0, 0, -s));
    require_valid_point(p);
    REQUIRE(p.face == paraboloid_back);
    REQUIRE(p.uv == vec2<T>(0, 0));
  }
  // A denormal length is no direction (the normal-range contract, docs/math.md, "GPU arithmetic model"): the
  // documented fallback {front, (0,0)}, as on a GPU that flushes it.
  const auto dp = vplkit::paraboloid_from_direction(vec3<T>(0, 0, -std::numeric_limits<T>::denorm_min()));
  REQUIRE(dp.face == paraboloid_front);
  REQUIRE(dp.uv == vec2<T>(0, 0));
  REQUIRE(vplkit::paraboloid_to_direction(paraboloid_back, vec2<T>(0)) == vec3<T>(0, 0, -1));
  // Near the back pole the back face divides by 1 + |z| ~ 2 (not 1 + z ~ 0): uv ~ (x, y) / 2
  // to full relative precision even for tiny x.
  for (T x : {T(1e-3), T(1e-7), T(1e-20), std::numeric_limits<T>::min()}) {
    const auto p = vplkit::paraboloid_from_direction(vec3<T>(x, -x, -1));
    require_valid_point(p);
    REQUIRE(p.face == paraboloid_back);
    REQUIRE(p.uv.x == Approx(double(x) / 2).epsilon(1e-6));
    REQUIRE(p.uv.y == Approx(-double(x) / 2).epsilon(1e-6));
    const vec3<T> d = vplkit::paraboloid_to_direction(p.face, p.uv);
    REQUIRE(finite3(d));
    REQUIRE(d.z < T(0));
    REQUIRE(d.x == Approx(double(x)).epsilon(1e-6));
  }
}

TEMPLATE_TEST_CASE("hard case: rim directions with z = 0 and z = -0", "[paraboloid][hardcase]",
                   float, double) {
  using T = TestType;
  for (int i = 0; i < 3600; ++i) {
    const double a = 2.0 * 3.14159265358979323846 * i / 3600.0;
    const vec3<T> d(T(std::cos(a)), T(std::sin(a)), T(0));
    for (T z : {T(0), -T(0)}) {
      const auto p = vplkit::paraboloid_from_direction(vec3<T>(d.x, d.y, z));
      require_valid_point(p);
      REQUIRE(p.face == paraboloid_front);  // the rim belongs to the front face, -0 included
      REQUIRE(glm::dot(p.uv, p.uv) >= T(1) - T(8) * std::numeric_limits<T>::epsilon());
      const vec3<T> back = vplkit::paraboloid_to_direction(p.face, p.uv);
      REQUIRE(finite3(back));
      REQUIRE(std::abs(back.z) <= T(8) * std::numeric_limits<T>::epsilon());
      // the rim texel is inside the map and has a finite solid angle
      const vplkit::ivec2 t = vplkit::texel_from_uv(p.uv, 256);
      REQUIRE(t.x >= 0);
      REQUIRE(t.x < 256);
      REQUIRE(t.y >= 0);
      REQUIRE(t.y < 256);
      REQUIRE(std::isfinite(vplkit::texel_solid_angle<T>(t.x, t.y, 256)));
    }
  }
}

TEMPLATE_TEST_CASE("hard case: rim directions with z = +-1 ulp", "[paraboloid][hardcase]", float,
                   double) {
  using T = TestType;
  const T tiny[] = {std::numeric_limits<T>::denorm_min(), std::numeric_limits<T>::min(),
                    std::nextafter(T(0), T(1)) * T(3), std::numeric_limits<T>::epsilon() / T(2),
                    std::numeric_limits<T>::epsilon()};
  for (int i = 0; i < 720; ++i) {
    const double a = 2.0 * 3.14159265358979323846 * i / 720.0;
    const T x = T(std::cos(a)), y = T(std::sin(a));
    for (T z : tiny) {
      const auto up = vplkit::paraboloid_from_direction(vec3<T>(x, y, z));
      const auto down = vplkit::paraboloid_from_direction(vec3<T>(x, y, -z));
      require_valid_point(up);
      require_valid_point(down);
      REQUIRE(up.face == paraboloid_front);
      // A z below the smallest normal T counts as 0: the rim's own face, the front.
      REQUIRE(down.face == (z >= std::numeric_limits<T>::min() ? paraboloid_back : paraboloid_front));
      // one ulp apart in direction, at most a few ulp apart in uv (same uv by the seam rule)
      REQUIRE(glm::length(up.uv - down.uv) <= T(4) * std::numeric_limits<T>::epsilon());
      const vec3<T> du = vplkit::paraboloid_to_direction(up.face, up.uv);
      const vec3<T> dd = vplkit::paraboloid_to_direction(down.face, down.uv);
      REQUIRE(finite3(du));
      REQUIRE(finite3(dd));
      REQUIRE(du.z >= T(0));
      REQUIRE((down.face == paraboloid_back ? dd.z <= T(0) : dd.z >= T(0)));
    }
  }
}

TEMPLATE_TEST_CASE("hard case: r2 slightly above 1 from rounding is pulled into the disk",
                   "[paraboloid][hardcase]", float, double) {
  using T = TestType;
  const T eps = std::numeric_limits<T>::epsilon();
  // direct overshoots of the clamp
  for (vec2<T> uv : {vec2<T>(std::nextafter(T(1), T(2)), 0), vec2<T>(0, T(1) + T(4) * eps),
                     vec2<T>(T(0.6) * (T(1) + eps), T(0.8) * (T(1) + eps)),
                     vec2<T>(-std::sqrt(T(0.5)) * (T(1) + eps), std::sqrt(T(0.5)))}) {
    const vec2<T> c = vplkit::paraboloid_clamp_to_disk(uv);
    REQUIRE(glm::dot(c, c) <= T(1));
    REQUIRE(glm::length(c - uv) <= T(8) * eps);
  }
  // Rim directions whose normalised (x, y) has x^2 + y^2 > 1 in T: the unclamped map would give
  // r2 > 1; prove such inputs occur and that the result still has r2 <= 1.
  std::mt19937_64 rng(41);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int overshooting = 0;
  for (int i = 0; i < 200000; ++i) {
    const vec3<T> d(T(u(rng)), T(u(rng)), T(0));
    const vec3<T> n = vplkit::unit_or_zero(d);
    const T raw = glm::dot(vec2<T>(n.x, n.y), vec2<T>(n.x, n.y));
    overshooting += raw > T(1) ? 1 : 0;
    const auto p = vplkit::paraboloid_from_direction(d);
    require_valid_point(p);
    // and the valid-texel lookup of a rim uv lands inside the map
    const vplkit::ivec2 t = vplkit::texel_from_uv(p.uv, 512);
    REQUIRE((t.x >= 0 && t.x < 512 && t.y >= 0 && t.y < 512));
  }
  INFO("rim directions with x^2 + y^2 > 1 after normalisation: " << overshooting);
  CHECK(overshooting > 1000);
}

TEMPLATE_TEST_CASE("hard case: zero NaN Inf and extreme-length directions",
                   "[paraboloid][hardcase]", float, double) {
  using T = TestType;
  const T nan = std::numeric_limits<T>::quiet_NaN(), inf = std::numeric_limits<T>::infinity();
  const T big = std::numeric_limits<T>::max(), dn = std::numeric_limits<T>::denorm_min();
  // degenerate: documented fallback {front, (0,0)}
  // (A vector whose components are all below the smallest normal T is zero: docs/math.md
  // "GPU arithmetic model".)
  for (vec3<T> d : {vec3<T>(0), vec3<T>(nan), vec3<T>(nan, 0, 1), vec3<T>(inf, 0, 0), vec3<T>(-inf, inf, 0),
                    vec3<T>(dn, dn, -dn), vec3<T>(dn, 0, 0)}) {
    const auto p = vplkit::paraboloid_from_direction(d);
    require_valid_point(p);
    REQUIRE(p.face == paraboloid_front);
    REQUIRE(p.uv == vec2<T>(0));
  }
  // extreme but finite lengths behave like their normalisation (to the rounding of normalising
  // twice: a few ulps)
  const T min = std::numeric_limits<T>::min();
  for (vec3<T> d : {vec3<T>(big, big, -big), vec3<T>(min, min, -min), vec3<T>(min, 0, 0), vec3<T>(big, 0, dn)}) {
    const auto p = vplkit::paraboloid_from_direction(d);
    require_valid_point(p);
    const vec3<T> n = vplkit::unit_or_zero(d);
    const auto q = vplkit::paraboloid_from_direction(n);
    REQUIRE(p.face == q.face);
    REQUIRE(glm::length(p.uv - q.uv) <= T(4) * std::numeric_limits<T>::epsilon());
    REQUIRE(std::abs(glm::length(n) - T(1)) <= T(4) * std::numeric_limits<T>::epsilon());
  }
}

TEMPLATE_TEST_CASE("hard case: light frame with front axis at or near (0,0,-1)",
                   "[paraboloid][hardcase]", float, double) {
  using T = TestType;
  const T tol = T(8) * std::numeric_limits<T>::epsilon();
  for (vec3<T> axis : {vec3<T>(0, 0, -1), vec3<T>(std::numeric_limits<T>::min(), 0, -1),
                       vec3<T>(T(1e-4), T(-1e-4), -1), vec3<T>(0, T(1e-8), -1),
                       vec3<T>(0, 0, -std::numeric_limits<T>::min())}) {
    const vplkit::light_frame<T> f(vec3<T>(0), axis);
    REQUIRE(finite3(f.axis_x));
    REQUIRE(finite3(f.axis_y));
    REQUIRE(std::abs(glm::dot(f.axis_x, f.axis_y)) <= tol);
    REQUIRE(std::abs(glm::length(f.axis_x) - T(1)) <= tol);
    REQUIRE(std::abs(glm::length(f.axis_y) - T(1)) <= tol);
    REQUIRE(glm::length(glm::cross(f.axis_x, f.axis_y) - f.axis_z) <= tol);
    REQUIRE(f.axis_z.z < T(-0.99));
  }
  // A denormal axis is zero (docs/math.md, "GPU arithmetic model"): rejected with the error of a zero axis.
  REQUIRE_THROWS_WITH(vplkit::light_frame<T>(vec3<T>(0), vec3<T>(0, 0, -std::numeric_limits<T>::denorm_min())),
                      Catch::Matchers::Contains("front axis is zero"));
}

TEST_CASE("hard case: texel validity next to the rim is exact", "[paraboloid][hardcase]") {
  // A centre (a, b) / R (a = 2x + 1 - R) can be within a few 1/R^2 of the rim (never on it:
  // a^2 + b^2 - R^2 is 2 mod 4 for even R, 3 mod 4 for odd R): below float resolution for large
  // R. texel_is_valid decides in integers; compare with exact 64-bit arithmetic and
  // show that a float r2 <= 1 test gets some of these texels wrong.
  int near_rim = 0, float_wrong = 0;
  for (int R : {3001, 4096, 4097, 16383, vplkit::paraboloid_max_resolution}) {
    for (int y = 0; y < R; ++y) {
      const long long b = 2LL * y + 1 - R;
      // the two x on this row closest to the rim, on each side
      const double xr = (std::sqrt(std::max(0.0, double(R) * R - double(b) * b)) + R - 1) / 2;
      for (int x = int(xr) - 1; x <= int(xr) + 2; ++x) {
        if (x < 0 || x >= R) continue;
        const long long a = 2LL * x + 1 - R;
        const long long excess = a * a + b * b - 1LL * R * R;
        const bool exact = excess <= 0;
        REQUIRE(vplkit::texel_is_valid(x, y, R) == exact);
        REQUIRE((vplkit::texel_solid_angle<float>(x, y, R) > 0.0f) == exact);
        if (excess >= -8 && excess <= 8) {
          ++near_rim;
          const vplkit::vec2<float> c = vplkit::texel_center_uv<float>(x, y, R);
          float_wrong += ((glm::dot(c, c) <= 1.0f) != exact) ? 1 : 0;
        }
      }
    }
  }
  INFO(near_rim << " centres within 8/R^2 of the rim, " << float_wrong
                << " misclassified by a float r2 <= 1 test");
  CHECK(near_rim > 0);
  CHECK(float_wrong > 0);
  // the largest resolution stays in int
  const int R = vplkit::paraboloid_max_resolution;
  REQUIRE(vplkit::texel_count(R) == 2 * R * R);
  REQUIRE(vplkit::texel_index(1, R - 1, R - 1, R) == 2 * R * R - 1);
  REQUIRE(vplkit::texel_is_valid(R / 2, R - 1, R));
  REQUIRE_FALSE(vplkit::texel_is_valid(0, 0, R));
}

TEMPLATE_TEST_CASE("hard case: clamp_to_disk of a uv whose r2 overflows lands on the rim in its own direction",
                   "[paraboloid][hardcase]", float, double) {
  using T = TestType;
  using lim = std::numeric_limits<T>;
  // |uv| beyond 2^64 (float; 2^512 in double): dot(uv, uv) overflows to Inf and uv / sqrt(Inf) is the
  // centre of the map, not the rim. Scaled first, every finite uv lands on the rim.
  const T big = exp2i<T>((lim::max_exponent - 2) / 2 + 1);  // 2^64 in float: its square is Inf
  const vec2<T> cases[] = {vec2<T>(big, T(0)),         vec2<T>(T(0), -big),    vec2<T>(big, big),
                           vec2<T>(-T(3) * big, T(4) * big), vec2<T>(lim::max(), T(0)), vec2<T>(lim::max(), lim::max()),
                           vec2<T>(-lim::max(), T(1)),  vec2<T>(lim::max(), -lim::max() / T(3))};
  for (const vec2<T> uv : cases) {
    INFO("uv = (" << uv.x << ", " << uv.y << ")");
    REQUIRE(!(glm::dot(uv, uv) <= lim::max()));  // the hazard: r2 is not finite
    const vec2<T> r = paraboloid_clamp_to_disk(uv);
    const T r2 = glm::dot(r, r);
    CHECK(r2 <= T(1));
    CHECK(r2 >= T(1) - T(16) * lim::epsilon());
    // Its own direction: the exact direction of uv, in double (uv / |uv| scaled by a power of two).
    const double s = double(std::max(std::abs(uv.x), std::abs(uv.y)));
    const double ux = double(uv.x) / s, uy = double(uv.y) / s, n = std::sqrt(ux * ux + uy * uy);
    CHECK(std::abs(double(r.x) - ux / n) <= 8.0 * double(lim::epsilon()));
    CHECK(std::abs(double(r.y) - uy / n) <= 8.0 * double(lim::epsilon()));
  }
  // A uv just below the switch keeps the unscaled path (and is on the rim too).
  const vec2<T> below(big / T(2), big / T(2));
  const vec2<T> r = paraboloid_clamp_to_disk(below);
  CHECK(glm::dot(r, r) <= T(1));
  CHECK(glm::dot(r, r) >= T(1) - T(16) * lim::epsilon());
  // Infinite components: no direction to keep; (0, 0), unit_or_zero's answer.
  CHECK(paraboloid_clamp_to_disk(vec2<T>(lim::infinity(), T(1))) == vec2<T>(T(0)));
}

TEMPLATE_TEST_CASE("hard case: scaled_length of vectors from 2^-124 to the largest float, flushed or not",
                   "[paraboloid][hardcase]", float, double) {
  using T = TestType;
  using lim = std::numeric_limits<T>;
  // (0.75, -1, 0) 2^k has length 1.25 2^k exactly. glm::length squares first: 0 or a denormal
  // below 2^-63 (float; a GPU flushes it) and Inf beyond 2^64; scaled first, it is exact over the
  // whole normal range, the same with denormals flushed (FTZ|DAZ, as a GPU).
  for (int k = lim::min_exponent; k < lim::max_exponent; ++k) {
    const vec3<T> v = vec3<T>(T(0.75), T(-1), T(0)) * exp2i<T>(k);
    const T expect = T(1.25) * exp2i<T>(k);
    INFO("k = " << k);
    CHECK(scaled_length(v) == expect);
    const vplkit_test::fp_mode_scope ftz(true);
    CHECK(scaled_length(v) == expect);
  }
  CHECK(scaled_length(vec3<T>(lim::max(), -lim::max(), T(0))) == lim::infinity());  // |v| beyond the largest T
  // Where the largest component lies in [2^-50, 2^62] (float): glm::length's bits.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::uniform_int_distribution<int> exponent(-50, 61);
  for (int i = 0; i < 20000; ++i) {
    const T s = std::ldexp(T(1), exponent(rng));
    const vec3<T> v(T(unit(rng)) * s, T(unit(rng)) * s, T(1.5) * s);
    INFO("v = (" << v.x << ", " << v.y << ", " << v.z << ")");
    REQUIRE(scaled_length(v) == glm::length(v));
  }
  CHECK(scaled_length(vec3<T>(T(0))) == T(0));
  CHECK(scaled_length(vec3<T>(lim::denorm_min(), T(0), -lim::denorm_min())) == T(0));  // below the normal range
  CHECK(scaled_length(vec3<T>(T(1), lim::infinity(), T(0))) == lim::infinity());
}
