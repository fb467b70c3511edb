// SPDX-License-Identifier: MIT
// Unit tests of the triangle voxel grid (include/vplkit/visibility/triangle_voxel_grid.hpp,
// voxelize_triangles.hpp, triangle_voxel_query.hpp): layout against brute force, the triangle
// records, validation, and visibility / first hits against exact brute force on random scenes.
#include <vplkit/visibility/triangle_box_overlap.hpp>
#include <vplkit/visibility/triangle_voxel_grid.hpp>
#include <vplkit/visibility/triangle_voxel_query.hpp>
#include <vplkit/visibility/voxelize_triangles.hpp>

#include <triangle_scene_reference.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <set>
#include <vector>

using vplkit::ivec3;
using vplkit_test::d3;

namespace {

template <class T>
struct mesh {
  std::vector<vplkit::vec3<T>> p;
  std::vector<std::uint32_t> idx;
};

// n random triangles in [0, 1]^3: mostly small, some large, some degenerate (a repeated vertex,
// collinear), some sharing vertices with the previous one.
template <class T>
mesh<T> random_mesh(std::mt19937& rng, int n) {
  std::uniform_real_distribution<double> u(0.0, 1.0), s(-0.25, 0.25);
  mesh<T> m;
  for (int i = 0; i < n; ++i) {
    const std::uint32_t b = std::uint32_t(m.p.size());
    const d3 c(u(rng), u(rng), u(rng));
    const double scale = i % 5 == 0 ? 3.0 : 1.0;
    d3 v[3] = {c + scale * d3(s(rng), s(rng), s(rng)), c + scale * d3(s(rng), s(rng), s(rng)),
               c + scale * d3(s(rng), s(rng), s(rng))};
    if (i % 11 == 3) v[2] = v[0];  // repeated vertex
    if (i % 11 == 7) {             // exactly collinear: dyadic coordinates, exact sums
      for (d3& q : v) q = glm::floor(q * 1024.0) / 1024.0;
      v[1] = glm::clamp(v[0] + d3(0.125, -0.0625, 0.25), d3(0.0), d3(1.0));
      v[2] = 0.5 * (v[0] + v[1]);
    }
    for (const d3& q : v) m.p.push_back(vplkit::vec3<T>(glm::clamp(q, d3(0.0), d3(1.0))));
    if (i % 4 == 1 && b >= 3) {  // shares an edge with the previous triangle
      m.idx.insert(m.idx.end(), {b - 3, b - 2, b});
    } else {
      m.idx.insert(m.idx.end(), {b, b + 1, b + 2});
    }
  }
  return m;
}

template <class T>
vplkit::triangle_voxel_grid<T> build(const mesh<T>& m, ivec3 res) {
  return vplkit::voxelize_triangles(vplkit::vec3<T>(T(-0.02)), vplkit::vec3<T>(T(1.03)), res, m.p.data(), m.p.size(),
                                    m.idx.data(), m.idx.size());
}

}  // namespace

