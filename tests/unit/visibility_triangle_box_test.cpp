// SPDX-License-Identifier: MIT
// Unit tests of the SAT triangle/box overlap test against an independent reference: clipping the
// triangle by the six closed half-spaces of the box (Sutherland-Hodgman, long double) leaves
// something iff they overlap. Near-touching configurations, where the answer depends on the last
// bits, are skipped: the reference is evaluated with the box shrunk and grown by a small eps and
// a case counts only when both agree.
#include <vplkit/visibility/triangle_box_overlap.hpp>

#include <catch2/catch.hpp>

#include <random>
#include <vector>

namespace {

using lvec = glm::vec<3, long double, glm::defaultp>;

bool clip_reference(lvec c, lvec h, lvec a, lvec b, lvec d) {
  std::vector<lvec> poly = {a, b, d};
  for (int axis = 0; axis < 3; ++axis) {
    for (int side = 0; side < 2; ++side) {
      // Keep s * (p[axis] - c[axis]) <= h[axis].
      const long double s = side == 0 ? 1.0L : -1.0L;
      std::vector<lvec> out;
      for (std::size_t i = 0; i < poly.size(); ++i) {
        const lvec p = poly[i], q = poly[(i + 1) % poly.size()];
        const long double fp = s * (p[axis] - c[axis]) - h[axis], fq = s * (q[axis] - c[axis]) - h[axis];
        if (fp <= 0) out.push_back(p);
        if ((fp < 0 && fq > 0) || (fp > 0 && fq < 0)) out.push_back(p + (q - p) * (fp / (fp - fq)));
      }
      poly = out;
      if (poly.empty()) return false;
    }
  }
  return true;
}

template <class T>
void compare_with_reference(std::uint32_t seed, int degenerate_mode) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int overlaps = 0, separated = 0, skipped = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    using v3 = vplkit::vec3<T>;
    const v3 c(T(u(rng) * 0.5), T(u(rng) * 0.5), T(u(rng) * 0.5));
    const v3 h(T(0.05 + 0.5 * (u(rng) + 1.0)), T(0.05 + 0.5 * (u(rng) + 1.0)), T(0.05 + 0.5 * (u(rng) + 1.0)));
    const double scale = 0.2 + 2.0 * (u(rng) + 1.0);
    const v3 a(T(u(rng) * 2.0), T(u(rng) * 2.0), T(u(rng) * 2.0));
    v3 b = a + v3(T(u(rng) * scale), T(u(rng) * scale), T(u(rng) * scale));
    v3 d = a + v3(T(u(rng) * scale), T(u(rng) * scale), T(u(rng) * scale));
    if (degenerate_mode == 1) d = a + T(u(rng) * 2.0) * (b - a);  // (nearly) collinear
    if (degenerate_mode == 2) d = b;                              // repeated vertex: a segment
    if (degenerate_mode == 3) b = d = a;                          // a point
    const long double eps = 1e-5L;
    const lvec lc(c), lh(h), la(a), lb(b), ld(d);
    const bool grown = clip_reference(lc, lh + lvec(eps), la, lb, ld);
    const bool shrunk = clip_reference(lc, lh - lvec(eps), la, lb, ld);
    if (grown != shrunk) {
      ++skipped;
      continue;
    }
    INFO("trial " << trial);
    REQUIRE(vplkit::triangle_box_overlap(c, h, a, b, d) == grown);
    // Vertex order and which vertex comes first do not matter.
    REQUIRE(vplkit::triangle_box_overlap(c, h, d, b, a) == grown);
    REQUIRE(vplkit::triangle_box_overlap(c, h, b, d, a) == grown);
    (grown ? overlaps : separated) += 1;
  }
  CHECK(overlaps > (degenerate_mode == 0 ? 2000 : 300));
  CHECK(separated > 2000);
  CHECK(skipped < 200);
}

}  // namespace

TEST_CASE("triangle/box overlap agrees with polygon clipping (random, double)", "[visibility]") {
  compare_with_reference<double>(1u, 0);
}

TEST_CASE("triangle/box overlap agrees with polygon clipping (random, float)", "[visibility]") {
  compare_with_reference<float>(2u, 0);
}

TEST_CASE("triangle/box overlap agrees with clipping on degenerate triangles", "[visibility]") {
  for (int mode = 1; mode <= 3; ++mode) {
    compare_with_reference<double>(10u + std::uint32_t(mode), mode);
    compare_with_reference<float>(20u + std::uint32_t(mode), mode);
  }
}

