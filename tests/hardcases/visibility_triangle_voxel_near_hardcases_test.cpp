// SPDX-License-Identifier: MIT
// Hard cases of the near-surface test (include/vplkit/visibility/triangle_voxel_near.hpp) and of
// the voxels' shared planes it asks (triangle_voxel_grid.hpp): coplanar neighbours (a floor of
// many triangles, one plane per voxel), a crease through x and beside it, a plane at exactly the
// tolerance, empty voxels, boxes wider than voxel_near_max_side. Every answer is also checked
// against triangle_voxel_surface_within_scan (every listed triangle asked: the same answers) and,
// where it is false, against brute force over the triangles (the guarantee).
#include <vplkit/visibility/triangle_voxel_near.hpp>
#include <vplkit/visibility/voxelize_triangles.hpp>
#include <vplkit/vpl/vpl.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

using vplkit::ivec3;

namespace {

template <class T>
using v3 = vplkit::vec3<T>;

template <class T>
struct mesh {
  std::vector<v3<T>> p;
  std::vector<std::uint32_t> idx;
  void quad(v3<T> a, v3<T> b, v3<T> c, v3<T> d) {
    const auto s = std::uint32_t(p.size());
    for (v3<T> q : {a, b, c, d}) p.push_back(q);
    for (std::uint32_t k : {0u, 1u, 2u, 0u, 2u, 3u}) idx.push_back(s + k);
  }
  // The floor z = 0 over [0, 1]^2 as n x n quads (2 n^2 coplanar triangles).
  void tiled_floor(int n) {
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i) {
        const T x0 = T(i) / T(n), x1 = T(i + 1) / T(n), y0 = T(j) / T(n), y1 = T(j + 1) / T(n);
        quad(v3<T>(x0, y0, 0), v3<T>(x1, y0, 0), v3<T>(x1, y1, 0), v3<T>(x0, y1, 0));
      }
  }
  vplkit::triangle_voxel_grid<T> voxelize(int res) const {
    const auto b = vplkit::fit_voxel_bounds(p.data(), p.size(), T(0.03));
    return vplkit::voxelize_triangles(b.min, b.max, ivec3(res), p.data(), p.size(), idx.data(), idx.size());
  }
  // Brute force: is a point of a triangle whose plane passes farther than tol from x within reach
  // of x? (The triangle sampled densely: what the test must never miss.)
  bool other_surface_within(v3<T> x, T reach, T tol) const {
    for (std::size_t t = 0; t < idx.size(); t += 3) {
      const v3<T> a = p[idx[t]], b = p[idx[t + 1]], c = p[idx[t + 2]];
      const v3<T> n = glm::normalize(glm::cross(b - a, c - a));
      if (std::abs(glm::dot(n, x - a)) <= tol) continue;
      for (int i = 0; i <= 32; ++i)
        for (int j = 0; i + j <= 32; ++j)
          if (glm::length(a + (b - a) * (T(i) / T(32)) + (c - a) * (T(j) / T(32)) - x) < reach) return true;
    }
    return false;
  }
};

// The test's answer, checked against the scan (the same answer) and, when false, against brute force.
template <class T>
bool near(const mesh<T>& m, const vplkit::triangle_voxel_grid<T>& g, v3<T> x, T reach, T tol) {
  const bool said = vplkit::triangle_voxel_surface_within(g.view(), x, reach, tol);
  INFO("x " << x.x << " " << x.y << " " << x.z << " reach " << reach << " tol " << tol);
  CHECK(said == vplkit::triangle_voxel_surface_within_scan(g.view(), x, reach, tol));
  // The brute force's planes round differently from the grid's (float): a few ulps of slack.
  const T slack = T(8) * std::numeric_limits<T>::epsilon() * (T(1) + std::abs(x.x) + std::abs(x.y) + std::abs(x.z));
  if (!said) CHECK_FALSE(m.other_surface_within(x, reach, tol + slack));
  return said;
}

template <class T>
T compensation_tolerance(v3<T> x) {
  return vplkit::vpl_coincidence_tolerance(x, x) / T(4);
}

template <class T>
std::size_t one_plane_voxels(const vplkit::triangle_voxel_grid<T>& g) {
  std::size_t n = 0;
  for (const auto& p : g.planes()) n += vplkit::voxel_plane_is_several(p) ? 0u : 1u;
  return n;
}

}  // namespace

