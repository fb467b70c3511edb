// SPDX-License-Identifier: MIT
// Unit tests of point-to-point voxel visibility (include/vplkit/visibility/voxel_visible.hpp) on
// small voxelised scenes: a floor meeting a wall (mutually visible everywhere), the same with a
// low occluding wall in between, axis-aligned and tilted.
#include <vplkit/visibility/voxel_visible.hpp>
#include <vplkit/visibility/voxelize.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

using vplkit::ivec3;
using d3 = vplkit::vec3<double>;

namespace {

struct scene {
  d3 R[3];  // rows of the rotation applied to the whole scene
  std::vector<d3> p;
  std::vector<std::uint32_t> idx;
  d3 rot(d3 q) const { return q.x * R[0] + q.y * R[1] + q.z * R[2]; }
  void quad(d3 a, d3 b, d3 c, d3 d) {
    const auto s = std::uint32_t(p.size());
    for (d3 q : {a, b, c, d}) p.push_back(rot(q));
    for (std::uint32_t k : {0u, 1u, 2u, 0u, 2u, 3u}) idx.push_back(s + k);
  }
};

// Floor z = 0 and wall x = 0 over [0,1]^2 (local frame), optionally a wall x = 0.5 of height 0.4.
scene make_scene(double ang, double ang2, bool occluder) {
  scene s;
  s.R[0] = d3(std::cos(ang), std::sin(ang), 0);
  s.R[1] = d3(-std::sin(ang), std::cos(ang), 0);
  s.R[2] = d3(0, 0, 1);
  for (d3& r : s.R) r = d3(r.x, std::cos(ang2) * r.y - std::sin(ang2) * r.z, std::sin(ang2) * r.y + std::cos(ang2) * r.z);
  s.quad(d3(0, 0, 0), d3(1, 0, 0), d3(1, 1, 0), d3(0, 1, 0));
  s.quad(d3(0, 0, 0), d3(0, 1, 0), d3(0, 1, 1), d3(0, 0, 1));
  if (occluder) s.quad(d3(0.5, 0, 0), d3(0.5, 1, 0), d3(0.5, 1, 0.4), d3(0.5, 0, 0.4));
  return s;
}

vplkit::voxel_grid<double> voxelized(const scene& s, int res) {
  // Bounds from the unoccluded scene's vertices, so both variants share one grid.
  const auto b = vplkit::fit_voxel_bounds(s.p.data(), 8, 0.03);
  vplkit::voxel_grid<double> g(b.min, b.max, ivec3(res));
  vplkit::voxelize(g, s.p.data(), s.p.size(), s.idx.data(), s.idx.size());
  return g;
}

// Fraction of the unoccluded floor -> wall transport (cos * cos / d^2) that the test keeps.
template <class Visible>
double transport_kept(const scene& s, Visible visible) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(0.02, 1.0);
  double all = 0, kept = 0;
  const d3 nx = s.rot(d3(0, 0, 1)), ny = s.rot(d3(1, 0, 0));
  for (int i = 0; i < 4000; ++i) {
    const d3 x = s.rot(d3(u(rng), u(rng), 0)), y = s.rot(d3(0, u(rng), u(rng)));
    const d3 d = y - x;
    const double dist = glm::length(d);
    const double w = std::max(0.0, glm::dot(nx, d)) * std::max(0.0, -glm::dot(ny, d)) / (dist * dist * std::max(dist * dist, 1e-2));
    all += w;
    if (visible(x, nx, y, ny)) kept += w;
  }
  return kept / all;
}

}  // namespace

TEST_CASE("voxel visibility: an empty grid hides nothing", "[visibility]") {
  vplkit::voxel_grid<float> g(vplkit::vec3<float>(0.0f), vplkit::vec3<float>(1.0f), ivec3(16));
  std::mt19937 rng(5);
  std::uniform_real_distribution<float> u(-0.5f, 1.5f);
  for (int i = 0; i < 1000; ++i) {
    const vplkit::vec3<float> x(u(rng), u(rng), u(rng)), y(u(rng), u(rng), u(rng)), n(u(rng), u(rng), u(rng));
    REQUIRE(vplkit::voxel_visible(g.view(), x, n, y));
    REQUIRE(vplkit::voxel_visible_two_sided(g.view(), x, n, y, -n));
  }
}

TEST_CASE("voxel visibility: surface_ray_origin lifts by offset * voxel_length along the unit normal",
          "[visibility]") {
  vplkit::voxel_grid<double> g(d3(0.0), d3(2.0, 1.0, 1.0), ivec3(8, 8, 8));  // voxel 0.25 x 0.125 x 0.125
  const d3 x(1.0, 0.5, 0.5);
  REQUIRE(g.voxel_length() == 0.25);
  const d3 o = vplkit::surface_ray_origin(g.view(), x, d3(0, 0, 7));
  REQUIRE(o.x == x.x);
  REQUIRE(o.z == Approx(0.5 + 1.75 * 0.25));
  REQUIRE(vplkit::surface_ray_origin(g.view(), x, d3(3, 0, 4), 2.0).x == Approx(1.0 + 2.0 * 0.25 * 0.6));
  // A zero or non-finite normal leaves the point where it is.
  REQUIRE(vplkit::surface_ray_origin(g.view(), x, d3(0.0)) == x);
  REQUIRE(vplkit::surface_ray_origin(g.view(), x, d3(std::nan(""), 0, 1)) == x);
}