TEMPLATE_TEST_CASE("triangle voxels: lists equal the overlap test, rank and offsets are consistent",
                   "[visibility][triangle_voxels]", float, double) {
  using T = TestType;
  std::mt19937 rng(11);
  for (int trial = 0; trial < 4; ++trial) {
    const mesh<T> m = random_mesh<T>(rng, 30);
    const ivec3 res(9 + trial, 12, 7 + 2 * trial);
    const vplkit::triangle_voxel_grid<T> g = build(m, res);
    const vplkit::triangle_voxel_view<T> v = g.view();
    // The occupancy is voxelize's.
    vplkit::voxel_grid<T> occ(vplkit::vec3<T>(T(-0.02)), vplkit::vec3<T>(T(1.03)), res);
    vplkit::voxelize(occ, m.p.data(), m.p.size(), m.idx.data(), m.idx.size());
    REQUIRE(occ.words() == g.occupancy().words());
    REQUIRE(g.occupied_count() == occ.count());
    const d3 bmin(v.grid.bounds_min), size = (d3(v.grid.bounds_max) - bmin) / d3(res);
    std::int64_t expected_index = 0, one_plane = 0;
    for (int z = 0; z < res.z; ++z)
      for (int y = 0; y < res.y; ++y)
        for (int x = 0; x < res.x; ++x) {
          const ivec3 c(x, y, z);
          std::set<std::uint32_t> want;
          for (std::size_t t = 0; t < m.idx.size() / 3; ++t) {
            d3 q[3];
            for (int k = 0; k < 3; ++k) q[k] = (d3(m.p[m.idx[3 * t + std::size_t(k)]]) - bmin) / size;
            if (vplkit::triangle_box_overlap(d3(c) + d3(0.5), d3(0.5 + vplkit::voxelize_default_margin), q[0], q[1], q[2]))
              want.insert(std::uint32_t(t));
          }
          const std::int64_t r = vplkit::voxel_occupied_index(v.grid, v.rank, c);
          if (!occ.test(c)) {
            REQUIRE(r == -1);
            REQUIRE(want.empty());
            continue;
          }
          REQUIRE(r == expected_index++);  // dense indices in flat-index order
          const std::vector<std::uint32_t> got(v.entries + v.offsets[r], v.entries + v.offsets[r + 1]);
          REQUIRE(std::is_sorted(got.begin(), got.end()));
          REQUIRE(std::set<std::uint32_t>(got.begin(), got.end()) == want);
          REQUIRE(got.size() == want.size());
          // planes[r]: the listed triangles' plane when all have it bit for bit, else the mark.
          const auto& plane = v.planes[r];
          bool shared = !got.empty();
          for (std::uint32_t t : got) {
            const auto& q = v.triangles[t].plane;
            shared = shared && q.normal == v.triangles[got[0]].plane.normal && q.offset == v.triangles[got[0]].plane.offset;
          }
          REQUIRE(vplkit::voxel_plane_is_several(plane) == !shared);
          if (shared) {
            REQUIRE(plane.normal == v.triangles[got[0]].plane.normal);
            REQUIRE(plane.offset == v.triangles[got[0]].plane.offset);
            ++one_plane;
          }
        }
    REQUIRE(vplkit::voxel_occupied_index(v.grid, v.rank, ivec3(-1, 0, 0)) == -1);
    REQUIRE(vplkit::voxel_occupied_index(v.grid, v.rank, res) == -1);
    REQUIRE(g.memory_bytes() == 4 * (g.occupancy().word_count() + g.rank().size() + g.offsets().size() +
                                     g.entries().size() + g.bricks().size()) +
                                    sizeof(vplkit::voxel_triangle<T>) * g.triangles().size() +
                                    sizeof(vplkit::voxel_plane<T>) * g.occupancy().count());
    REQUIRE(g.bricks() == vplkit::voxel_brick_words(v.grid));
    REQUIRE(v.bricks == g.bricks().data());
    REQUIRE(v.planes == g.planes().data());
    REQUIRE(g.planes().size() == std::size_t(g.occupied_count()));
    REQUIRE(one_plane > 0);  // random triangles: voxels that list one of them
    REQUIRE(one_plane < g.occupied_count());
  }
}

TEST_CASE("triangle voxels: the record's inside test and degenerate triangles", "[visibility][triangle_voxels]") {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-2.0, 2.0), w(-0.2, 1.2);
  for (int i = 0; i < 2000; ++i) {
    const d3 a(u(rng), u(rng), u(rng)), b(u(rng), u(rng), u(rng)), c(u(rng), u(rng), u(rng));
    const vplkit::voxel_triangle<double> t = vplkit::make_voxel_triangle(a, b, c);
    REQUIRE(glm::length(t.plane.normal) == Approx(1.0));
    for (int k = 0; k < 3; ++k) {
      REQUIRE(glm::dot(t.plane.normal, (k == 0 ? a : k == 1 ? b : c)) - t.plane.offset == Approx(0.0).margin(1e-12));
      REQUIRE(glm::dot(t.edge[k].normal, t.plane.normal) == Approx(0.0).margin(1e-12));
    }
    for (int j = 0; j < 20; ++j) {
      const double s = w(rng), r = w(rng);
      const d3 p = a + s * (b - a) + r * (c - a);
      const bool inside = s >= 0.0 && r >= 0.0 && s + r <= 1.0;
      const bool clear = std::min(std::min(s, r), 1.0 - s - r) > 1e-9 || std::min(std::min(s, r), 1.0 - s - r) < -1e-9;
      if (clear) REQUIRE(vplkit::voxel_triangle_contains(t, p, 0.0) == inside);
    }
  }
  // Degenerate: repeated vertex, collinear, a point, non-finite: all four planes zero.
  const d3 a(0.1, 0.2, 0.3), b(0.4, 0.5, 0.6);
  for (const auto& t : {vplkit::make_voxel_triangle(a, a, b), vplkit::make_voxel_triangle(a, b, 0.5 * (a + b)),
                        vplkit::make_voxel_triangle(a, a, a),
                        vplkit::make_voxel_triangle(a, b, d3(std::numeric_limits<double>::infinity(), 0.0, 0.0))}) {
    REQUIRE(t.plane.normal == d3(0.0));
    REQUIRE(t.plane.offset == 0.0);
    for (const auto& e : t.edge) REQUIRE(e.normal == d3(0.0));
  }
}

