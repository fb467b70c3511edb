// SPDX-License-Identifier: MIT
// Unit tests of the triangle voxel grid's offset contract (triangle_voxel_query.hpp:
// triangle_voxel_visible_offset, triangle_voxel_first_hit_offset) and of the hits' shading normals
// (triangle_corners.hpp, triangle_voxel_tracer's corners): against brute force over the moved ends
// in double, and against the library's exact BVH (bvh_visibility.hpp), whose contract it is.
#include <vplkit/visibility/bvh_build.hpp>
#include <vplkit/visibility/bvh_visibility.hpp>
#include <vplkit/visibility/triangle_corners.hpp>
#include <vplkit/visibility/triangle_voxel_query.hpp>
#include <vplkit/visibility/visibility_callables.hpp>
#include <vplkit/visibility/voxelize_triangles.hpp>

#include <triangle_scene_reference.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <vector>

using vplkit::ivec3;
using vplkit_test::d3;

namespace {

template <class T>
struct mesh {
  std::vector<vplkit::vec3<T>> p;
  std::vector<std::uint32_t> idx;
};

// n random triangles in [0, 1]^3, every fourth sharing an edge with the one before, some large.
template <class T>
mesh<T> random_mesh(std::mt19937& rng, int n) {
  std::uniform_real_distribution<double> u(0.0, 1.0), s(-0.25, 0.25);
  mesh<T> m;
  for (int i = 0; i < n; ++i) {
    const std::uint32_t b = std::uint32_t(m.p.size());
    const d3 c(u(rng), u(rng), u(rng));
    const double scale = i % 5 == 0 ? 3.0 : 1.0;
    for (int k = 0; k < 3; ++k)
      m.p.push_back(vplkit::vec3<T>(glm::clamp(c + scale * d3(s(rng), s(rng), s(rng)), d3(0.0), d3(1.0))));
    if (i % 4 == 1 && b >= 3)
      m.idx.insert(m.idx.end(), {b - 3, b - 2, b});
    else
      m.idx.insert(m.idx.end(), {b, b + 1, b + 2});
  }
  return m;
}

template <class T>
vplkit::triangle_voxel_grid<T> build(const mesh<T>& m, ivec3 res) {
  return vplkit::voxelize_triangles(vplkit::vec3<T>(T(-0.02)), vplkit::vec3<T>(T(1.03)), res, m.p.data(), m.p.size(),
                                    m.idx.data(), m.idx.size());
}

// A surface point and its normal: on a random triangle (either side) or, for every third, in the air
// with a random normal.
template <class T>
void random_end(const std::vector<vplkit_test::ref_triangle>& tris, std::mt19937& rng, int i, d3& p, d3& n) {
  std::uniform_real_distribution<double> u(-0.05, 1.05), s(-1.0, 1.0);
  if (i % 3 == 0) {
    p = d3(u(rng), u(rng), u(rng));
    n = d3(s(rng), s(rng), s(rng));
    return;
  }
  const vplkit_test::ref_triangle& t = tris[std::size_t(rng() % tris.size())];
  p = vplkit_test::point_on(t, rng);
  double c = 0.0;
  if (!vplkit_test::ref_plane(t, n, c)) n = d3(0.0, 1.0, 0.0);
  if (rng() % 2 == 0) n = -n;
}

}  // namespace

