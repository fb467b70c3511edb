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
      const glm::dvec3 e(estimate_exact(rs, light, gp, glm::normalize(gp.normal), rng, per_batch));
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

TEST_CASE("exact method: the gather point's geometric normal comes from the triangle under it") {
  const scene s = make_cornell_scene();
  const ray_scene rs(s);
  // A point the camera sees: the middle of the back wall along the camera's view ray.
  const ray_scene::hit h = rs.intersect(s.cam.eye, s.cam.target - s.cam.eye);
  REQUIRE(h.hit);
  const vec3 toward_eye = glm::normalize(s.cam.eye - h.position);
  vec3 n_s = h.geometric_normal;
  if (glm::dot(n_s, toward_eye) < 0.0f) n_s = -n_s;
  // A tilted shading normal on the camera's side: the geometric normal is the triangle's, oriented
  // to the shading normal's side.
  const vec3 tilted = glm::normalize(n_s + 0.3f * glm::normalize(glm::cross(n_s, vec3(0.3f, 1.0f, 0.1f))));
  const vec3 n_g = gather_point_geometric_normal(rs, {h.position, tilted, vec3(0.5f)});
  CHECK(glm::dot(n_g, n_s) == Approx(1.0f).margin(1e-6));
  // Off every surface (in mid-air): the G-buffer normal is kept.
  const vec3 mid = 0.5f * (s.cam.eye + h.position);
  const vec3 kept = gather_point_geometric_normal(rs, {mid, tilted, vec3(0.5f)});
  CHECK(glm::dot(kept, tilted) == Approx(1.0f).margin(1e-6));
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
