// SPDX-License-Identifier: MIT
// dprsm_patch_vpl (docs/math.md section 11): the jittered point of a texel's patch.
//  - At xi = (0.5, 0.5) it is the point VPL: y = y_t to rounding, the same flux bit for bit (a rim
//    texel's is drawn over a 2 x 2 block: no such identity).
//  - Every accepted point lies on the texel's plane, projects back into its texel, and inside a
//    triangle is exactly the surface point the light sees in that direction (a ray cast).
//  - The texels' domains (uv square inside the disk, plus the band parts a rim texel owns) tile the
//    face: the pointwise solid angles of the valid texels' accepted points add up to 2 pi.
//  - The depth window is dprsm_lookup's: an accepted point is what the lookup calls lit.
#include <float_bits.hpp>
#include <planar_scene.hpp>
#include <synthetic_scene.hpp>

#include <vplkit/paraboloid/texel_grid.hpp>
#include <vplkit/vpl/dprsm_lookup.hpp>
#include <vplkit/vpl/dprsm_patch.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>

using namespace vplkit;
using namespace vplkit_test;

TEMPLATE_TEST_CASE("dprsm_patch_vpl: the texel centre is the point VPL", "[vpl]", float, double) {
  using T = TestType;
  const synthetic_scene<T> scene;
  const dprsm_data<T> d = scene.make_dprsm(16);
  const dprsm_view<T> view = d.view();
  const T inf = std::numeric_limits<T>::infinity();
  const T rel = std::is_same<T, float>::value ? T(2e-6) : T(1e-13);
  int lit = 0, rim = 0;
  for (int t = 0; t < view.texel_count(); ++t) {
    const vpl<T> v = view.vpl_at(t);
    const dprsm_patch_sample<T> s = dprsm_patch_vpl(view, t, vec2<T>(T(0.5)), inf);
    INFO("texel " << t);
    const ivec2 xy = texel_coords(t, 16);
    const texel_block block = texel_patch_block(xy.x, xy.y, 16);
    if (block.nx * block.ny == 1) REQUIRE(s.uv == texel_center_uv<T>(xy.x, xy.y, 16));
    if (!vpl_has_flux(v)) {
      REQUIRE(!vpl_has_flux(s.point));  // zero wherever the point VPL has none
      continue;
    }
    ++lit;
    // A rim texel draws its point over the 2 x 2 texels on its outer side: xi = (0.5, 0.5) is not
    // its centre (the tiling test below covers its points).
    if (block.nx * block.ny != 1) {
      ++rim;
      continue;
    }
    REQUIRE(same_bits(s.point.flux, v.flux));
    const T d1 = glm::length(v.position - view.light.position);
    CHECK(glm::length(s.point.position - v.position) <= rel * d1);
    CHECK(std::abs(s.distance - d1) <= rel * d1);
    CHECK(s.solid_angle == view.solid_angle(t));
    CHECK(std::abs(s.cos_alpha - vpl_cos_alpha(view.light.position, v.position, v.normal)) <= T(8) * rel);
  }
  CHECK(lit > 300);
  CHECK(rim > 0);
}

TEST_CASE("dprsm_patch_vpl: points lie on the texel's plane, in the texel, on the surface the light sees") {
  const synthetic_scene<double> scene;
  const int R = 32;
  const dprsm_data<double> d = scene.make_dprsm(R);
  const dprsm_view<double> view = d.view();
  const double inf = std::numeric_limits<double>::infinity();
  const vec3<double> c = view.light.position;
  int accepted = 0, same_surface = 0, on_cast = 0;
  for (int t = 0; t < view.texel_count(); ++t) {
    if (!vpl_has_flux(view.vpl_at(t))) continue;
    const vec3<double> n = glm::normalize(view.normal[t]);
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 4; ++i) {
        const vec2<double> xi((i + 0.3) / 4, (j + 0.6) / 4);
        const dprsm_patch_sample<double> s = dprsm_patch_vpl(view, t, xi, inf);
        if (!vpl_has_flux(s.point)) continue;
        ++accepted;
        const vec3<double> y = s.point.position;
        INFO("texel " << t << " xi " << xi.x << ", " << xi.y);
        CHECK(std::abs(glm::dot(n, y - view.position[t])) <= 1e-12 * s.distance);
        CHECK(view.texel_of_point(y) == t);
        CHECK(std::abs(glm::length(y - c) - s.distance) <= 1e-12 * s.distance);
        CHECK(std::abs(glm::dot(n, glm::normalize(c - y)) - s.cos_alpha) <= 1e-12);
        const ivec2 xy = texel_coords(t, R);
        CHECK(s.solid_angle == texel_block_point_solid_angle(s.uv, texel_patch_block(xy.x, xy.y, R), R));
        // Where the light ray meets a triangle of the texel's own plane, y is that hit exactly.
        const scene_hit<double> h = scene.intersect(c, y - c);
        REQUIRE(h.hit);
        if (glm::dot(h.normal, n) > 1.0 - 1e-12 && std::abs(glm::dot(n, h.position - view.position[t])) < 1e-9) {
          ++same_surface;
          if (glm::length(h.position - y) <= 1e-11 * s.distance) ++on_cast;
        }
      }
  }
  std::printf("patch points: %d accepted, %d on the texel centre's surface, %d of those equal to the ray cast\n",
              accepted, same_surface, on_cast);
  CHECK(on_cast == same_surface);
  CHECK(same_surface > 0.9 * accepted);  // the rest: texels across an edge (creases, silhouettes)
}