TEMPLATE_TEST_CASE("triangle voxels, offset contract: visibility and first hits equal brute force over the moved ends",
                   "[visibility][triangle_voxels]", float, double) {
  using T = TestType;
  using v3 = vplkit::vec3<T>;
  std::mt19937 rng(11);
  long checked = 0, ties = 0, blocked = 0, hits = 0;
  for (int trial = 0; trial < 5; ++trial) {
    const mesh<T> m = random_mesh<T>(rng, 25);
    const auto g = build(m, ivec3(8 + 6 * trial));
    const auto v = g.view();
    const auto tris = vplkit_test::ref_triangles(m.p, m.idx);
    const T offset = vplkit::triangle_voxel_surface_offset(v.grid);
    const double slack = double(vplkit::triangle_voxel_offset_slack(v.grid));
    const double L = double(vplkit::voxel_length(v.grid));
    const double delta = (std::is_same<T, float>::value ? 1e-4 : 1e-9) * L;
    for (int i = 0; i < 3000; ++i) {
      d3 x, nx, y, ny;
      random_end<T>(tris, rng, i, x, nx);
      random_end<T>(tris, rng, i + 1, y, ny);
      const v3 xf(x), yf(y), nxf(nx), nyf(ny);
      // The moved ends as the library computes them (bvh_offset_point in T).
      const d3 xo(vplkit::bvh_offset_point(xf, nxf, offset)), yo(vplkit::bvh_offset_point(yf, nyf, offset));
      if (vplkit_test::segment_near_tie(tris, xo, yo, 0.0, slack, delta)) {
        ++ties;
        continue;
      }
      const bool want = !vplkit_test::segment_blocked(tris, xo, yo, 0.0, slack);
      INFO("trial " << trial << " i " << i);
      REQUIRE(vplkit::triangle_voxel_visible_offset(v, xf, nxf, yf, nyf, offset) == want);
      const vplkit::triangle_voxel_visibility<T> adaptor{v, T(vplkit::triangle_voxel_default_end_tolerance),
                                                         vplkit::triangle_voxel_ends::offset, offset};
      REQUIRE(adaptor(xf, nxf, yf, nyf) == want);
      blocked += want ? 0 : 1;
      ++checked;
      // The first hit along x -> y from the moved x.
      if (!(glm::length(yo - xo) > 0.0)) continue;
      const d3 dir = glm::normalize(d3(yf) - d3(xf));
      const double t_lo = vplkit_test::first_hit(tris, xo, dir, delta, std::max(0.0, slack - delta));
      const double t_hi = vplkit_test::first_hit(tris, xo, dir, 0.0, slack + delta);
      if (t_lo != t_hi) continue;  // a near-tie decides which triangle is met first
      const auto h = vplkit::triangle_voxel_first_hit_offset(v, xf, nxf, v3(dir), offset);
      REQUIRE(h.hit == std::isfinite(t_lo));
      if (!h.hit) continue;
      ++hits;
      d3 n(0.0);
      double c = 0.0;
      REQUIRE(vplkit_test::ref_plane(tris[h.triangle], n, c));
      const double cos_in = std::abs(glm::dot(n, dir));
      const double tol = (std::is_same<T, float>::value ? 1e-5 : 1e-12) * (L + t_lo) / cos_in;
      REQUIRE(std::abs(double(h.t) - t_lo) <= tol);
      REQUIRE(glm::length(d3(h.point) - (xo + double(h.t) * dir)) <= tol + 1e-6 * L);
    }
  }
  INFO("checked " << checked << ", near-ties skipped " << ties << ", blocked " << blocked << ", hits " << hits);
  REQUIRE(checked > 12000);
  REQUIRE(ties < checked / 50);
  REQUIRE(blocked > checked / 10);
  REQUIRE(blocked < checked * 9 / 10);
  REQUIRE(hits > checked / 10);
}

TEST_CASE("triangle voxels, offset contract: the same answers as the library's BVH with the same offset",
          "[visibility][triangle_voxels]") {
  using v3 = vplkit::vec3<float>;
  std::mt19937 rng(5);
  long pairs = 0, differ = 0, blocked = 0;
  for (int trial = 0; trial < 4; ++trial) {
    const mesh<float> m = random_mesh<float>(rng, 40);
    const auto g = build(m, ivec3(24));
    const auto v = g.view();
    const auto tris = vplkit_test::ref_triangles(m.p, m.idx);
    const vplkit::bvh<float> b = vplkit::build_bvh(m.p.data(), m.p.size(), m.idx.data(), m.idx.size());
    const float offset = vplkit::bvh_surface_offset(b.view());
    for (int i = 0; i < 4000; ++i) {
      d3 x, nx, y, ny;
      random_end<float>(tris, rng, i, x, nx);
      random_end<float>(tris, rng, i + 2, y, ny);
      const bool exact = vplkit::bvh_visible(b.view(), v3(x), v3(nx), v3(y), v3(ny));
      const bool voxels = vplkit::triangle_voxel_visible_offset(v, v3(x), v3(nx), v3(y), v3(ny), offset);
      ++pairs;
      blocked += exact ? 0 : 1;
      differ += exact != voxels ? 1 : 0;
    }
  }
  INFO("pairs " << pairs << ", differ " << differ << ", blocked " << blocked);
  // The two differ only where a segment passes within the slack (2^-18 of the largest coordinate)
  // of a triangle's edge or an end within rounding of a plane: none in 16,000 random pairs.
  REQUIRE(differ <= pairs / 4000);
  REQUIRE(blocked > pairs / 10);
}

