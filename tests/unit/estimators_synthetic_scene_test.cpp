// SPDX-License-Identifier: MIT
// The shared synthetic test scene (tests/support/synthetic_scene.hpp) is what it claims to be:
// closed, with the block really casting a shadow, a valid DPRSM, G-buffer and voxel grid.
#include <synthetic_scene.hpp>

#include <vplkit/sampling/rng.hpp>
#include <vplkit/vpl/luminance.hpp>
#include <vplkit/visibility/voxel_visible.hpp>

#include <catch2/catch.hpp>

#include <cmath>

using vplkit::vec3;
using namespace vplkit_test;

TEMPLATE_TEST_CASE("synthetic scene: closed room, every ray from inside hits", "[scene]", double, float) {
  using T = TestType;
  const synthetic_scene<T> s;
  REQUIRE(s.triangle_count() == 24);
  vplkit::counter_rng rng = vplkit::make_counter_rng(1u, 2u);
  for (int i = 0; i < 2000; ++i) {
    vec3<T> d(vplkit::rng_next_unit<T>(rng) - T(0.5), vplkit::rng_next_unit<T>(rng) - T(0.5),
              vplkit::rng_next_unit<T>(rng) - T(0.5));
    const scene_hit<T> h = s.intersect(s.light.position, d);
    REQUIRE(h.hit);
    // the light sees the front side of whatever it hits
    CHECK(glm::dot(h.normal, s.light.position - h.position) > T(0));
  }
}

TEST_CASE("synthetic scene: gather points, shadow of the block, exact visibility") {
  const synthetic_scene<double> s;
  const auto gps = s.gather_points();
  REQUIRE(gps.size() == 7);
  for (const auto& g : gps) {
    INFO(g.name);
    CHECK(vplkit::gather_point_valid(g.gp));
    CHECK(g.gp.albedo.x > 0.0);
    CHECK(g.in_shadow == (g.name == "floor_shadow" || g.name == "block_bottom" || g.name == "block_side"));
  }
  // the floor under the block cannot see the block's top; it sees the red wall
  const auto& fs = gps[1].gp;
  CHECK_FALSE(s.visible(fs.position, fs.normal, vec3<double>(-0.3, 1.2, -0.1), vec3<double>(0, 1, 0)));
  CHECK(s.visible(fs.position, fs.normal, vec3<double>(-2, 0.3, -0.1), vec3<double>(1, 0, 0)));
  // trace from a surface point hits the block bottom first
  const vplkit::ray_hit<double> h = s.trace(fs.position, fs.normal, vec3<double>(0, 1, 0));
  REQUIRE(h.hit);
  CHECK(h.position.y == Approx(0.8));
}

TEST_CASE("synthetic scene: DPRSM, G-buffer and voxel grid") {
  const synthetic_scene<double> s;
  const dprsm_data<double> d = s.make_dprsm(32);
  const vplkit::dprsm_view<double> v = d.view();
  REQUIRE_NOTHROW(v.validate());
  int valid = 0, lit = 0;
  for (int i = 0; i < v.texel_count(); ++i) {
    if (!v.texel_valid(i)) continue;
    ++valid;
    CHECK(d.albedo[std::size_t(i)].x > 0.0);  // closed room: every valid texel sees a surface
    if (vplkit::luminance(v.vpl_at(i).flux) > 0.0) ++lit;
  }
  CHECK(lit == valid);
  const gbuffer_data<double> g = s.make_gbuffer(16, 16);
  for (int i = 0; i < g.view().pixel_count(); ++i) CHECK(vplkit::gather_point_valid(g.view().at(i)));
  const vplkit::voxel_grid<double> grid = s.make_voxel_grid(32);
  CHECK(grid.count() > 0);
  // voxel visibility agrees with exact visibility on an easy pair, and sees the block
  const auto gp = s.gather_points()[1].gp;
  CHECK_FALSE(vplkit::voxel_visible(grid.view(), gp.position, gp.normal, s.light.position));
  CHECK(vplkit::voxel_visible(grid.view(), s.gather_points()[0].gp.position, s.gather_points()[0].gp.normal,
                              s.light.position));
}
