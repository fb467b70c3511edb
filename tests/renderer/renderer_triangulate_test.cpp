// SPDX-License-Identifier: MIT
// Polygon triangulation for OBJ faces: area preserved, winding kept, concave and degenerate
// inputs handled, no hang on large or self-intersecting polygons.
#include <catch2/catch.hpp>

#include "scene/triangulate.hpp"

#include <glm/geometric.hpp>

#include <cmath>
#include <vector>

using namespace vplrender;
using glm::dvec3;

namespace {

double polygon_area(const std::vector<dvec3>& p) {  // planar, via the Newell normal length / 2
  dvec3 n(0.0);
  for (std::size_t i = 0; i < p.size(); ++i) n += glm::cross(p[i], p[(i + 1) % p.size()]);
  return 0.5 * glm::length(n);
}

// Sum of triangle areas, and every triangle wound like the polygon (positive along its normal).
double triangulated_area(const std::vector<dvec3>& p, const triangulation& t) {
  double sum = 0.0;
  for (const auto& tri : t.triangles) {
    const dvec3 c = glm::cross(p[tri[1]] - p[tri[0]], p[tri[2]] - p[tri[0]]);
    CHECK(glm::dot(c, t.normal) > 0.0);
    sum += 0.5 * glm::length(c);
  }
  return sum;
}

// Rotate a planar xy polygon into a tilted plane and move it far from the origin.
std::vector<dvec3> tilt(const std::vector<dvec3>& p) {
  std::vector<dvec3> out;
  const double a = 0.7, b = 0.4;
  for (const dvec3& v : p) {
    const dvec3 r(v.x, v.y * std::cos(a) - v.z * std::sin(a), v.y * std::sin(a) + v.z * std::cos(a));
    out.push_back(dvec3(r.x * std::cos(b) + r.z * std::sin(b), r.y, -r.x * std::sin(b) + r.z * std::cos(b)) +
                  dvec3(1000.0, -2000.0, 500.0));
  }
  return out;
}

}  // namespace

TEST_CASE("convex polygons of 3 to 12 vertices keep their area and winding") {
  for (std::size_t n = 3; n <= 12; ++n) {
    std::vector<dvec3> p;
    for (std::size_t i = 0; i < n; ++i) {
      const double a = 2.0 * 3.141592653589793 * static_cast<double>(i) / static_cast<double>(n);
      p.emplace_back(std::cos(a), std::sin(a), 0.0);
    }
    for (const auto& poly : {p, tilt(p)}) {
      const triangulation t = triangulate_polygon(poly);
      CHECK(t.triangles.size() == n - 2);
      CHECK_FALSE(t.fan_fallback);
      CHECK(triangulated_area(poly, t) == Approx(polygon_area(poly)).epsilon(1e-9));
    }
  }
}

TEST_CASE("a triangle's normal follows its winding") {
  const triangulation ccw = triangulate_polygon({dvec3(0, 0, 0), dvec3(1, 0, 0), dvec3(0, 1, 0)});
  CHECK(ccw.normal.z == Approx(1.0));
  const triangulation cw = triangulate_polygon({dvec3(0, 0, 0), dvec3(0, 1, 0), dvec3(1, 0, 0)});
  CHECK(cw.normal.z == Approx(-1.0));
}

TEST_CASE("concave polygons (L shape, comb, clockwise) are triangulated without overlap") {
  const std::vector<dvec3> l = {dvec3(0, 0, 0), dvec3(2, 0, 0), dvec3(2, 1, 0),
                                dvec3(1, 1, 0), dvec3(1, 2, 0), dvec3(0, 2, 0)};
  std::vector<dvec3> comb = {dvec3(0, 0, 0), dvec3(7, 0, 0)};
  for (int k = 3; k >= 0; --k) {  // teeth pointing up
    comb.emplace_back(2 * k + 1, 3, 0);
    comb.emplace_back(2 * k + 0.5, 1, 0);
    comb.emplace_back(2 * k, 3, 0);
  }
  comb.erase(comb.end() - 1);
  std::vector<dvec3> l_cw(l.rbegin(), l.rend());
  for (const auto& poly : {l, comb, l_cw, tilt(l), tilt(comb)}) {
    const triangulation t = triangulate_polygon(poly);
    CHECK(t.triangles.size() == poly.size() - 2);
    CHECK_FALSE(t.fan_fallback);
    // Equal areas with all triangles positively wound: no overlap, no triangle outside.
    CHECK(triangulated_area(poly, t) == Approx(polygon_area(poly)).epsilon(1e-9));
  }
}

TEST_CASE("collinear vertices are dropped, not turned into slivers") {
  const std::vector<dvec3> a = {dvec3(0, 0, 0), dvec3(1, 0, 0), dvec3(2, 0, 0), dvec3(2, 1, 0), dvec3(0, 1, 0)};
  const std::vector<dvec3> b = {dvec3(1, 0, 0), dvec3(2, 0, 0), dvec3(2, 1, 0), dvec3(0, 1, 0), dvec3(0, 0, 0)};
  for (const auto& p : {a, b}) {
    const triangulation t = triangulate_polygon(p);
    CHECK(triangulated_area(p, t) == Approx(2.0));
    for (const auto& tri : t.triangles)
      CHECK(glm::length(glm::cross(p[tri[1]] - p[tri[0]], p[tri[2]] - p[tri[0]])) > 0.1);
  }
  // Met first, the straight vertex is removed and the rectangle needs only two triangles.
  CHECK(triangulate_polygon(b).triangles.size() == 2);
}

TEST_CASE("degenerate polygons give no triangles") {
  CHECK(triangulate_polygon({dvec3(0, 0, 0), dvec3(1, 1, 1), dvec3(2, 2, 2), dvec3(3, 3, 3)}).triangles.empty());
  CHECK(triangulate_polygon({dvec3(1, 2, 3), dvec3(1, 2, 3), dvec3(1, 2, 3)}).triangles.empty());
  CHECK(triangulate_polygon({dvec3(0, 0, 0), dvec3(1, 0, 0)}).triangles.empty());
  CHECK(triangulate_polygon({}).triangles.empty());
  const double nan = std::nan("");
  CHECK(triangulate_polygon({dvec3(0, 0, 0), dvec3(1, 0, 0), dvec3(nan, 1, 0)}).triangles.empty());
}

TEST_CASE("self-intersecting and very large polygons are fanned, without hanging") {
  // A bow tie: no ear is ever free of the other crossing edge, so the splitter falls back.
  const std::vector<dvec3> bow = {dvec3(0, 0, 0), dvec3(2, 2, 0), dvec3(2, 0, 0), dvec3(0, 2, 0), dvec3(1, 3, 0)};
  const triangulation t = triangulate_polygon(bow);
  CHECK(t.triangles.size() >= 1);
  CHECK(t.triangles.size() <= bow.size() - 2);

  std::vector<dvec3> big;
  const std::size_t n = 100000;
  for (std::size_t i = 0; i < n; ++i) {
    const double a = 2.0 * 3.141592653589793 * static_cast<double>(i) / static_cast<double>(n);
    big.emplace_back(std::cos(a), std::sin(a), 0.0);
  }
  const triangulation tb = triangulate_polygon(big);
  CHECK(tb.fan_fallback);
  CHECK(tb.triangles.size() == n - 2);
}
