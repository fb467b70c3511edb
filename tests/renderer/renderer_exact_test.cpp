// SPDX-License-Identifier: MIT
// --method exact (render/cpu/exact_estimator.hpp) against a brute-force numerical integral of the
// same one-bounce integral, with the same Embree scene for every visibility and shadow test:
//
//   L(x) = sum over the scene's triangles, each cut into m^2 equal sub-triangles (centroid rule),
//          (rho_x / pi) L_o(y) cos_x cos_y / |y - x|^2 V(x, y) dA,
//   L_o(y) = rho_y I cos(alpha) / (pi d^2) V(y, c) (y's lit side facing x),
//
// at gather points on the built-in Cornell box's floor, a wall and a block (flat surfaces, so the
// geometric and shading normals agree and the estimator's cos_s / cos_g is 1). The estimator's
// standard error comes from 256 independent batches of 512 directions; the test requires
// |estimate - integral| <= 4 sigma per channel, and shows its power: the same integral without the
// shadow term V(y, c) is more than 4 sigma away at some gather point. No GL needed.
#include "render/cpu/exact_estimator.hpp"
#include "render/cpu/ray_scene.hpp"
#include "scene/builtin_scenes.hpp"
#include "scene/scene.hpp"

#include <vplkit/sampling/cosine_hemisphere.hpp>
#include <vplkit/sampling/orthonormal_basis.hpp>
#include <vplkit/sampling/rng.hpp>
#include <vplkit/visibility/bvh_visibility.hpp>
#include <vplkit/vpl/dprsm_view.hpp>
#include <vplkit/vpl/vpl.hpp>

#include <catch2/catch.hpp>

#include <glm/geometric.hpp>

#include <cmath>
#include <iostream>
#include <vector>

using namespace vplrender;

namespace {

struct integral {
  glm::dvec3 with_shadows{0.0}, without_shadows{0.0};
};

integral brute_force(const scene& s, const ray_scene& rs, const vplkit::point_light<float>& light,
                     const vplkit::gather_point<float>& gp, int m) {
  const vec3 x = gp.position, n_x = glm::normalize(gp.normal);
  const float off = rs.surface_offset();
  const vec3 xo = vplkit::bvh_offset_point(x, n_x, off);
  integral r;
  for (std::size_t t = 0; t < s.triangles.size(); ++t) {
    const triangle& tri = s.triangles[t];
    const glm::dvec3 cr = glm::cross(glm::dvec3(tri.p[1] - tri.p[0]), glm::dvec3(tri.p[2] - tri.p[0]));
    const double area = 0.5 * glm::length(cr);
    if (!(area > 0.0)) continue;
    const vec3 n_tri = vec3(cr / glm::length(cr));
    const double dA = area / (double(m) * m);
    auto add = [&](double a, double b) {  // a, b: barycentric weights of corners 1 and 2
      ray_scene::hit h;
      h.hit = true;
      h.triangle = static_cast<std::uint32_t>(t);
      h.u = float(a);
      h.v = float(b);
      h.geometric_normal = n_tri;
      const vec3 y = (1.0f - h.u - h.v) * tri.p[0] + h.u * tri.p[1] + h.v * tri.p[2];
      const glm::dvec3 d = glm::dvec3(y) - glm::dvec3(x);
      const double r2 = glm::dot(d, d);
      const glm::dvec3 w = d / std::sqrt(r2);
      const double cos_x = glm::dot(glm::dvec3(n_x), w);
      if (!(cos_x > 0.0)) return;
      vec3 n_gy = n_tri;
      if (glm::dot(n_gy, light.position - y) < 0.0f) n_gy = -n_gy;  // the lit side
      const double cos_y = -glm::dot(glm::dvec3(n_gy), w);
      if (!(cos_y > 0.0)) return;  // x sees y's unlit side
      const vec3 yo = vplkit::bvh_offset_point(y, n_gy, off);
      if (rs.occluded(xo, yo - xo, 1.0f)) return;
      vec3 n_sy = rs.shading_normal(h);
      if (glm::dot(n_sy, n_gy) < 0.0f) n_sy = -n_sy;
      const glm::dvec3 l_o(vplkit::reflected_radiance(light.position, light.intensity, y, n_sy, rs.albedo_at(h)));
      const glm::dvec3 f = glm::dvec3(gp.albedo) / 3.141592653589793 * l_o * (cos_x * cos_y / r2 * dA);
      r.without_shadows += f;
      if (!rs.occluded(yo, light.position - yo, 1.0f)) r.with_shadows += f;
    };
    for (int i = 0; i < m; ++i)
      for (int j = 0; i + j < m; ++j) {
        add((i + 1.0 / 3.0) / m, (j + 1.0 / 3.0) / m);
        if (i + j <= m - 2) add((i + 2.0 / 3.0) / m, (j + 2.0 / 3.0) / m);
      }
  }
  return r;
}

// The gather point at barycentric (0.3, 0.3) of the first triangle whose facing normal is close to
// `dir`, lifted nowhere (on the surface), with the material's albedo.
vplkit::gather_point<float> gather_point_on(const scene& s, const ray_scene& rs, vec3 dir, std::size_t skip = 0) {
  for (std::size_t t = 0; t < s.triangles.size(); ++t) {
    const vec3 n = facing_normal(s.triangles[t]);
    if (glm::dot(n, dir) > 0.99f && skip-- == 0) {
      ray_scene::hit h;
      h.triangle = static_cast<std::uint32_t>(t);
      h.u = h.v = 0.3f;
      const triangle& tri = s.triangles[t];
      const vec3 p = 0.4f * tri.p[0] + 0.3f * tri.p[1] + 0.3f * tri.p[2];
      return {p, n, rs.albedo_at(h)};
    }
  }
  FAIL("no triangle faces the requested direction");
  return {};
}

}  // namespace

