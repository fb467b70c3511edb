// SPDX-License-Identifier: MIT
#include <vplkit/paraboloid/texel_grid.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

using vplkit::ivec2;
using vplkit::vec2;

TEST_CASE("texel grid: flat index and (face, x, y) are inverse", "[paraboloid]") {
  for (int R : {1, 3, 64}) {
    REQUIRE(vplkit::texel_count(R) == 2 * R * R);
    int expected = 0;
    for (int face = 0; face < 2; ++face)
      for (int y = 0; y < R; ++y)
        for (int x = 0; x < R; ++x) {
          const int i = vplkit::texel_index(face, x, y, R);
          REQUIRE(i == expected++);  // front first, each face row-major with x fastest
          REQUIRE(vplkit::texel_face(i, R) == face);
          REQUIRE(vplkit::texel_coords(i, R) == ivec2(x, y));
        }
  }
}

TEMPLATE_TEST_CASE("texel grid: texel_from_uv(texel_center_uv) is the identity", "[paraboloid]",
                   float, double) {
  using T = TestType;
  for (int R : {1, 2, 3, 7, 64, 256, 1000, 4096}) {
    for (int y = 0; y < R; y += (R > 300 ? 7 : 1))
      for (int x = 0; x < R; x += (R > 300 ? 5 : 1)) {
        const vec2<T> c = vplkit::texel_center_uv<T>(x, y, R);
        REQUIRE(vplkit::texel_from_uv(c, R) == ivec2(x, y));
      }
    // the last row/column too
    REQUIRE(vplkit::texel_from_uv(vplkit::texel_center_uv<T>(R - 1, R - 1, R), R) ==
            ivec2(R - 1, R - 1));
  }
}

TEMPLATE_TEST_CASE("texel grid: centres and edges", "[paraboloid]", float, double) {
  using T = TestType;
  CHECK(vplkit::texel_center_uv<T>(0, 0, 1) == vec2<T>(0, 0));
  CHECK(vplkit::texel_center_uv<T>(0, 3, 4) == vec2<T>(T(-0.75), T(0.75)));
  // Texel k of 4 covers [-1 + k/2, -1 + (k+1)/2): edges belong to the texel above them.
  CHECK(vplkit::texel_from_uv(vec2<T>(T(-1), T(-0.5)), 4) == ivec2(0, 1));
  CHECK(vplkit::texel_from_uv(vec2<T>(T(0), T(0.5)), 4) == ivec2(2, 3));
  // uv = 1 is the closed end of the map: last texel.
  CHECK(vplkit::texel_from_uv(vec2<T>(T(1), T(1)), 4) == ivec2(3, 3));
}

TEMPLATE_TEST_CASE("texel grid: uv outside the map or non-finite is clamped into it",
                   "[paraboloid]", float, double) {
  using T = TestType;
  const T inf = std::numeric_limits<T>::infinity(), nan = std::numeric_limits<T>::quiet_NaN();
  const int R = 16;
  CHECK(vplkit::texel_from_uv(vec2<T>(T(-1.5), T(7)), R) == ivec2(0, R - 1));
  CHECK(vplkit::texel_from_uv(vec2<T>(-inf, inf), R) == ivec2(0, R - 1));
  CHECK(vplkit::texel_from_uv(vec2<T>(nan, nan), R) == ivec2(0, 0));
  const T big = std::numeric_limits<T>::max();
  CHECK(vplkit::texel_from_uv(vec2<T>(big, -big), R) == ivec2(R - 1, 0));
}

TEST_CASE("texel grid: validity is the centre inside the unit disk", "[paraboloid]") {
  for (int R : {1, 2, 3, 10, 64, 255, 256}) {
    long valid = 0;
    for (int y = 0; y < R; ++y)
      for (int x = 0; x < R; ++x) {
        const bool v = vplkit::texel_is_valid(x, y, R);
        const vec2<double> c = vplkit::texel_center_uv<double>(x, y, R);
        const double r2 = glm::dot(c, c);
        if (std::abs(r2 - 1.0) > 1e-12) REQUIRE(v == (r2 <= 1.0));
        // symmetric under both reflections and the diagonal swap
        REQUIRE(v == vplkit::texel_is_valid(R - 1 - x, y, R));
        REQUIRE(v == vplkit::texel_is_valid(x, R - 1 - y, R));
        REQUIRE(v == vplkit::texel_is_valid(y, x, R));
        valid += v ? 1 : 0;
      }
    if (R >= 64) {
      const double fraction = double(valid) / double(R) / double(R);
      CHECK(fraction == Approx(3.14159265358979323846 / 4).epsilon(0.01));
    }
  }
  CHECK(vplkit::texel_is_valid(0, 0, 1));        // centre (0, 0)
  CHECK(vplkit::texel_is_valid(0, 0, 2));        // centre (-1/2, -1/2): r2 = 1/2
  CHECK(vplkit::texel_is_valid(0, 0, 3));        // centre (-2/3, -2/3): r2 = 8/9
  CHECK_FALSE(vplkit::texel_is_valid(0, 0, 4));  // centre (-3/4, -3/4): r2 = 9/8
  CHECK_FALSE(vplkit::texel_is_valid(-1, 0, 4));
  CHECK_FALSE(vplkit::texel_is_valid(0, 4, 4));
}