TEST_CASE("voxel visibility: tolerance, nearby points and non-finite input", "[visibility]") {
  vplkit::voxel_grid<double> g(d3(0.0), d3(1.0), ivec3(10));
  for (int y = 0; y < 10; ++y)
    for (int z = 0; z < 10; ++z) g.set(ivec3(5, y, z));  // a wall filling x in [0.5, 0.6]
  const d3 n(0, 0, 0);  // no offset: exact segment tests
  // Behind the wall: blocked; the wall entered at t = 0.4 from x.
  REQUIRE_FALSE(vplkit::voxel_visible(g.view(), d3(0.1, 0.5, 0.5), n, d3(0.9, 0.5, 0.5), 0.0, 0.0));
  // y inside the wall's first voxel layer, 0.05 = 0.5 voxel deep: blocked with psi = 0.25 voxel,
  // visible with psi = 1 voxel (the wall entered within psi of y).
  REQUIRE_FALSE(vplkit::voxel_visible(g.view(), d3(0.1, 0.5, 0.5), n, d3(0.55, 0.5, 0.5), 0.0, 0.25));
  REQUIRE(vplkit::voxel_visible(g.view(), d3(0.1, 0.5, 0.5), n, d3(0.55, 0.5, 0.5), 0.0, 1.0));
  // Points closer than psi are visible whatever lies between.
  REQUIRE(vplkit::voxel_visible(g.view(), d3(0.48, 0.5, 0.5), n, d3(0.62, 0.5, 0.5), 0.0, 2.0));
  // Non-finite ends: not visible, no NaN anywhere.
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  REQUIRE_FALSE(vplkit::voxel_visible(g.view(), d3(nan, 0.5, 0.5), n, d3(0.9, 0.5, 0.5)));
  REQUIRE_FALSE(vplkit::voxel_visible(g.view(), d3(0.1, 0.5, 0.5), n, d3(0.9, inf, 0.5)));
  REQUIRE_FALSE(vplkit::voxel_visible_two_sided(g.view(), d3(0.1, 0.5, 0.5), n, d3(0.9, 0.5, nan), n));
  // x == y: visible (nothing to march).
  REQUIRE(vplkit::voxel_visible(g.view(), d3(0.55, 0.5, 0.5), n, d3(0.55, 0.5, 0.5)));
}

TEST_CASE("voxel visibility: a floor and a wall see each other (axis-aligned and tilted)", "[visibility]") {
  for (int tilted = 0; tilted < 2; ++tilted) {
    const scene s = make_scene(tilted ? 0.61 : 0.0, tilted ? 0.37 : 0.0, false);
    const auto g = voxelized(s, 64);
    const auto view = g.view();
    const double two = transport_kept(s, [&](d3 x, d3 nx, d3 y, d3 ny) {
      return vplkit::voxel_visible_two_sided(view, x, nx, y, ny);
    });
    const double one = transport_kept(s, [&](d3 x, d3 nx, d3 y, d3) { return vplkit::voxel_visible(view, x, nx, y); });
    INFO("tilted " << tilted << " two-sided kept " << two << " one-sided kept " << one);
    // Measured: two-sided 1.000 / 0.987, one-sided 0.994 / 0.785 (see docs/api/visibility.md).
    CHECK(two >= (tilted ? 0.97 : 0.999));
    CHECK(one >= (tilted ? 0.70 : 0.98));
    CHECK(two >= one);
  }
}

TEST_CASE("voxel visibility: an occluding wall blocks (both tests, axis-aligned and tilted)", "[visibility]") {
  for (int tilted = 0; tilted < 2; ++tilted) {
    const scene s = make_scene(tilted ? 0.61 : 0.0, tilted ? 0.37 : 0.0, true);
    const auto g = voxelized(s, 64);
    const double L = g.voxel_length();
    std::mt19937 rng(9);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    int tested = 0;
    for (int i = 0; i < 4000; ++i) {
      // x on the floor beyond the occluder, y on the back wall: the segment crosses x = 0.5 at
      // height z_y * (x_x - 0.5) / x_x; keep pairs crossing well inside the occluder.
      const d3 xl(0.5 + 8 * L + (0.5 - 8 * L) * u(rng), 0.05 + 0.9 * u(rng), 0), yl(0, 0.05 + 0.9 * u(rng), 0.4 * u(rng));
      const double zc = yl.z * (xl.x - 0.5) / xl.x;
      if (zc > 0.4 - 4 * L) continue;
      ++tested;
      const d3 x = s.rot(xl), y = s.rot(yl), nx = s.rot(d3(0, 0, 1)), ny = s.rot(d3(1, 0, 0));
      INFO("tilted " << tilted << " pair " << i);
      REQUIRE_FALSE(vplkit::voxel_visible_two_sided(g.view(), x, nx, y, ny));
      REQUIRE_FALSE(vplkit::voxel_visible(g.view(), x, nx, y));
    }
    CHECK(tested > 2000);
  }
}
