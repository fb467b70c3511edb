// SPDX-License-Identifier: MIT
// Hard cases of the triangle voxel grid's offset contract (triangle_voxel_visible_offset,
// triangle_voxel_query.hpp): where the plane rule and the offset differ (a surface behind a wall
// seen along the wall's own plane, Sponza's case), a concave junction closer than the offset, a
// segment through the shared edge of two triangles, a scene far from the origin. Each answer is
// stated outright and checked against the library's exact BVH with the same offset, whose
// contract this is.
#include <vplkit/visibility/bvh_build.hpp>
#include <vplkit/visibility/bvh_visibility.hpp>
#include <vplkit/visibility/triangle_voxel_query.hpp>
#include <vplkit/visibility/voxelize_triangles.hpp>

#include <catch2/catch.hpp>

#include <vector>

namespace {

using v3 = vplkit::vec3<float>;

struct quads {
  std::vector<v3> p;
  std::vector<std::uint32_t> idx;
  void quad(v3 a, v3 b, v3 c, v3 d) {
    const auto s = std::uint32_t(p.size());
    for (v3 q : {a, b, c, d}) p.push_back(q);
    for (std::uint32_t k : {0u, 1u, 2u, 0u, 2u, 3u}) idx.push_back(s + k);
  }
};

struct both {
  vplkit::triangle_voxel_grid<float> grid;
  vplkit::bvh<float> bvh;
};

both build(const quads& q, int resolution) {
  const vplkit::voxel_bounds<float> b = vplkit::fit_voxel_bounds(q.p.data(), q.p.size());
  return both{vplkit::voxelize_triangles(b.min, b.max, vplkit::ivec3(resolution), q.p.data(), q.p.size(),
                                         q.idx.data(), q.idx.size()),
              vplkit::build_bvh(q.p.data(), q.p.size(), q.idx.data(), q.idx.size())};
}

// The offset contract's answer, required equal to the BVH's with the same offset.
bool offset_visible(const both& s, v3 x, v3 nx, v3 y, v3 ny, float offset) {
  const bool voxels = vplkit::triangle_voxel_visible_offset(s.grid.view(), x, nx, y, ny, offset);
  const bool exact = !vplkit::bvh_occluded(s.bvh.view(), vplkit::bvh_offset_point(x, nx, offset),
                                           vplkit::bvh_offset_point(y, ny, offset) - vplkit::bvh_offset_point(x, nx, offset),
                                           0.0f, 1.0f);
  REQUIRE(voxels == exact);
  return voxels;
}

}  // namespace

TEST_CASE("offset contract: a floor behind a wall, seen along the wall's own plane, is hidden",
          "[visibility][triangle_voxels][hardcases]") {
  // A wall in the plane x = 0 facing -x, and a floor y = 0 behind it (x > 0) facing +y: x on the
  // wall's front face, y on the floor at the wall's foot, half a thousandth behind the wall's plane.
  quads q;
  q.quad(v3(0, 0, -1), v3(0, 0, 1), v3(0, 1, 1), v3(0, 1, -1));      // wall
  q.quad(v3(0, 0, -1), v3(1, 0, -1), v3(1, 0, 1), v3(0, 0, 1));      // floor behind it
  q.quad(v3(-1, -0.5f, -1), v3(-1, -0.5f, 1), v3(-1, 1, 1), v3(-1, 1, -1));  // a far wall: the box in front
  for (int res : {8, 32, 128}) {
    const both s = build(q, res);
    const v3 x(0, 0.01f, 0), nx(-1, 0, 0), y(0.0005f, 0, -0.02f), ny(0, 1, 0);
    INFO("resolution " << res);
    // The end rule ignores the wall: its plane passes within 0.01 voxel of y (at 128^3, 0.0005 is
    // 0.03 voxel: there the band is narrower than the gap and the rule blocks too).
    const float L = vplkit::voxel_length(s.grid.view().grid);
    if (0.0005f < 0.01f * L) CHECK(vplkit::triangle_voxel_visible(s.grid.view(), x, y));
    // Moved off their surfaces, x lies in front of the wall and y behind it: the wall hides y.
    CHECK_FALSE(offset_visible(s, x, nx, y, ny, 0.001f));
    CHECK_FALSE(offset_visible(s, x, nx, y, ny, vplkit::bvh_surface_offset(s.bvh.view())));
  }
}