TEST_CASE("triangle voxels, offset contract: ends, non-finite input, the ray's reach", "[visibility][triangle_voxels]") {
  using v3 = vplkit::vec3<float>;
  // One triangle in the plane z = 0.5, facing +z.
  const mesh<float> m{{v3(0.1f, 0.1f, 0.5f), v3(0.9f, 0.1f, 0.5f), v3(0.1f, 0.9f, 0.5f)}, {0, 1, 2}};
  const auto g = build(m, ivec3(8));
  const auto v = g.view();
  const float off = 0.01f;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  // Across the triangle: blocked; ends on it, moved off along the normals given, are not.
  CHECK_FALSE(vplkit::triangle_voxel_visible_offset(v, v3(0.3f, 0.3f, 0.2f), v3(0, 0, 1), v3(0.3f, 0.3f, 0.8f),
                                                    v3(0, 0, -1), off));
  CHECK(vplkit::triangle_voxel_visible_offset(v, v3(0.3f, 0.3f, 0.5f), v3(0, 0, 1), v3(0.4f, 0.2f, 0.9f), v3(0, 0, -1),
                                              off));
  // An end on the triangle moved to its other side is behind it (what the normal given says).
  CHECK_FALSE(vplkit::triangle_voxel_visible_offset(v, v3(0.3f, 0.3f, 0.5f), v3(0, 0, -1), v3(0.4f, 0.2f, 0.9f),
                                                    v3(0, 0, -1), off));
  // A moved end exactly on a plane counts as a crossing (t in (0, 1], as bvh_occluded's range).
  CHECK_FALSE(vplkit::triangle_voxel_segment_free(v, v3(0.3f, 0.3f, 0.75f), v3(0.3f, 0.3f, 0.5f), 0.0f));
  CHECK(vplkit::triangle_voxel_segment_free(v, v3(0.3f, 0.3f, 0.5f), v3(0.3f, 0.3f, 0.75f), 0.0f));
  // A zero or non-finite normal leaves its point where it is; non-finite points are not visible.
  CHECK(vplkit::triangle_voxel_visible_offset(v, v3(0.3f, 0.3f, 0.7f), v3(0.0f), v3(0.4f, 0.2f, 0.9f), v3(nan), off));
  CHECK_FALSE(vplkit::triangle_voxel_visible_offset(v, v3(nan), v3(0, 0, 1), v3(0.5f), v3(0, 0, 1), off));
  CHECK_FALSE(vplkit::triangle_voxel_first_hit_offset(v, v3(nan), v3(0, 0, 1), v3(0, 0, 1), off).hit);
  // The first hit from below, from a point moved along -z, and its reach.
  const auto h = vplkit::triangle_voxel_first_hit_offset(v, v3(0.3f, 0.3f, 0.2f), v3(0, 0, -1), v3(0, 0, 1), off);
  REQUIRE(h.hit);
  CHECK(h.t == Approx(0.31).epsilon(1e-5));
  CHECK(h.point.z == Approx(0.5).epsilon(1e-6));
  CHECK(h.triangle == 0u);
  CHECK_FALSE(vplkit::triangle_voxel_first_hit_offset(v, v3(0.3f, 0.3f, 0.2f), v3(0, 0, -1), v3(0, 0, 1), off, 0.3f).hit);
  // The tracer adaptor's reach is x's: reach + offset from the moved origin.
  vplkit::triangle_voxel_tracer<float> tr{v};
  tr.ends = vplkit::triangle_voxel_ends::offset;
  tr.offset = off;
  CHECK(tr.trace_within(v3(0.3f, 0.3f, 0.2f), v3(0, 0, -1), v3(0, 0, 1), 0.3001f).hit);
  CHECK_FALSE(tr.trace_within(v3(0.3f, 0.3f, 0.2f), v3(0, 0, -1), v3(0, 0, 1), 0.29f).hit);
}