TEST_CASE("exact method: unbiased against a brute-force area integral on the Cornell box (4 sigma)") {
  // The light moved down beside the tall block, so that its shadow covers much of the floor and
  // the left wall, and the shadow term is large enough to be seen at 4 sigma.
  scene s = make_cornell_scene();
  s.light.position = vec3(0.25f, 0.7f, -0.35f);
  const ray_scene rs(s);
  const vplkit::point_light<float> light = vplkit::make_point_light(s.light.position, s.light.intensity);
  const std::vector<vplkit::gather_point<float>> points = {
      gather_point_on(s, rs, vec3(0, 1, 0)),      // floor (or a block's top)
      gather_point_on(s, rs, vec3(1, 0, 0)),      // the left wall (or a block's side)
      gather_point_on(s, rs, vec3(0, 0, 1), 1)};  // a wall facing +z
  int shadow_term_matters = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const vplkit::gather_point<float>& gp = points[i];
    constexpr int batches = 256, per_batch = 512;
    glm::dvec3 sum(0.0), sum2(0.0);
    for (int b = 0; b < batches; ++b) {
      vplkit::counter_rng rng = vplkit::make_counter_rng(7u, static_cast<std::uint32_t>(b));
      const glm::dvec3 e(estimate_exact(rs, light, gp, rng, per_batch));
      sum += e;
      sum2 += e * e;
    }
    const glm::dvec3 mean = sum / double(batches);
    const glm::dvec3 sigma = glm::sqrt(glm::max(sum2 / double(batches) - mean * mean, glm::dvec3(0.0)) / double(batches - 1));
    const integral ref = brute_force(s, rs, light, gp, 160);
    for (int c = 0; c < 3; ++c) {
      INFO("gather point " << i << " channel " << c << ": estimate " << mean[c] << " +- " << sigma[c] << ", integral "
                           << ref.with_shadows[c] << ", without shadows " << ref.without_shadows[c]);
      std::cout << "gather point " << i << " channel " << c << ": estimate " << mean[c] << " +- " << sigma[c]
                << ", integral " << ref.with_shadows[c] << " (" << (mean[c] - ref.with_shadows[c]) / sigma[c]
                << " sigma), without shadows " << ref.without_shadows[c] << "\n";
      REQUIRE(ref.with_shadows[c] > 0.0);
      CHECK(sigma[c] < 0.02 * mean[c]);  // precise enough that the 4-sigma test means something
      CHECK(std::abs(mean[c] - ref.with_shadows[c]) <= 4.0 * sigma[c]);
      if (std::abs(mean[c] - ref.without_shadows[c]) > 4.0 * sigma[c]) ++shadow_term_matters;
    }
  }
  CHECK(shadow_term_matters > 0);
}

namespace {

// estimate_exact's loop with the hemisphere around n_g instead of gp's geometric normal: what the
// estimator did before it took the G-buffer's normal, where the camera ray met the other triangle.
glm::dvec3 estimate_around(const ray_scene& rs, const vplkit::point_light<float>& light,
                           const vplkit::gather_point<float>& gp, vec3 n_g, std::uint32_t seed, int n_dirs) {
  vplkit::counter_rng rng = vplkit::make_counter_rng(seed, 0u);
  const vplkit::orthonormal_basis<float> frame = vplkit::make_orthonormal_basis(n_g);
  glm::dvec3 sum(0.0);
  for (int k = 0; k < n_dirs; ++k) {
    const float u0 = vplkit::rng_next_unit<float>(rng);
    const float u1 = vplkit::rng_next_unit<float>(rng);
    const vec3 local = vplkit::sample_cosine_hemisphere(vplkit::vec2<float>(u0, u1));
    sum += glm::dvec3(exact_sample(rs, light, gp, n_g, vplkit::to_world(frame, local)));
  }
  return sum / double(n_dirs);
}

double luminance(glm::dvec3 c) { return (c.x + c.y + c.z) / 3.0; }

}  // namespace