TEST_CASE("offset contract: a concave junction closer than the offset does not self-occlude",
          "[visibility][triangle_voxels][hardcases]") {
  // A floor y = 0 (x < 0) facing +y meets a wall x = 0 facing -x; x on the floor 5e-5 from the
  // wall, a twentieth of the offset, y on the wall: both moved ends lie in front of both surfaces.
  quads q;
  q.quad(v3(-1, 0, -1), v3(-1, 0, 1), v3(0, 0, 1), v3(0, 0, -1));  // floor
  q.quad(v3(0, 0, -1), v3(0, 0, 1), v3(0, 1, 1), v3(0, 1, -1));    // wall
  for (int res : {8, 64}) {
    const both s = build(q, res);
    const v3 x(-5e-5f, 0, 0), nx(0, 1, 0);
    CHECK(offset_visible(s, x, nx, v3(0, 0.5f, 0.3f), v3(-1, 0, 0), 0.001f));
    CHECK(offset_visible(s, x, nx, v3(0, 0.0005f, -0.7f), v3(-1, 0, 0), 0.001f));  // the wall's foot
    CHECK(offset_visible(s, x, nx, v3(-0.9f, 0, 0.9f), v3(0, 1, 0), 0.001f));     // grazing along the floor
  }
}

TEST_CASE("offset contract: a segment through the shared edge of two triangles is blocked",
          "[visibility][triangle_voxels][hardcases]") {
  // One quad in the plane z = 0.5 (two triangles sharing the diagonal from (0,0) to (1,1)): segments
  // across it through points on the diagonal, where each triangle's inside test is rounding noise.
  quads q;
  q.quad(v3(0, 0, 0.5f), v3(1, 0, 0.5f), v3(1, 1, 0.5f), v3(0, 1, 0.5f));
  const both s = build(q, 16);
  for (int i = 1; i < 64; ++i) {
    const float t = float(i) / 64.0f;
    const v3 on(t, t, 0.5f);
    INFO("t " << t);
    CHECK_FALSE(offset_visible(s, on + v3(0.013f, -0.007f, -0.3f), v3(0, 0, -1), on + v3(-0.013f, 0.007f, 0.3f),
                               v3(0, 0, 1), 0.001f));
  }
}

TEST_CASE("offset contract: far from the origin the offset still clears a grazing segment's own surface",
          "[visibility][triangle_voxels][hardcases]") {
  // A floor at y = 3000, 1 unit wide, 4000 units from the origin: rasterised points on it lie off
  // the plane by rounding (a few ulps of 4000, ~1e-3 in float); the offset's 2^-15 M term (0.12 here)
  // clears it, and a segment between two points of the floor at a grazing angle is visible.
  const v3 o(4000, 3000, -2000);
  quads q;
  q.quad(o + v3(0, 0, 0), o + v3(0, 0, 1), o + v3(1, 0, 1), o + v3(1, 0, 0));
  q.quad(o + v3(0, -1, 0), o + v3(0, 1, 0), o + v3(0, 1, 1), o + v3(0, -1, 1));  // a wall at the floor's edge
  const both s = build(q, 32);
  const float off = vplkit::bvh_surface_offset(s.bvh.view());
  REQUIRE(off > 0.1f);
  for (int i = 0; i < 16; ++i) {
    const float a = 0.05f + 0.05f * float(i);
    // Points a hair below and above the plane, as rasterisation leaves them.
    const v3 x = o + v3(a, i % 2 == 0 ? -0.0005f : 0.0005f, 0.2f), y = o + v3(0.9f, 0, 0.2f + 0.04f * float(i));
    CHECK(offset_visible(s, x, v3(0, 1, 0), y, v3(0, 1, 0), off));
    // Behind the wall at the floor's edge (x < 4000, facing -x): hidden.
    CHECK_FALSE(offset_visible(s, x, v3(0, 1, 0), o + v3(-0.5f, 0.5f, 0.5f), v3(0, 1, 0), off));
  }
}