TEST_CASE("triangle voxels: the adopting constructor checks its arrays", "[visibility][triangle_voxels]") {
  std::mt19937 rng(5);
  const mesh<float> m = random_mesh<float>(rng, 10);
  const auto g = build(m, ivec3(8));
  auto adopt = [&](std::vector<std::uint32_t> rank, std::vector<std::uint32_t> offsets, std::vector<std::uint32_t> entries) {
    return vplkit::triangle_voxel_grid<float>(g.occupancy(), std::move(rank), std::move(offsets), std::move(entries),
                                              g.triangles());
  };
  REQUIRE_NOTHROW(adopt(g.rank(), g.offsets(), g.entries()));
  auto rank = g.rank();
  rank.back() += 1;
  REQUIRE_THROWS_WITH(adopt(rank, g.offsets(), g.entries()), Catch::Contains("rank"));
  auto offsets = g.offsets();
  offsets.pop_back();
  REQUIRE_THROWS_WITH(adopt(g.rank(), offsets, g.entries()), Catch::Contains("offsets given"));
  offsets = g.offsets();
  std::swap(offsets[1], offsets[2]);
  if (offsets[1] != offsets[2]) REQUIRE_THROWS_WITH(adopt(g.rank(), offsets, g.entries()), Catch::Contains("decrease"));
  auto entries = g.entries();
  entries[0] = 1000;
  REQUIRE_THROWS_WITH(adopt(g.rank(), g.offsets(), entries), Catch::Contains("entry 0"));
  entries.pop_back();
  REQUIRE_THROWS_WITH(adopt(g.rank(), g.offsets(), entries), Catch::Contains("entry count"));
  // Bad meshes are refused as voxelize refuses them, naming the triangle.
  std::vector<std::uint32_t> bad = m.idx;
  bad[4] = 999;
  REQUIRE_THROWS_WITH(vplkit::voxelize_triangles(vplkit::vec3<float>(0.0f), vplkit::vec3<float>(1.0f), ivec3(4),
                                                 m.p.data(), m.p.size(), bad.data(), bad.size()),
                      Catch::Contains("triangle 1"));
}

