// SPDX-License-Identifier: MIT
// dprsm_patch_vpl (docs/math.md section 11): the jittered point of a texel's patch.
//  - At xi = (0.5, 0.5) it is the point VPL: y = y_t to rounding, the same flux bit for bit (a rim
//    texel's is drawn over a 2 x 2 block: no such identity).
//  - Every accepted point lies on the texel's plane, projects back into its texel, and inside a
//    triangle is exactly the surface point the light sees in that direction (a ray cast).
//  - The texels' domains (uv square inside the disk, plus the band parts a rim texel owns) tile the
//    face: the pointwise solid angles of the valid texels' accepted points add up to 2 pi.
//  - The depth window is dprsm_lookup's: an accepted point is what the lookup calls lit.
//  - At a crease, a plane point hidden by a neighbour's plane moves to the centre with its flux.
#include <float_bits.hpp>
#include <planar_scene.hpp>
#include <synthetic_scene.hpp>

#include <vplkit/estimators/mis_estimator.hpp>
#include <vplkit/paraboloid/texel_grid.hpp>
#include <vplkit/vpl/dprsm_lookup.hpp>
#include <vplkit/vpl/dprsm_patch.hpp>
#include <vplkit/vpl/dprsm_raycast.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <optional>
#include <vector>

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
  int beyond_former = 0, tested = 0, rejected = 0, edge_flips = 0;
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
        // The lookup recomputes uv from the 3D point (a normalisation and a division: a few
        // ulps); a point whose uv lies within that of an ownership edge may be filed under the
        // neighbour. Allowed only there (a decision compared with a margin), and counted.
        if (lk.texel != t) {
          bool at_edge = false;
          for (double f : {1.0 - 64 * std::numeric_limits<double>::epsilon(), 1.0 + 64 * std::numeric_limits<double>::epsilon()})
            for (double g : {-1.0, 1.0})
              at_edge = at_edge || texel_owner_from_uv(vec2<double>(all.uv.x * f, all.uv.y * (g > 0 ? f : 2.0 - f)),
                                                       view.resolution) != texel_coords(t, view.resolution);
          CHECK(at_edge);
          ++edge_flips;
          continue;
        }
        CHECK(lk.lit == vpl_has_flux(s.point));
        if (!vpl_has_flux(s.point)) ++rejected;
        else CHECK(same_bits(s.point.position, all.point.position));
        if (vpl_has_flux(s.point) &&
            std::abs(all.distance - glm::length(view.position[t] - view.light.position)) > tol)
          ++beyond_former;
      }
    }
  }
  std::printf("depth window: %d points tested, %d rejected, %d kept beyond the former window, %d at an ownership "
              "edge filed under the neighbour\n",
              tested, rejected, beyond_former, edge_flips);
  CHECK(tested > 1000);
  CHECK(edge_flips <= tested / 1000);
  CHECK(beyond_former > tested / 10);
}

namespace {

// A room corner seen by a light above the floor: the floor z = 0 (normal +z) for x < wall_x and a
// wall x = wall_x (normal -x, facing the light). Texels along the crease show the floor at their
// centre and the wall in part of their cone: the floor's plane extended over such a texel runs
// under the wall, where no receiver in the room sees it.
struct corner_dprsm {
  static constexpr double wall_x = 0.3;
  std::vector<vec3<double>> position, normal, albedo;
  dprsm_view<double> view;
  explicit corner_dprsm(int R) {
    const point_light<double> light = make_point_light(vec3<double>(0, 0, 1), vec3<double>(1), vec3<double>(0, 0, -1));
    view = render_dprsm(
        light, R,
        [](vec3<double> o, vec3<double> d) -> std::optional<dprsm_hit<double>> {
          double best = std::numeric_limits<double>::infinity();
          std::optional<dprsm_hit<double>> hit;
          if (d.z < 0) {  // the floor
            const double t = -o.z / d.z;
            const vec3<double> p = o + t * d;
            if (t > 0 && p.x <= wall_x) best = t, hit = dprsm_hit<double>{p, vec3<double>(0, 0, 1), vec3<double>(0.5)};
          }
          if (d.x > 0) {  // the wall
            const double t = (wall_x - o.x) / d.x;
            const vec3<double> p = o + t * d;
            if (t > 0 && t < best && p.z >= 0) hit = dprsm_hit<double>{p, vec3<double>(-1, 0, 0), vec3<double>(0.5)};
          }
          return hit;
        },
        position, normal, albedo);
  }
  corner_dprsm(const corner_dprsm&) = delete;
  corner_dprsm& operator=(const corner_dprsm&) = delete;
};

}  // namespace

