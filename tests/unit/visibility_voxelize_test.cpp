// SPDX-License-Identifier: MIT
// Unit tests of the conservative voxelisation (include/vplkit/visibility/voxelize.hpp).
#include <vplkit/visibility/dda.hpp>
#include <vplkit/visibility/voxelize.hpp>

#include <voxel_cells.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <string>
#include <vector>

using vplkit::ivec3;

namespace {

// Brute force over ALL voxels with the same SAT in the same (double, voxel-unit) coordinates.
template <class T>
std::vector<ivec3> brute_force_voxels(const vplkit::voxel_grid<T>& g, vplkit::vec3<T> a, vplkit::vec3<T> b,
                                      vplkit::vec3<T> c, double margin) {
  using d3 = vplkit::vec3<double>;
  const d3 bmin(g.bounds_min());
  const d3 size = (d3(g.bounds_max()) - bmin) / d3(g.resolution());
  const d3 v0 = (d3(a) - bmin) / size, v1 = (d3(b) - bmin) / size, v2 = (d3(c) - bmin) / size;
  std::vector<ivec3> out;
  const ivec3 r = g.resolution();
  for (int z = 0; z < r.z; ++z)
    for (int y = 0; y < r.y; ++y)
      for (int x = 0; x < r.x; ++x)
        if (vplkit::triangle_box_overlap(d3(x, y, z) + d3(0.5), d3(0.5 + margin), v0, v1, v2))
          out.push_back(ivec3(x, y, z));
  return out;
}

template <class T>
void single_triangles_match_brute_force(std::uint32_t seed) {
  using v3 = vplkit::vec3<T>;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const v3 bmin(T(-1.3), T(0.2), T(2.0)), bmax(T(2.1), T(3.0), T(4.5));
  const ivec3 res(13, 11, 9);
  int total_marked = 0;
  for (int trial = 0; trial < 150; ++trial) {
    // Vertices partly outside the bounds, triangles from tiny to larger than the grid.
    v3 p[3];
    const double s = trial % 3 == 0 ? 0.1 : 1.0;
    const v3 base(T(-1.6 + 4.0 * u(rng)), T(-0.2 + 3.6 * u(rng)), T(1.6 + 3.3 * u(rng)));
    for (v3& q : p) q = base + v3(T(s * (u(rng) - 0.5) * 3), T(s * (u(rng) - 0.5) * 3), T(s * (u(rng) - 0.5) * 3));
    const std::uint32_t idx[3] = {0, 1, 2};
    for (double margin : {0.0, vplkit::voxelize_default_margin}) {
      vplkit::voxel_grid<T> g(bmin, bmax, res);
      vplkit::voxelize(g, p, 3, idx, 3, margin);
      const std::vector<ivec3> got = vplkit_test::occupied_voxels(g), expected = brute_force_voxels(g, p[0], p[1], p[2], margin);
      INFO("trial " << trial << " margin " << margin);
      REQUIRE(got == expected);
      total_marked += int(got.size());
      // Independent of the SAT: every sampled point of the triangle lies in a marked voxel.
      for (int k = 0; k < 200; ++k) {
        double b0 = u(rng), b1 = u(rng);
        if (b0 + b1 > 1.0) {
          b0 = 1.0 - b0;
          b1 = 1.0 - b1;
        }
        const vplkit::vec3<double> q = vplkit::vec3<double>(p[0]) * (1.0 - b0 - b1) + vplkit::vec3<double>(p[1]) * b0 +
                                       vplkit::vec3<double>(p[2]) * b1;
        const vplkit::vec3<double> cq = (q - vplkit::vec3<double>(bmin)) /
                                        ((vplkit::vec3<double>(bmax) - vplkit::vec3<double>(bmin)) / vplkit::vec3<double>(res));
        // Skip points within 1e-6 voxel of a voxel plane (either neighbour may be the one).
        bool near_plane = false;
        for (int a = 0; a < 3; ++a) near_plane |= std::abs(cq[a] - std::round(cq[a])) < 1e-6;
        const ivec3 v(int(std::floor(cq.x)), int(std::floor(cq.y)), int(std::floor(cq.z)));
        if (!near_plane && g.contains(v)) REQUIRE(g.test(v));
      }
    }
  }
  CHECK(total_marked > 1000);
}

// A closed box mesh (12 triangles) with centre c, half size h, rotated by the orthonormal rows R.
struct box_mesh {
  std::vector<vplkit::vec3<double>> p;
  std::vector<std::uint32_t> idx;
};

box_mesh make_box(vplkit::vec3<double> c, vplkit::vec3<double> h, const vplkit::vec3<double> R[3]) {
  box_mesh m;
  for (int i = 0; i < 8; ++i) {
    const vplkit::vec3<double> l((i & 1) ? h.x : -h.x, (i & 2) ? h.y : -h.y, (i & 4) ? h.z : -h.z);
    m.p.push_back(c + l.x * R[0] + l.y * R[1] + l.z * R[2]);
  }
  const std::uint32_t f[12][3] = {{0, 2, 1}, {1, 2, 3}, {4, 5, 6}, {5, 7, 6}, {0, 1, 4}, {1, 5, 4},
                                  {2, 6, 3}, {3, 6, 7}, {0, 4, 2}, {2, 4, 6}, {1, 3, 5}, {3, 7, 5}};
  for (const auto& t : f) m.idx.insert(m.idx.end(), t, t + 3);
  return m;
}

// Rays from random points inside a rotated closed box: every one must hit the voxel shell no later
// than where it crosses the box surface, at a point within a voxel diagonal of that surface.
template <class T>
void watertight_rotated_box(double margin, std::uint32_t seed) {
  using d3 = vplkit::vec3<double>;
  const double ang = 0.61, ang2 = 0.37;
  d3 R[3] = {d3(std::cos(ang), std::sin(ang), 0), d3(-std::sin(ang), std::cos(ang), 0), d3(0, 0, 1)};
  // Tilt about x as well, so no face is axis-aligned.
  for (d3& r : R) r = d3(r.x, std::cos(ang2) * r.y - std::sin(ang2) * r.z, std::sin(ang2) * r.y + std::cos(ang2) * r.z);
  const d3 c(0.52, 0.47, 0.55), h(0.27, 0.19, 0.23);
  const box_mesh m = make_box(c, h, R);
  std::vector<vplkit::vec3<T>> pos;
  for (const d3& q : m.p) pos.push_back(vplkit::vec3<T>(q));
  vplkit::voxel_grid<T> g(vplkit::vec3<T>(T(0)), vplkit::vec3<T>(T(1)), ivec3(32, 32, 32));
  vplkit::voxelize(g, pos.data(), pos.size(), m.idx.data(), m.idx.size(), margin);
  const double L = double(g.voxel_length());

  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::normal_distribution<double> n01(0.0, 1.0);
  for (int r = 0; r < 20000; ++r) {
    const d3 local(u(rng) * h.x, u(rng) * h.y, u(rng) * h.z);
    const vplkit::vec3<T> o(c + local.x * R[0] + local.y * R[1] + local.z * R[2]);
    const vplkit::vec3<T> dir(T(n01(rng)), T(n01(rng)), T(n01(rng)));
    vplkit::vec3<T> dn(T(0));
    REQUIRE(vplkit::dda_unit_direction(dir, dn));
    // Exact exit distance from the box, in its own frame.
    const d3 ol(glm::dot(d3(o) - c, R[0]), glm::dot(d3(o) - c, R[1]), glm::dot(d3(o) - c, R[2]));
    const d3 dl(glm::dot(d3(dn), R[0]), glm::dot(d3(dn), R[1]), glm::dot(d3(dn), R[2]));
    double t_exit = 1e30;
    for (int a = 0; a < 3; ++a)
      if (dl[a] != 0.0) t_exit = std::min(t_exit, ((dl[a] > 0 ? h[a] : -h[a]) - ol[a]) / dl[a]);
    const vplkit::dda_hit<T> hit = vplkit::dda_first_hit(g.view(), o, dir);
    INFO("ray " << r);
    REQUIRE(hit.hit);
    REQUIRE(double(hit.t) <= t_exit + 1e-4 * L);
    const d3 e = d3(o) + double(hit.t) * d3(dn);
    const d3 el(glm::dot(e - c, R[0]), glm::dot(e - c, R[1]), glm::dot(e - c, R[2]));
    // Distance of the entry point to the box surface (inside: to the nearest face).
    double dist = 1e30;
    for (int a = 0; a < 3; ++a) dist = std::min(dist, h[a] - std::abs(el[a]));
    REQUIRE(dist <= std::sqrt(3.0) * L + 1e-9);
  }
}

}  // namespace