TEMPLATE_TEST_CASE("near-surface test: coplanar neighbours share one plane per voxel and are no other surface",
                   "[visibility][triangle_voxels][hardcases]", float, double) {
  using T = TestType;
  mesh<T> m;
  m.tiled_floor(24);  // triangles smaller than a voxel: every floor voxel lists several
  for (int res : {16, 32, 64}) {
    const auto g = m.voxelize(res);
    INFO("resolution " << res);
    // Axis-aligned: every triangle's plane is (0, 0, 1), 0 bit for bit, so every voxel has one plane.
    REQUIRE(one_plane_voxels(g) == g.planes().size());
    for (const auto& p : g.planes()) {
      CHECK(p.normal == v3<T>(0, 0, 1));
      CHECK(p.offset == T(0));
    }
    const T L = T(g.occupancy().voxel_length());
    for (int k = 0; k < 50; ++k) {
      const v3<T> x(T(0.1) + T(0.8) * T(k % 10) / T(10), T(0.1) + T(0.8) * T(k / 10) / T(5), T(0));
      CHECK_FALSE(near(m, g, x, T(1.5) * L, compensation_tolerance(x)));
      // Above the floor by a tenth of a voxel: the floor's plane is another surface within reach.
      CHECK(near(m, g, x + v3<T>(0, 0, T(0.1) * L), T(1.5) * L, compensation_tolerance(x)));
    }
  }
}

TEMPLATE_TEST_CASE("near-surface test: a tilted tiled floor gives the scan's answers", "[visibility][triangle_voxels][hardcases]",
                   float, double) {
  using T = TestType;
  mesh<T> flat;
  flat.tiled_floor(12);
  mesh<T> m;  // the floor tilted about x and z: its triangles' planes round differently
  const T a = T(0.37), b = T(0.61);
  for (const v3<T>& q : flat.p) {
    const v3<T> r(std::cos(a) * q.x - std::sin(a) * q.y, std::sin(a) * q.x + std::cos(a) * q.y, q.z);
    m.p.push_back(v3<T>(r.x, std::cos(b) * r.y - std::sin(b) * r.z, std::sin(b) * r.y + std::cos(b) * r.z));
  }
  m.idx = flat.idx;
  const auto g = m.voxelize(32);
  const T L = T(g.occupancy().voxel_length());
  int trues = 0, falses = 0;
  for (std::size_t t = 0; t < m.idx.size(); t += 3) {
    // each triangle's centroid, on it up to rounding; and a point a voxel above it
    const v3<T> c = (m.p[m.idx[t]] + m.p[m.idx[t + 1]] + m.p[m.idx[t + 2]]) / T(3);
    const v3<T> n = glm::normalize(glm::cross(m.p[m.idx[t + 1]] - m.p[m.idx[t]], m.p[m.idx[t + 2]] - m.p[m.idx[t]]));
    for (const T tol : {compensation_tolerance(c), T(1e-4) * L}) (near(m, g, c, T(1.2) * L, tol) ? trues : falses)++;
    CHECK(near(m, g, c + n * L, T(1.2) * L, compensation_tolerance(c)));
  }
  CHECK(falses > 0);  // with a tolerance above the planes' rounding the floor is one surface
  (void)trues;
}

TEMPLATE_TEST_CASE("near-surface test: a crease through x, and beside it", "[visibility][triangle_voxels][hardcases]", float,
                   double) {
  using T = TestType;
  mesh<T> m;  // the floor z = 0 and the wall x = 0.5 standing on it (a crease along x = 0.5, z = 0)
  m.tiled_floor(8);
  m.quad(v3<T>(T(0.5), 0, 0), v3<T>(T(0.5), 1, 0), v3<T>(T(0.5), 1, 1), v3<T>(T(0.5), 0, 1));
  for (int res : {16, 32, 64}) {
    const auto g = m.voxelize(res);
    INFO("resolution " << res);
    REQUIRE(one_plane_voxels(g) > 0);                  // floor voxels away from the wall
    REQUIRE(one_plane_voxels(g) < g.planes().size());  // the crease's voxels: several
    const T L = T(g.occupancy().voxel_length());
    for (const T y : {T(0.2), T(0.5), T(0.77)}) {
      const v3<T> on_crease(T(0.5), y, T(0));
      CHECK_FALSE(near(m, g, on_crease, T(2) * L, compensation_tolerance(on_crease)));  // both planes pass through x
      const v3<T> on_wall(T(0.5), y, T(0.5));
      CHECK_FALSE(near(m, g, on_wall, T(1.5) * L, compensation_tolerance(on_wall)));  // only the wall within reach
      const v3<T> low_on_wall(T(0.5), y, T(0.3) * L);
      CHECK(near(m, g, low_on_wall, T(1.5) * L, compensation_tolerance(low_on_wall)));  // the floor 0.3 voxels below
      const v3<T> beside(T(0.5) - T(0.3) * L, y, T(0));
      CHECK(near(m, g, beside, T(1.5) * L, compensation_tolerance(beside)));  // the wall 0.3 voxels away
      CHECK_FALSE(near(m, g, beside, T(0.2) * L, compensation_tolerance(beside)));  // ... but not within 0.2
    }
  }
}