TEST_CASE("dprsm_patch_vpl: the texels' domains tile the disk (solid angles add up to 2 pi)") {
  // The planar scene's floor fills the whole front face, so every valid front texel accepts every
  // point of its domain (no depth window): its square inside the disk and, for a rim texel, the
  // parts of invalid squares it owns (texel_owner_from_uv), drawn over its 2 x 2 block.
  const planar_scene<double> scene;
  const double two_pi = 2.0 * 3.14159265358979323846, inf = std::numeric_limits<double>::infinity();
  for (int R : {8, 32, 64}) {
    const dprsm_data<double> d = scene.make_dprsm(R);
    const dprsm_view<double> view = d.view();
    double own_square = 0.0, band = 0.0, point_sum = 0.0;
    int rim = 0;
    for (int y = 0; y < R; ++y)
      for (int x = 0; x < R; ++x) {
        const int t = texel_index(paraboloid_front, x, y, R);
        point_sum += view.solid_angle(t);
        if (!texel_is_valid(x, y, R)) continue;
        const texel_block block = texel_patch_block(x, y, R);
        rim += block.nx * block.ny != 1;
        const int mx = 24 * block.nx, my = 24 * block.ny;  // midpoint grid over the block: 24 x 24 per texel
        for (int j = 0; j < my; ++j)
          for (int i = 0; i < mx; ++i) {
            const vec2<double> xi((i + 0.5) / mx, (j + 0.5) / my);
            const vec2<double> uv = texel_block_point_uv(block, R, xi);
            const bool owned = glm::dot(uv, uv) <= 1.0 && texel_owner_from_uv(uv, R) == ivec2(x, y);
            const dprsm_patch_sample<double> s = dprsm_patch_vpl(view, t, xi, inf);
            // accepted exactly where the texel owns the point, with the block's solid angle
            REQUIRE((s.solid_angle > 0.0) == owned);
            if (!owned) continue;
            REQUIRE(s.uv == uv);
            REQUIRE(s.solid_angle == texel_block_point_solid_angle(uv, block, R));
            (texel_from_uv(uv, R) == ivec2(x, y) ? own_square : band) += s.solid_angle / (mx * my);
          }
      }
    std::printf("R %3d: valid texels' own squares in the disk %.6f + the band parts their %d rim texels own %.6f = "
                "%.6f (2 pi %.6f); the band is %.3f%% of the face; midpoint sum %.6f\n",
                R, own_square, rim, band, own_square + band, two_pi, 100.0 * band / two_pi, point_sum);
    // a midpoint quadrature of the disk's indicator: error O(1 / (m R))
    CHECK(std::abs(own_square + band - two_pi) < 0.004 / R * two_pi);
    CHECK(band > 0.0);
    CHECK(band < 2.0 / R * two_pi);  // a rim band: O(1/R)
  }
}

TEST_CASE("dprsm_patch_vpl: the depth window is dprsm_lookup's lit test") {
  // A patch point lies on its texel's plane, where the lit test's plane rule accepts it: the patch
  // keeps exactly what the lookup calls lit, including the points far from the centre's depth on
  // tilted texels that the former window (|d1 - |y_t - c|| <= tol) dropped.
  const synthetic_scene<double> scene;
  const dprsm_data<double> d = scene.make_dprsm(32);
  const dprsm_view<double> view = d.view();
  const double inf = std::numeric_limits<double>::infinity();
  int beyond_former = 0, tested = 0, rejected = 0;
  for (double tol : {0.0, 0.02, 0.1}) {
    for (int t = 0; t < view.texel_count(); t += 3) {
      if (!vpl_has_flux(view.vpl_at(t))) continue;
      for (int k = 0; k < 5; ++k) {
        const vec2<double> xi(0.1 + 0.2 * k, 0.93 - 0.17 * k);
        const dprsm_patch_sample<double> all = dprsm_patch_vpl(view, t, xi, inf);
        const dprsm_patch_sample<double> s = dprsm_patch_vpl(view, t, xi, tol);
        if (!vpl_has_flux(all.point)) {
          CHECK(!vpl_has_flux(s.point));
          continue;
        }
        const dprsm_lookup_result lk = dprsm_lookup(view, all.point.position, tol);
        ++tested;
        INFO("texel " << t << " tol " << tol);
        CHECK(lk.texel == t);
        CHECK(lk.lit == vpl_has_flux(s.point));
        if (!vpl_has_flux(s.point)) ++rejected;
        else CHECK(same_bits(s.point.position, all.point.position));
        if (vpl_has_flux(s.point) &&
            std::abs(all.distance - glm::length(view.position[t] - view.light.position)) > tol)
          ++beyond_former;
      }
    }
  }
  std::printf("depth window: %d points tested, %d rejected, %d kept beyond the former window\n", tested, rejected,
              beyond_former);
  CHECK(tested > 1000);
  CHECK(beyond_former > tested / 10);
}