TEST_CASE("voxelize: single triangles mark exactly the voxels a brute force over all voxels marks (double)",
          "[visibility]") {
  single_triangles_match_brute_force<double>(5u);
}

TEST_CASE("voxelize: single triangles mark exactly the voxels a brute force over all voxels marks (float)",
          "[visibility]") {
  single_triangles_match_brute_force<float>(6u);
}

TEST_CASE("voxelize: axis-aligned triangle exactly on voxel faces marks both sides", "[visibility]") {
  using v3 = vplkit::vec3<float>;
  for (double margin : {0.0, vplkit::voxelize_default_margin}) {
    vplkit::voxel_grid<float> g(v3(0.0f), v3(8.0f), ivec3(8));
    const v3 p[3] = {v3(1, 1, 4), v3(6, 1, 4), v3(1, 6, 4)};
    const std::uint32_t idx[3] = {0, 1, 2};
    vplkit::voxelize(g, p, 3, idx, 3, margin);
    for (int z = 0; z < 8; ++z)
      for (int y = 0; y < 8; ++y)
        for (int x = 0; x < 8; ++x) {
          // Closed square [x, x+1] x [y, y+1] meets {x >= 1, y >= 1, x + y <= 7}, layers 3 and 4.
          const bool column = std::max(x, 1) + std::max(y, 1) <= 7;
          INFO("margin " << margin << " voxel " << x << " " << y << " " << z);
          REQUIRE(g.test(ivec3(x, y, z)) == (column && (z == 3 || z == 4)));
        }
  }
  // On the grid's own min and max faces only the inside layer exists.
  vplkit::voxel_grid<double> g(vplkit::vec3<double>(0.0), vplkit::vec3<double>(4.0), ivec3(4));
  const vplkit::vec3<double> p[6] = {{0, 0, 0}, {4, 0, 0}, {0, 4, 0}, {0, 0, 4}, {4, 0, 4}, {0, 4, 4}};
  const std::uint32_t idx[6] = {0, 1, 2, 3, 4, 5};
  vplkit::voxelize(g, p, 6, idx, 6);
  for (int z = 0; z < 4; ++z)
    for (int y = 0; y < 4; ++y)
      for (int x = 0; x < 4; ++x) REQUIRE(g.test(ivec3(x, y, z)) == ((z == 0 || z == 3) && x + y <= 4));
}