// A pixel centre on an edge: the rasteriser keeps one triangle (its geometric and shading normals
// in the G-buffer), while a ray from the eye may meet the other at the same t. The estimate must
// be that of the G-buffer's triangle, continuous with the points just inside it, as gathering's
// is. (It once took the normal of the triangle the camera ray met, with the G-buffer's shading
// normal: on sponza a pixel on an arch's edge, shading normal turned up, geometric normal down,
// read 0 where every gathering method read 0.45-0.56.)
TEST_CASE("exact method: a gather point on an edge is estimated in its own triangle's hemisphere") {
  const scene s = make_cornell_scene();
  const ray_scene rs(s);
  const vplkit::point_light<float> light = vplkit::make_point_light(s.light.position, s.light.intensity);
  // The short block's top face (y = 0.6) and the side face that shares one of its edges.
  std::vector<vec3> top;
  for (const triangle& t : s.triangles)
    if (glm::dot(facing_normal(t), vec3(0, 1, 0)) > 0.999f && t.p[0].y > 0.59f && t.p[0].y < 0.61f && t.p[0].x > 0.0f)
      for (const vec3& p : t.p) top.push_back(p);
  REQUIRE(top.size() == 6);  // two triangles
  vec3 centre(0.0f);
  for (const vec3& p : top) centre += p / 6.0f;
  vec3 a(0.0f), b(0.0f), n_side(0.0f);
  for (const triangle& t : s.triangles) {
    const vec3 n = facing_normal(t);
    if (std::abs(n.y) > 1e-3f || glm::dot(n, vec3(0, 0, 1)) < 0.5f) continue;  // a side facing the camera
    std::vector<vec3> shared;
    for (const vec3& p : t.p)
      for (const vec3& q : top)
        if (glm::length(p - q) < 1e-5f) {
          shared.push_back(p);
          break;
        }
    if (shared.size() == 2) {
      a = shared[0], b = shared[1], n_side = n;
      break;
    }
  }
  REQUIRE(glm::length(n_side) > 0.5f);
  const vec3 m = 0.5f * (a + b);
  const vec3 n_top(0, 1, 0);
  const vec3 into_top = glm::normalize(vec3(centre.x - m.x, 0.0f, centre.z - m.z));
  const vec3 albedo(0.5f);
  const vplkit::gather_point<float> on_edge_top{m, n_top, albedo}, inside_top{m + 2e-3f * into_top, n_top, albedo};
  const vplkit::gather_point<float> on_edge_side{m, n_side, albedo},
      inside_side{m - vec3(0.0f, 2e-3f, 0.0f), n_side, albedo};
  constexpr int n = 1 << 14;
  auto estimate = [&](const vplkit::gather_point<float>& gp) {
    vplkit::counter_rng rng = vplkit::make_counter_rng(11u, 0u);
    return luminance(glm::dvec3(estimate_exact(rs, light, gp, rng, n)));
  };
  const double top_edge = estimate(on_edge_top), top_in = estimate(inside_top);
  const double side_edge = estimate(on_edge_side), side_in = estimate(inside_side);
  INFO("top: edge " << top_edge << ", inside " << top_in << "; side: edge " << side_edge << ", inside " << side_in);
  REQUIRE(top_in > 0.0);
  REQUIRE(side_in > 0.0);
  // The same directions from points 2 mm apart: equal but for the rays that graze the edge.
  CHECK(std::abs(top_edge - top_in) <= 0.03 * top_in);
  CHECK(std::abs(side_edge - side_in) <= 0.03 * side_in);
  // The test's power: either point estimated around the other face's normal (with its own as the
  // receiver's cosine) is far from it.
  const double top_around_side = luminance(estimate_around(rs, light, on_edge_top, n_side, 11u, n));
  const double side_around_top = luminance(estimate_around(rs, light, on_edge_side, n_top, 11u, n));
  INFO("top around the side's normal " << top_around_side << ", side around the top's " << side_around_top);
  CHECK(std::abs(top_around_side - top_in) > 0.2 * top_in);
  CHECK(std::abs(side_around_top - side_in) > 0.2 * side_in);
}