TEMPLATE_TEST_CASE("texel grid: solid angle is the Jacobian at the centre times the texel area",
                   "[paraboloid]", float, double) {
  using T = TestType;
  const int R = 64;
  for (int y = 0; y < R; ++y)
    for (int x = 0; x < R; ++x) {
      const T omega = vplkit::texel_solid_angle<T>(x, y, R);
      if (!vplkit::texel_is_valid(x, y, R)) {
        REQUIRE(omega == T(0));
        continue;
      }
      const vec2<T> c = vplkit::texel_center_uv<T>(x, y, R);
      const T q = T(1) + glm::dot(c, c);
      REQUIRE(omega == Approx(T(4) / (q * q) * (T(2) / T(R)) * (T(2) / T(R))).epsilon(1e-6));
      REQUIRE(omega > T(0));
    }
  // pole texels subtend about 4x the rim texels
  const double pole = vplkit::texel_solid_angle<double>(R / 2, R / 2, R);
  const double rim = vplkit::texel_solid_angle<double>(R / 2, R - 1, R);
  CHECK(pole / rim == Approx(4.0).epsilon(0.07));
}

namespace {
// Integral of the Jacobian 4 / (1 + u^2 + v^2)^2 over texel (x, y) of an R x R map: 4x4-point
// Gauss-Legendre on n x n sub-squares (exact to ~1e-14 here).
double integrate_texel(int x, int y, int R, int n) {
  const double g[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563,
                       0.8611363115940526};
  const double w[4] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461,
                       0.3478548451374538};
  const double h = 2.0 / R, s = h / n;
  double sum = 0.0;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const double u0 = -1.0 + x * h + (i + 0.5) * s, v0 = -1.0 + y * h + (j + 0.5) * s;
      for (int a = 0; a < 4; ++a)
        for (int b = 0; b < 4; ++b) {
          const double u = u0 + 0.5 * s * g[a], v = v0 + 0.5 * s * g[b];
          const double q = 1.0 + u * u + v * v;
          sum += w[a] * w[b] * 0.25 * s * s * 4.0 / (q * q);
        }
    }
  return sum;
}
}  // namespace

TEST_CASE("texel grid: solid angle agrees with numerical integration of one texel",
          "[paraboloid]") {
  // Midpoint rule: relative error O(R^-2). Pole, mid-radius and rim texels.
  for (int R : {16, 64, 256}) {
    const int m = R / 2;
    const int texels[3][2] = {{m, m}, {m + R / 4, m + R / 8}, {m, R - 1}};
    for (const auto& t : texels) {
      REQUIRE(vplkit::texel_is_valid(t[0], t[1], R));
      const double exact = integrate_texel(t[0], t[1], R, 8);
      const double approx = vplkit::texel_solid_angle<double>(t[0], t[1], R);
      const double rel = std::abs(approx - exact) / exact;
      INFO("R " << R << " texel (" << t[0] << ", " << t[1] << ") relative error " << rel);
      CHECK(rel < 1.5 * 16.0 / (double(R) * R));  // 0.6% at R = 16, 4e-4 at 64, 2.3e-5 at 256
    }
  }
  // second-order convergence: near the same uv the relative error quarters when R doubles
  const auto rel_error = [](int x, int y, int R) {
    const double exact = integrate_texel(x, y, R, 8);
    return std::abs(vplkit::texel_solid_angle<double>(x, y, R) - exact) / exact;
  };
  const double e64 = rel_error(48, 40, 64), e128 = rel_error(96, 80, 128);
  INFO("relative error R=64 " << e64 << ", R=128 " << e128);
  CHECK(e64 / e128 > 3.5);
  CHECK(e64 / e128 < 4.5);
}