TEST_CASE("voxelize: a closed box mesh gives a watertight shell (double)", "[visibility]") {
  watertight_rotated_box<double>(vplkit::voxelize_default_margin, 31u);
  watertight_rotated_box<double>(0.0, 32u);
}

TEST_CASE("voxelize: a closed box mesh gives a watertight shell (float)", "[visibility]") {
  watertight_rotated_box<float>(vplkit::voxelize_default_margin, 33u);
}

TEST_CASE("voxelize: geometry outside the bounds is ignored, inside parts are kept", "[visibility]") {
  using v3 = vplkit::vec3<double>;
  vplkit::voxel_grid<double> g(v3(0.0), v3(1.0), ivec3(10));
  const v3 p[6] = {v3(5, 5, 5), v3(6, 5, 5), v3(5, 6, 5), v3(-1, 0.55, 0.55), v3(2, 0.55, 0.55), v3(0.5, 0.56, 0.55)};
  const std::uint32_t idx[6] = {0, 1, 2, 3, 4, 5};
  vplkit::voxelize(g, p, 6, idx, 6);
  // Only the second (sliver) triangle, crossing the grid along x at y, z in voxel 5.
  REQUIRE(g.count() == 10);
  for (int x = 0; x < 10; ++x) REQUIRE(g.test(ivec3(x, 5, 5)));
}