TEMPLATE_TEST_CASE("triangle voxels: visibility and first hits equal exact brute force", "[visibility][triangle_voxels]",
                   float, double) {
  using T = TestType;
  using v3 = vplkit::vec3<T>;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-0.05, 1.05);
  std::uniform_int_distribution<int> pick(0, 1 << 20);
  long checked = 0, ties = 0, blocked = 0;
  for (int trial = 0; trial < 6; ++trial) {
    const mesh<T> m = random_mesh<T>(rng, 25);
    const auto g = build(m, ivec3(10 + 5 * trial));
    const auto v = g.view();
    const auto tris = vplkit_test::ref_triangles(m.p, m.idx);
    const double L = double(vplkit::voxel_length(v.grid));
    const double eps = vplkit::triangle_voxel_default_end_tolerance * L;
    const double slack = vplkit::triangle_voxel_edge_slack * L;
    // Float: ends are rounded to float, the records too: a tie margin of 1e-4 voxel.
    const double delta = (std::is_same<T, float>::value ? 1e-4 : 1e-9) * L;
    for (int i = 0; i < 3000; ++i) {
      // Ends on triangles (the estimators' case) or in the air.
      const d3 x = i % 3 == 0 ? d3(u(rng), u(rng), u(rng)) : vplkit_test::point_on(tris[std::size_t(pick(rng)) % tris.size()], rng);
      const d3 y = i % 4 == 0 ? d3(u(rng), u(rng), u(rng)) : vplkit_test::point_on(tris[std::size_t(pick(rng)) % tris.size()], rng);
      const v3 xf(x), yf(y);
      const d3 xr(xf), yr(yf);  // what the grid sees
      if (vplkit_test::segment_near_tie(tris, xr, yr, eps, slack, delta)) {
        ++ties;
        continue;
      }
      const bool want = !vplkit_test::segment_blocked(tris, xr, yr, eps, slack);
      REQUIRE(vplkit::triangle_voxel_visible(v, xf, yf) == want);
      blocked += want ? 0 : 1;
      ++checked;
      // First hit along x -> y from x.
      const d3 dir = glm::normalize(yr - xr);
      if (!(glm::length(yr - xr) > 0.0)) continue;
      const double t_ref = vplkit_test::first_hit(tris, xr, dir, eps, slack);
      const double t_lo = vplkit_test::first_hit(tris, xr, dir, eps + delta, std::max(0.0, slack - delta));
      const double t_hi = vplkit_test::first_hit(tris, xr, dir, eps - delta, slack + delta);
      const auto h = vplkit::triangle_voxel_first_hit(v, xf, v3(yr - xr));
      if (t_lo != t_hi) continue;  // a near-tie decides which triangle is met first
      INFO("trial " << trial << " i " << i << " t_ref " << t_ref << " hit " << h.hit << " t " << h.t << " tri " << h.triangle);
      REQUIRE(h.hit == std::isfinite(t_ref));
      if (h.hit) {
        // On the plane of the triangle met, at the reference's distance up to the rounding of
        // the plane's offset, amplified by 1 / cos at grazing incidence.
        d3 n(0.0);
        double c = 0.0;
        REQUIRE(vplkit_test::ref_plane(tris[h.triangle], n, c));
        const double cos_in = std::abs(glm::dot(n, dir));
        const double tol = (std::is_same<T, float>::value ? 1e-5 : 1e-12) * (L + t_ref) / cos_in;
        REQUIRE(std::abs(double(h.t) - t_ref) <= tol);
        REQUIRE(std::abs(glm::dot(n, d3(h.point)) - c) <= (std::is_same<T, float>::value ? 1e-5 : 1e-12) * (1.0 + L));
      }
    }
  }
  INFO("checked " << checked << ", near-ties skipped " << ties << ", blocked " << blocked);
  REQUIRE(checked > 15000);
  REQUIRE(ties < checked / 50);
  REQUIRE(blocked > checked / 10);
  REQUIRE(blocked < checked * 9 / 10);
}

TEST_CASE("triangle voxels: a segment and a ray that miss the grid, zero length, non-finite input",
          "[visibility][triangle_voxels]") {
  std::mt19937 rng(9);
  const mesh<float> m = random_mesh<float>(rng, 20);
  const auto g = build(m, ivec3(16));
  const auto v = g.view();
  using v3 = vplkit::vec3<float>;
  const float inf = std::numeric_limits<float>::infinity(), nan = std::numeric_limits<float>::quiet_NaN();
  REQUIRE(vplkit::triangle_voxel_visible(v, v3(5, 5, 5), v3(6, 7, 5)));       // outside the grid
  REQUIRE(vplkit::triangle_voxel_visible(v, v3(0.5f), v3(0.5f)));            // x == y
  REQUIRE_FALSE(vplkit::triangle_voxel_visible(v, v3(nan, 0, 0), v3(0.5f)));  // non-finite: no contribution
  REQUIRE_FALSE(vplkit::triangle_voxel_visible(v, v3(0.5f), v3(inf, 0, 0)));
  REQUIRE_FALSE(vplkit::triangle_voxel_first_hit(v, v3(5, 5, 5), v3(1, 0, 0)).hit);
  REQUIRE_FALSE(vplkit::triangle_voxel_first_hit(v, v3(0.5f), v3(0.0f)).hit);
  REQUIRE_FALSE(vplkit::triangle_voxel_first_hit(v, v3(nan), v3(1, 0, 0)).hit);
  REQUIRE_FALSE(vplkit::triangle_voxel_first_hit(v, v3(0.5f), v3(1, 0, 0), -1.0f).hit);
  const auto miss = vplkit::triangle_voxel_first_hit(v, v3(0.5f), v3(0.0f));
  REQUIRE(miss.t == 0.0f);
  REQUIRE(miss.point == v3(0.5f));
  REQUIRE(miss.triangle == 0xFFFFFFFFu);
}