TEMPLATE_TEST_CASE("near-surface test: a plane at exactly the tolerance is through x", "[visibility][triangle_voxels][hardcases]",
                   float, double) {
  using T = TestType;
  mesh<T> m;
  m.tiled_floor(8);
  const auto g = m.voxelize(32);
  const T L = T(g.occupancy().voxel_length());
  for (const T h : {T(0.25) * L, T(1e-3) * L, std::numeric_limits<T>::min()}) {
    const v3<T> x(T(0.4), T(0.6), h);  // the floor's plane is at exactly h from x
    CHECK_FALSE(near(m, g, x, T(1.5) * L, h));
    CHECK(near(m, g, x, T(1.5) * L, std::nextafter(h, T(0))));
    CHECK(near(m, g, x, h, std::nextafter(h, T(0))));              // at exactly reach: within
    CHECK_FALSE(near(m, g, x, std::nextafter(h, T(0)), T(0)));     // just beyond reach
  }
}

TEMPLATE_TEST_CASE("near-surface test: empty voxels, and boxes wider than voxel_near_max_side",
                   "[visibility][triangle_voxels][hardcases]", float, double) {
  using T = TestType;
  mesh<T> m;  // two floors, z = 0 and z = 1: the space between is empty
  m.tiled_floor(4);
  m.quad(v3<T>(0, 0, 1), v3<T>(1, 0, 1), v3<T>(1, 1, 1), v3<T>(0, 1, 1));
  const auto g = m.voxelize(32);
  const T L = T(g.occupancy().voxel_length());
  const v3<T> mid(T(0.5), T(0.5), T(0.5));
  const T tol = compensation_tolerance(mid);
  CHECK_FALSE(near(m, g, mid, T(3) * L, tol));  // every voxel of the box empty
  CHECK_FALSE(near(m, g, mid, T(0), tol));
  // A box of voxel_near_max_side voxels or more per axis is not looked at: true, even where empty.
  const T wide = T(vplkit::voxel_near_max_side) * L / T(2);
  CHECK(vplkit::triangle_voxel_surface_within(g.view(), mid, wide, tol));
  CHECK(vplkit::triangle_voxel_surface_within_scan(g.view(), mid, wide, tol));
  // Just below it (7 voxels wide at most): looked at, and empty.
  CHECK_FALSE(near(m, g, mid, T(2.9) * L, tol));
  // Outside the grid: nothing occupied there.
  CHECK_FALSE(near(m, g, v3<T>(T(5), T(5), T(5)), L, tol));
}

TEMPLATE_TEST_CASE("near-surface test: a view without planes, and a voxel listing nothing", "[visibility][triangle_voxels][hardcases]",
                   float, double) {
  using T = TestType;
  mesh<T> m;
  m.tiled_floor(6);
  m.quad(v3<T>(T(0.5), 0, 0), v3<T>(T(0.5), 1, 0), v3<T>(T(0.5), 1, 1), v3<T>(T(0.5), 0, 1));
  const auto built = m.voxelize(16);
  // The same occupancy with every list emptied (a grid adopted from arrays, as read back from a
  // GPU): every voxel is marked several, and nothing is near.
  const std::vector<std::uint32_t> offsets(built.offsets().size(), 0u);
  const vplkit::triangle_voxel_grid<T> empty_lists(built.occupancy(), built.rank(), offsets, {}, built.triangles());
  REQUIRE(one_plane_voxels(empty_lists) == 0);
  vplkit::triangle_voxel_view<T> no_planes = built.view();
  no_planes.planes = nullptr;
  const T L = T(built.occupancy().voxel_length());
  for (int k = 0; k < 64; ++k) {
    const v3<T> x(T(0.05) + T(0.9) * T(k % 8) / T(8), T(0.05) + T(0.9) * T(k / 8) / T(8), T(k % 3) * T(0.2) * L);
    const T tol = compensation_tolerance(x);
    CHECK_FALSE(vplkit::triangle_voxel_surface_within(empty_lists.view(), x, T(1.5) * L, tol));
    CHECK(vplkit::triangle_voxel_surface_within(no_planes, x, T(1.5) * L, tol) == near(m, built, x, T(1.5) * L, tol));
  }
}