TEST_CASE("voxelize rejects bad meshes, naming the triangle, and leaves the grid untouched", "[visibility]") {
  using v3 = vplkit::vec3<float>;
  vplkit::voxel_grid<float> g(v3(0.0f), v3(1.0f), ivec3(4));
  const v3 p[4] = {v3(0.1f), v3(0.9f, 0.1f, 0.1f), v3(0.1f, 0.9f, 0.1f), v3(0.5f, std::nanf(""), 0.5f)};
  const std::uint32_t good[3] = {0, 1, 2};
  const std::uint32_t bad_index[6] = {0, 1, 2, 0, 1, 7};
  const std::uint32_t bad_pos[9] = {0, 1, 2, 0, 1, 2, 1, 3, 2};
  REQUIRE_THROWS_WITH(vplkit::voxelize(g, p, 4, bad_index, 6),
                      Catch::Contains("triangle 1") && Catch::Contains("index 7"));
  REQUIRE_THROWS_WITH(vplkit::voxelize(g, p, 4, bad_pos, 9),
                      Catch::Contains("triangle 2") && Catch::Contains("non-finite"));
  REQUIRE_THROWS_AS(vplkit::voxelize(g, p, 4, good, 2), vplkit::invalid_input);
  REQUIRE_THROWS_AS(vplkit::voxelize(g, p, 4, static_cast<const std::uint32_t*>(nullptr), 3), vplkit::invalid_input);
  REQUIRE_THROWS_AS(vplkit::voxelize(g, p, 4, good, 3, -1.0), vplkit::invalid_input);
  REQUIRE(g.count() == 0);
  REQUIRE_NOTHROW(vplkit::voxelize(g, p, 4, good, 3));
  REQUIRE(g.count() > 0);
  REQUIRE_NOTHROW(vplkit::voxelize(g, p, 4, good, 0));  // no triangles: nothing to do
}

TEST_CASE("fit_voxel_bounds: padded cube or box around the scene", "[visibility]") {
  using v3 = vplkit::vec3<double>;
  const v3 p[3] = {v3(-1, 2, 3), v3(3, 2.5, 4), v3(0, 3, 3.5)};
  const auto box = vplkit::fit_voxel_bounds(p, 3, 0.01, false);
  REQUIRE(box.min.x == Approx(-1.04));
  REQUIRE(box.max.x == Approx(3.04));
  REQUIRE(box.min.y == Approx(1.96));
  REQUIRE(box.max.z == Approx(4.04));
  const auto cube = vplkit::fit_voxel_bounds(p, 3);
  const v3 e = cube.max - cube.min;
  REQUIRE(e.x == Approx(4.08));
  REQUIRE(e.y == Approx(4.08));
  REQUIRE(e.z == Approx(4.08));
  for (const v3& q : p) REQUIRE((glm::all(glm::greaterThan(q, cube.min)) && glm::all(glm::lessThan(q, cube.max))));
  // Flat scene (a floor): the flat axis still gets a usable extent; a single point too.
  const v3 floor[3] = {v3(0, 0, 0), v3(2, 0, 0), v3(0, 0, 2)};
  const auto fb = vplkit::fit_voxel_bounds(floor, 3, 0.0, false);
  REQUIRE(fb.max.y - fb.min.y == Approx(2.0));
  REQUIRE_NOTHROW(vplkit::voxel_grid<double>(fb.min, fb.max, ivec3(8)));
  const auto pt = vplkit::fit_voxel_bounds(floor, 1, 0.0, true);
  REQUIRE(pt.max.x - pt.min.x == Approx(1.0));
  REQUIRE_NOTHROW(vplkit::voxel_grid<double>(pt.min, pt.max, ivec3(8)));
  REQUIRE_THROWS_AS(vplkit::fit_voxel_bounds(p, 0), vplkit::invalid_input);
  REQUIRE_THROWS_AS(vplkit::fit_voxel_bounds(p, 3, -0.1), vplkit::invalid_input);
  const v3 bad[2] = {v3(0.0), v3(std::nan(""), 0, 0)};
  REQUIRE_THROWS_WITH(vplkit::fit_voxel_bounds(bad, 2), Catch::Contains("vertex 1"));
}