TEST_CASE("triangle/box overlap: cases that need each kind of axis", "[visibility]") {
  using v3 = vplkit::vec3<double>;
  const v3 c(0.0), h(1.0);
  // Triangle inside the box; box inside the triangle's plane region (no vertex inside).
  REQUIRE(vplkit::triangle_box_overlap(c, h, v3(0.1, 0.1, 0.1), v3(0.2, 0.1, 0.1), v3(0.1, 0.3, 0.2)));
  REQUIRE(vplkit::triangle_box_overlap(c, h, v3(-10, -10, 0.3), v3(10, -10, 0.3), v3(0, 10, 0.3)));
  // Separated by a box normal.
  REQUIRE_FALSE(vplkit::triangle_box_overlap(c, h, v3(1.01, 0, 0), v3(3, 1, 0), v3(3, 0, 1)));
  // Separated only by the triangle normal: its AABB covers the box, its plane x+y+z = 3.2 does not
  // reach the box corner (x+y+z <= 3).
  REQUIRE_FALSE(vplkit::triangle_box_overlap(c, h, v3(3.2, 0, 0), v3(0, 3.2, 0), v3(0, 0, 3.2)));
  REQUIRE(vplkit::triangle_box_overlap(c, h, v3(2.9, 0, 0), v3(0, 2.9, 0), v3(0, 0, 2.9)));
  // Separated only by an edge axis: the AABB overlaps the box, the plane cuts the box, but every
  // point of the triangle has x + y >= 2.5 while the box has x + y <= 2 (edge AB x unit z).
  const v3 A(0, 2.5, 0), B(2.5, 0, 0), C(3, 3, -3);
  REQUIRE_FALSE(vplkit::triangle_box_overlap(c, h, A, B, C));
  const v3 n = glm::cross(B - A, C - A);
  REQUIRE(std::abs(glm::dot(n, A)) < std::abs(n.x) + std::abs(n.y) + std::abs(n.z));  // plane cuts the box
}

TEST_CASE("triangle/box overlap: touching counts (closed sets)", "[visibility]") {
  using v3 = vplkit::vec3<float>;
  const v3 c(0.5f), h(0.5f);  // the unit cube [0, 1]^3
  // Lying exactly on a face, from inside the face and from outside overlapping part of it.
  REQUIRE(vplkit::triangle_box_overlap(c, h, v3(0.2f, 0.2f, 1.0f), v3(0.8f, 0.2f, 1.0f), v3(0.2f, 0.8f, 1.0f)));
  REQUIRE(vplkit::triangle_box_overlap(c, h, v3(-1, -1, 0), v3(3, -1, 0), v3(-1, 3, 0)));
  // Touching at one vertex of the triangle, at a box corner, along an edge.
  REQUIRE(vplkit::triangle_box_overlap(c, h, v3(1, 1, 1), v3(2, 1, 1), v3(1, 2, 2)));
  // An edge passing exactly through the box corner (1, 1, 1), the rest of the triangle outside.
  REQUIRE(vplkit::triangle_box_overlap(c, h, v3(0.5f, 1.5f, 1), v3(1.5f, 0.5f, 1), v3(2, 2, 2)));
  REQUIRE(vplkit::triangle_box_overlap(c, h, v3(1, 0, 0), v3(1, 1, 0), v3(2, 0.5f, 0)));     // shares an edge of the box
  // The same triangles pushed away by a small distance are separated.
  REQUIRE_FALSE(vplkit::triangle_box_overlap(c, h, v3(1.001f, 1, 1), v3(2, 1, 1), v3(1.001f, 2, 2)));
  REQUIRE_FALSE(vplkit::triangle_box_overlap(c, h, v3(0.2f, 0.2f, 1.001f), v3(0.8f, 0.2f, 1.001f),
                                             v3(0.2f, 0.8f, 1.001f)));
}

TEST_CASE("triangle/box overlap: degenerate triangles (documented behaviour)", "[visibility]") {
  using v3 = vplkit::vec3<double>;
  const v3 c(0.0), h(1.0);
  // A segment through the box; one passing beside a box edge (only an edge axis separates it);
  // one touching a box corner exactly.
  REQUIRE(vplkit::triangle_box_overlap(c, h, v3(-3, 0, 0), v3(3, 0.5, 0), v3(0, 0.25, 0)));
  REQUIRE_FALSE(vplkit::triangle_box_overlap(c, h, v3(0, 2.5, 0.5), v3(2.5, 0, 0.5), v3(1.25, 1.25, 0.5)));
  REQUIRE(vplkit::triangle_box_overlap(c, h, v3(0, 2, 0.5), v3(2, 0, 0.5), v3(1, 1, 0.5)));
  REQUIRE(vplkit::triangle_box_overlap(c, h, v3(0, 2, 1), v3(2, 0, 1), v3(2, 0, 1)));
  // A zero-area triangle with all three vertices equal: the point test.
  REQUIRE(vplkit::triangle_box_overlap(c, h, v3(1, 1, 1), v3(1, 1, 1), v3(1, 1, 1)));
  REQUIRE(vplkit::triangle_box_overlap(c, h, v3(0.3), v3(0.3), v3(0.3)));
  REQUIRE_FALSE(vplkit::triangle_box_overlap(c, h, v3(1, 1, 1.5), v3(1, 1, 1.5), v3(1, 1, 1.5)));
  // A zero-size box is a point: overlap iff the point lies on the triangle.
  REQUIRE(vplkit::triangle_box_overlap(v3(0.25, 0.25, 0), v3(0.0), v3(0, 0, 0), v3(1, 0, 0), v3(0, 1, 0)));
  REQUIRE_FALSE(vplkit::triangle_box_overlap(v3(0.75, 0.75, 0), v3(0.0), v3(0, 0, 0), v3(1, 0, 0), v3(0, 1, 0)));
}