TEST_CASE("dprsm_patch_vpl: a plane point hidden by a neighbour's plane moves to the centre with its flux") {
  // Without the move, the floor texels along the crease lose the flux of the points under the
  // wall. With it: no accepted point lies behind the wall, every moved point sits at y_t with the
  // flux rho I Omega(uv) it had, and interior texels (neighbours on one plane) never move a point.
  const int R = 32;
  const corner_dprsm s(R);
  const double inf = std::numeric_limits<double>::infinity();
  int moved = 0, kept = 0, interior_checked = 0;
  for (int t = 0; t < s.view.texel_count(); ++t) {
    if (s.view.albedo[t] == vec3<double>(0)) continue;
    const bool floor = s.view.normal[t].z > 0.5;
    for (int i = 0; i < 8; ++i)
      for (int j = 0; j < 8; ++j) {
        const vec2<double> xi((i + 0.5) / 8, (j + 0.5) / 8);
        const dprsm_patch_sample<double> p = dprsm_patch_vpl(s.view, t, xi, 0.0);
        if (!vpl_has_flux(p.point)) continue;
        INFO("texel " << t << " xi " << xi.x << " " << xi.y);
        CHECK(p.point.flux.x == Approx(0.5 * texel_block_point_solid_angle(
                                               p.uv, texel_patch_block(texel_coords(t, R).x, texel_coords(t, R).y, R), R))
                                    .epsilon(1e-12));
        if (p.at_centre) {
          ++moved;
          CHECK(p.point.position == s.view.position[t]);
          CHECK(p.distance == Approx(glm::length(s.view.position[t] - s.view.light.position)));
        } else {
          ++kept;
          // Never under the wall / below the floor, beyond the test's relative margin (1e-3 of d1,
          // d1 < 1.5 here).
          const double slack = 1.5 * dprsm_patch_hidden_margin<double>();
          if (floor) CHECK(p.point.position.x <= corner_dprsm::wall_x + slack);
          else CHECK(p.point.position.z >= -slack);
        }
        // The same split, decided from the plane point's direction alone (what MIS does for a
        // gathering hit there).
        const vec3<double> c = s.view.light.position;
        const vec3<double> w = s.view.light.frame.to_world(paraboloid_to_direction(texel_face(t, R), p.uv));
        const vec3<double> n = glm::normalize(s.view.normal[t]);
        const vec3<double> y_plane = c + (glm::dot(n, c - s.view.position[t]) / -glm::dot(n, w)) * w;
        CHECK(mis_patch_hit_at_centre(s.view, t, y_plane) == p.at_centre);
      }
    // An interior floor texel (all eight neighbours floor, far from the crease): nothing moves.
    const ivec2 xy = texel_coords(t, R);
    bool interior = floor;
    for (int dy = -1; dy <= 1 && interior; ++dy)
      for (int dx = -1; dx <= 1 && interior; ++dx) {
        const int x = xy.x + dx, y = xy.y + dy;
        if (x < 0 || y < 0 || x >= R || y >= R || !texel_is_valid(x, y, R)) { interior = false; break; }
        const int u = texel_index(texel_face(t, R), x, y, R);
        interior = s.view.albedo[u] != vec3<double>(0) && s.view.normal[u].z > 0.5;
      }
    if (interior) {
      ++interior_checked;
      for (int k = 0; k < 16; ++k) CHECK_FALSE(dprsm_patch_vpl(s.view, t, vec2<double>((k % 4 + 0.5) / 4, (k / 4 + 0.5) / 4), inf).at_centre);
    }
  }
  CHECK(moved > 50);
  CHECK(kept > 1000);
  CHECK(interior_checked > 100);
}