TEST_CASE("triangle corners: the shading normal interpolates the corners' normals", "[visibility][triangle_voxels]") {
  using v3 = vplkit::vec3<float>;
  const std::vector<v3> pos = {v3(0, 0, 0), v3(1, 0, 0), v3(0, 1, 0),  // triangle 0
                               v3(0, 0, 1), v3(0, 0, 1), v3(1, 1, 1)}; // triangle 1: degenerate
  const std::vector<v3> nrm = {v3(0, 0, 1), v3(1, 0, 1), v3(0, 2, 2), v3(0, 0, 1), v3(0, 0, 1), v3(0, 0, 1)};
  const vplkit::triangle_corner_view<float> c{pos.data(), nrm.data(), 2};
  const auto close = [](v3 a, v3 b) { return glm::length(a - b) < 1e-6f; };
  CHECK(close(vplkit::triangle_corner_shading_normal(c, 0, v3(0, 0, 0)), v3(0, 0, 1)));
  CHECK(close(vplkit::triangle_corner_shading_normal(c, 0, v3(1, 0, 0)), glm::normalize(v3(1, 0, 1))));
  CHECK(close(vplkit::triangle_corner_shading_normal(c, 0, v3(0, 1, 0)), glm::normalize(v3(0, 1, 1))));
  // Halfway along the edge 0-1: the mean of the two corners' (unnormalised) normals.
  CHECK(close(vplkit::triangle_corner_shading_normal(c, 0, v3(0.5f, 0, 0)), glm::normalize(v3(0.5f, 0, 1))));
  // A point a hair outside (the grid's slack) is clamped to the triangle: corner 1's normal.
  CHECK(close(vplkit::triangle_corner_shading_normal(c, 0, v3(1.001f, -0.001f, 0)), glm::normalize(v3(1, 0, 1))));
  // None: a degenerate triangle, an index out of range, a view without normals.
  CHECK(vplkit::triangle_corner_shading_normal(c, 1, v3(0, 0, 1)) == v3(0.0f));
  CHECK(vplkit::triangle_corner_shading_normal(c, 2, v3(0, 0, 0)) == v3(0.0f));
  CHECK(vplkit::triangle_corner_shading_normal(vplkit::triangle_corner_view<float>{}, 0, v3(0, 0, 0)) == v3(0.0f));
  // Normals that cancel at the point.
  const std::vector<v3> opposite = {v3(0, 0, 1), v3(0, 0, -1), v3(0, 0, 1)};
  const vplkit::triangle_corner_view<float> o{pos.data(), opposite.data(), 1};
  CHECK(vplkit::triangle_corner_shading_normal(o, 0, v3(0.5f, 0, 0)) == v3(0.0f));
}

TEST_CASE("triangle voxels: the tracer hands back the corners' shading normal where it has them",
          "[visibility][triangle_voxels]") {
  using v3 = vplkit::vec3<float>;
  const mesh<float> m{{v3(0.1f, 0.1f, 0.5f), v3(0.9f, 0.1f, 0.5f), v3(0.1f, 0.9f, 0.5f)}, {0, 1, 2}};
  const std::vector<v3> nrm = {v3(0, 0, 1), v3(1, 0, 1), v3(0, 0, 1)};
  const auto g = build(m, ivec3(8));
  for (const auto ends : {vplkit::triangle_voxel_ends::plane_rule, vplkit::triangle_voxel_ends::offset}) {
    vplkit::triangle_voxel_tracer<float> tr{g.view()};
    tr.ends = ends;
    tr.offset = 0.01f;
    const auto without = tr(v3(0.5f, 0.3f, 0.9f), v3(0, 0, 1), v3(0, 0, -1));
    REQUIRE(without.hit);
    CHECK(without.shading_normal == v3(0.0f));
    tr.corners = vplkit::triangle_corner_view<float>{m.p.data(), nrm.data(), 1};
    const auto with = tr(v3(0.5f, 0.3f, 0.9f), v3(0, 0, 1), v3(0, 0, -1));
    REQUIRE(with.hit);
    CHECK(with.normal == without.normal);
    CHECK(glm::length(with.shading_normal - vplkit::triangle_corner_shading_normal(tr.corners, 0, with.position)) == 0.0f);
    CHECK(with.shading_normal.x > 0.1f);  // corner 1's normal leans towards +x
  }
}