namespace {

// A floor (y = 0, 2 x 2) and a ramp that rises over its +x half, facing up and to -x (n_B =
// (-1, 1, 0) / sqrt 2), its plane `behind` off the origin along n_B (negative: the origin lies
// behind it), lit from the upper left. Flat normals.
scene floor_and_ramp(float behind) {
  scene s;
  s.name = "floor_and_ramp";
  s.materials.push_back(material{"white", vec3(0.8f), -1, vec3(0.0f)});
  auto quad = [&](vec3 a, vec3 b, vec3 c, vec3 d) {
    const vec3 n = glm::normalize(glm::cross(b - a, c - a));
    s.triangles.push_back(triangle{{a, b, c}, {n, n, n}, {}, 0});
    s.triangles.push_back(triangle{{a, c, d}, {n, n, n}, {}, 0});
  };
  quad(vec3(-1, 0, -1), vec3(-1, 0, 1), vec3(1, 0, 1), vec3(1, 0, -1));  // floor, +y
  const vec3 n_b = glm::normalize(vec3(-1, 1, 0)), up_b = glm::normalize(vec3(1, 1, 0));
  const vec3 p0 = behind * n_b;  // the ramp's foot line passes here (the origin is `behind` its plane)
  quad(p0 + vec3(0, 0, -1), p0 + up_b + vec3(0, 0, -1), p0 + up_b + vec3(0, 0, 1), p0 + vec3(0, 0, 1));
  s.light.position = vec3(-0.8f, 1.5f, 0.0f);
  s.light.intensity = vec3(2.0f);
  s.cam.eye = vec3(-2.0f, 1.0f, 0.0f);
  s.cam.target = vec3(0.0f);
  return s;
}

}  // namespace

// At a junction the gather point may lie a hair behind the plane of the surface it meets (meshes
// that overlap at a crease: on sponza 6e-5 behind, three times the crease rule's tolerance). The
// ray origin, lifted along x's own normal, can cross that plane and meet the surface's lit front a
// few millimetres away; x itself sees only its back. The side is x's, as gathering decides it
// (dprsm_hit_radiance). (It was the direction's: sponza's pixel (57, 56) at 96x96 read 0.125 in
// (c) and 0.036-0.040 in gather and mis.)
TEST_CASE("exact method: a surface whose plane lies just in front of x sends nothing, whatever the lifted origin sees") {
  const float offset = ray_scene(floor_and_ramp(0.0f)).surface_offset();
  REQUIRE(offset > 0.0f);
  // x behind the ramp's plane by a third of what the lift moves it across (the lift along the
  // floor's normal moves it offset / sqrt 2 along n_B).
  const float delta = offset / (3.0f * std::sqrt(2.0f));
  const vec3 dir = glm::normalize(vec3(1.0f, 0.3f, 0.0f));  // from x towards the ramp, low
  for (const float behind : {delta, -delta}) {
    const scene s = floor_and_ramp(behind);
    const ray_scene rs(s);
    REQUIRE(rs.surface_offset() == offset);
    const vplkit::point_light<float> light = vplkit::make_point_light(s.light.position, s.light.intensity);
    const vplkit::gather_point<float> gp{vec3(0.0f), vec3(0, 1, 0), vec3(0.5f)};
    const ray_scene::hit h = rs.intersect(vplkit::bvh_offset_point(gp.position, gp.normal, offset), dir);
    REQUIRE(h.hit);
    INFO("x " << (behind > 0.0f ? "behind" : "in front of") << " the ramp's plane by " << delta << "; hit at "
              << h.position.x << ", " << h.position.y << ", normal y " << h.geometric_normal.y);
    REQUIRE(std::abs(h.geometric_normal.x) > 0.5f);  // the ramp, not the floor
    REQUIRE(h.position.x < 10.0f * offset);  // met near x: the junction's near field
    const vec3 value = exact_sample(rs, light, gp, vec3(0, 1, 0), dir);
    if (behind > 0.0f)
      CHECK(value == vec3(0.0f));  // x sees the ramp's back
    else
      CHECK(value.y > 0.0f);  // the same ray from in front: the lit front (the test's power)
  }
}

TEST_CASE("exact visibility on the CPU follows the pack BVH's contract") {
  const scene s = make_cornell_scene();
  const ray_scene rs(s);
  const aabb box = bounds(s);
  CHECK(rs.surface_offset() > 0.0f);
  CHECK(rs.surface_offset() < 1e-3f * box.diagonal());
  // Two points on the floor see each other unless a block stands between them; a point sees itself.
  const vec3 up(0, 1, 0);
  const vec3 a(box.lo.x + 0.05f * (box.hi.x - box.lo.x), box.lo.y, box.lo.z + 0.05f * (box.hi.z - box.lo.z));
  CHECK(rs.visible(a, up, a, up));
  CHECK_FALSE(rs.visible(vec3(NAN), up, a, up));
  // Through the floor: the point below the floor is hidden from the one above.
  CHECK_FALSE(rs.visible(a + vec3(0, 0.1f, 0), up, a - vec3(0, 0.1f, 0), -up));
  const vplkit::ray_hit<float> down = rs.trace(a + vec3(0, 0.2f, 0), up, vec3(0, -1, 0));
  REQUIRE(down.hit);
  CHECK(down.position.y == Approx(box.lo.y).margin(1e-5));
}