TEMPLATE_TEST_CASE("texel grid: every uv of the disk has one valid owner next to the texel holding it",
                   "[paraboloid]", float, double) {
  // texel_owner_from_uv: the texel holding uv when it is valid; else (the rim band: an invalid
  // square's part inside the disk) the one holding uv (1 - 2/R), an 8-neighbour and a rim texel
  // whose patch block holds uv's texel.
  using T = TestType;
  const double pi = 3.14159265358979323846;
  for (int R : {1, 2, 3, 4, 5, 8, 9, 17, 64, 255, 512, 4096, 16384}) {
    int band = 0;
    const int n_angles = 20000;
    for (int k = 0; k < n_angles; ++k) {
      const double phi = 2.0 * pi * (k + 0.37) / n_angles;
      // on the rim (clamped into the disk as paraboloid_from_direction does) and just inside it
      for (double depth : {0.0, 1e-7, 0.3 / R, 0.9 / R, 1.5 / R, 3.0 / R}) {
        const vec2<T> uv = vplkit::paraboloid_clamp_to_disk(
            vec2<T>(T((1.0 - depth) * std::cos(phi)), T((1.0 - depth) * std::sin(phi))));
        const ivec2 in = vplkit::texel_from_uv(uv, R);
        const ivec2 owner = vplkit::texel_owner_from_uv(uv, R);
        INFO("R " << R << " uv " << uv.x << ", " << uv.y << " in (" << in.x << ", " << in.y << ") owner (" << owner.x
                  << ", " << owner.y << ")");
        REQUIRE(vplkit::texel_is_valid(owner.x, owner.y, R));
        if (vplkit::texel_is_valid(in.x, in.y, R)) {
          REQUIRE(owner == in);
          continue;
        }
        ++band;
        REQUIRE(std::abs(owner.x - in.x) <= 1);
        REQUIRE(std::abs(owner.y - in.y) <= 1);
        REQUIRE(vplkit::texel_is_rim(owner.x, owner.y, R));
        // in the owner's patch block (dprsm_patch_vpl draws its points there)
        const vplkit::texel_block b = vplkit::texel_patch_block(owner.x, owner.y, R);
        REQUIRE((in.x >= b.x0 && in.x < b.x0 + b.nx && in.y >= b.y0 && in.y < b.y0 + b.ny));
      }
    }
    if (R >= 4) CHECK(band > 0);  // the band exists: R = 1..3 have no invalid texel the disk reaches
  }
}

TEMPLATE_TEST_CASE("texel grid: patch blocks are the texel off the rim and 2 x 2 on a rim texel's outer side",
                   "[paraboloid]", float, double) {
  using T = TestType;
  for (int R : {36, 37}) {
    int rim = 0;
    for (int y = 0; y < R; ++y)
      for (int x = 0; x < R; ++x) {
        const vplkit::texel_block b = vplkit::texel_patch_block(x, y, R);
        INFO("R " << R << " texel (" << x << ", " << y << ")");
        for (T a : {T(0), T(0.25), T(0.5), T(0.999), T(1)}) {
          const vec2<T> xi(a, T(1) - a);
          if (!vplkit::texel_is_rim(x, y, R)) {
            REQUIRE((b.x0 == x && b.y0 == y && b.nx == 1 && b.ny == 1));
            REQUIRE(vplkit::texel_block_point_uv(b, R, xi) == vplkit::texel_point_uv(x, y, R, xi));
            REQUIRE(vplkit::texel_block_point_solid_angle(vplkit::texel_point_uv(x, y, R, xi), b, R) ==
                    vplkit::texel_point_solid_angle(vplkit::texel_point_uv(x, y, R, xi), R));
            continue;
          }
          // the block holds the texel, and its corners are texel corners
          REQUIRE((x >= b.x0 && x < b.x0 + b.nx && y >= b.y0 && y < b.y0 + b.ny));
          REQUIRE((b.nx == 2 || (b.nx == 3 && 2 * x + 1 == R)));
          REQUIRE((b.ny == 2 || (b.ny == 3 && 2 * y + 1 == R)));
          CHECK(vplkit::texel_block_point_uv(b, R, vec2<T>(T(0))) == vplkit::texel_point_uv(b.x0, b.y0, R, vec2<T>(T(0))));
          CHECK(vplkit::texel_block_point_uv(b, R, vec2<T>(T(1))) ==
                vplkit::texel_point_uv(b.x0 + b.nx - 1, b.y0 + b.ny - 1, R, vec2<T>(T(1))));
        }
        rim += vplkit::texel_is_rim(x, y, R);
      }
    CHECK(!vplkit::texel_is_rim(R / 2, R / 2, R));
    CHECK(!vplkit::texel_is_rim(0, 0, R));  // invalid
    CHECK(rim > 2 * R);  // a ring about the circumference (pi R texel widths) long, one or two deep
    CHECK(rim < 8 * R);
  }
}
