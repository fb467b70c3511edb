// SPDX-License-Identifier: MIT
// The built-in scenes: valid, closed where they should be, open where they should be; and the
// ray casting and camera geometry they are checked with.
#include <catch2/catch.hpp>

#include "cli/scene_setup.hpp"
#include "io/errors.hpp"
#include "scene/builtin_scenes.hpp"
#include "scene/camera.hpp"
#include "scene/raycast.hpp"

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

using namespace vplrender;

namespace {

void check_well_formed(const scene& s) {
  REQUIRE_NOTHROW(validate_scene(s));
  for (const triangle& t : s.triangles) {
    CHECK(triangle_double_area(t) > 1e-6);
    // Shading normals agree with the winding (flat built-ins).
    const vec3 g = facing_normal(t);
    for (const vec3& n : t.n) CHECK(glm::dot(g, n) == Approx(1.0f).margin(1e-5));
  }
}

}  // namespace

TEST_CASE("built-in scenes are finite, unit-normal and otherwise valid") {
  for (const char* name : {"cornell", "open"}) {
    INFO(name);
    const scene s = make_builtin_scene(name);
    CHECK(s.name == name);
    check_well_formed(s);
    CHECK_NOTHROW(check_light_position(s, "built-in"));
  }
  CHECK(is_builtin_scene_name("cornell"));
  CHECK_FALSE(is_builtin_scene_name("Cornell"));
  CHECK_THROWS_AS(make_builtin_scene("nope"), input_error);
}

TEST_CASE("the cornell box is closed: every ray from the light or the camera hits a front face") {
  const scene s = make_cornell_scene();
  const aabb b = bounds(s);
  for (const glm::dvec3 origin : {glm::dvec3(s.light.position), glm::dvec3(s.cam.eye), glm::dvec3(0.9, 0.1, 2.9),
                                  glm::dvec3(-0.95, 1.95, -0.95)}) {
    std::size_t misses = 0, back = 0;
    for (const glm::dvec3& d : sphere_directions(4096)) {
      const ray_hit h = cast_ray(s.triangles, origin, d);
      if (!h.hit) {
        ++misses;
        continue;
      }
      if (h.back_face) ++back;
      const glm::dvec3 p = origin + h.t * d;
      CHECK(p.x >= b.lo.x - 1e-4);
      CHECK(p.x <= b.hi.x + 1e-4);
    }
    CHECK(misses == 0);
    CHECK(back == 0);
  }
}

TEST_CASE("the cornell box: red left wall, green right wall, camera inside looking at the back wall") {
  const scene s = make_cornell_scene();
  const aabb b = bounds(s);
  CHECK(glm::all(glm::greaterThan(s.cam.eye, b.lo)));
  CHECK(glm::all(glm::lessThan(s.cam.eye, b.hi)));
  // Light just below the ceiling.
  CHECK(s.light.position.y < b.hi.y);
  CHECK(b.hi.y - s.light.position.y <= 0.1f * (b.hi.y - b.lo.y) + 1e-6f);
  // What the camera sees in the middle, left and right of the image.
  const camera_frame f = make_camera_frame(s.cam);
  auto seen = [&](float x, float y) {
    const vec3 d = primary_ray_direction(f, 512, 512, x, y);
    const ray_hit h = cast_ray(s.triangles, glm::dvec3(f.eye), glm::dvec3(d));
    REQUIRE(h.hit);
    CHECK_FALSE(h.back_face);
    return s.materials[s.triangles[h.triangle].material].name;
  };
  CHECK(seen(1.0f, 256.0f) == "red");
  CHECK(seen(511.0f, 256.0f) == "green");
  CHECK(seen(256.0f, 10.0f) == "white");  // ceiling
  // Both blocks are in view: some pixel in the lower half sees a block face (not the floor).
  std::size_t block_pixels = 0;
  for (int x = 0; x < 64; ++x) {
    for (int y = 32; y < 64; ++y) {
      const vec3 d = primary_ray_direction(f, 64, 64, x + 0.5f, y + 0.5f);
      const ray_hit h = cast_ray(s.triangles, glm::dvec3(f.eye), glm::dvec3(d));
      if (h.hit && h.triangle >= 12) ++block_pixels;  // the room is the first 12 triangles
    }
  }
  CHECK(block_pixels > 100);
}

TEST_CASE("the open scene: the light sees geometry in every hemisphere, and light escapes") {
  const scene s = make_open_scene();
  const glm::dvec3 c(s.light.position);
  std::size_t misses = 0;
  // For each axis and sign: count the directions of that hemisphere that hit something.
  std::size_t hits[3][2] = {{0, 0}, {0, 0}, {0, 0}}, total[3][2] = {{0, 0}, {0, 0}, {0, 0}};
  for (const glm::dvec3& d : sphere_directions(4096)) {
    const ray_hit h = cast_ray(s.triangles, c, d);
    if (!h.hit) ++misses;
    for (int a = 0; a < 3; ++a) {
      const int side = d[a] >= 0.0 ? 0 : 1;
      ++total[a][side];
      if (h.hit) ++hits[a][side];
    }
  }
  CHECK(misses > 200);  // open: a real fraction of the light escapes
  for (int a = 0; a < 3; ++a) {
    for (int side = 0; side < 2; ++side) {
      INFO("axis " << a << " side " << side);
      CHECK(hits[a][side] > total[a][side] / 10);  // every hemisphere sees a fair amount of geometry
    }
  }
}

TEST_CASE("ray casting: hits, misses, back faces and distances") {
  const scene s = make_cornell_scene();
  const ray_hit down = cast_ray(s.triangles, glm::dvec3(0.0, 1.0, 2.0), glm::dvec3(0.0, -1.0, 0.0));
  REQUIRE(down.hit);
  CHECK(down.t == Approx(1.0));
  CHECK_FALSE(down.back_face);
  // From outside the room the walls show their backs.
  const ray_hit in = cast_ray(s.triangles, glm::dvec3(0.0, 1.0, 10.0), glm::dvec3(0.0, 0.0, -1.0));
  REQUIRE(in.hit);
  CHECK(in.t == Approx(7.0));
  CHECK(in.back_face);
  CHECK_FALSE(cast_ray(s.triangles, glm::dvec3(0.0, 1.0, 10.0), glm::dvec3(0.0, 0.0, 1.0)).hit);
  CHECK(distance_to_geometry(s.triangles, glm::dvec3(0.0, 1.9, 0.0)) == Approx(0.1));
  // A zero direction hits nothing rather than producing NaN.
  CHECK_FALSE(cast_ray(s.triangles, glm::dvec3(0.0, 1.0, 2.0), glm::dvec3(0.0)).hit);
}

namespace {

// Every answer of rays_from_point against cast_ray's for the same ray, bit for bit.
std::size_t check_same_answers(const std::vector<triangle>& tris, const glm::dvec3& origin,
                               const std::vector<glm::dvec3>& dirs) {
  const rays_from_point from(tris, origin);
  std::size_t hits = 0;
  for (const glm::dvec3& d : dirs) {
    for (double t_min : {0.0, 1e-3, -1.0}) {
      const ray_hit a = cast_ray(tris, origin, d, t_min), b = from.cast(d, t_min);
      INFO("origin " << origin.x << " " << origin.y << " " << origin.z << " dir " << d.x << " " << d.y << " " << d.z
                     << " t_min " << t_min);
      REQUIRE(a.hit == b.hit);
      if (!a.hit) continue;
      ++hits;
      REQUIRE(a.triangle == b.triangle);
      REQUIRE(a.t == b.t);
      REQUIRE(a.back_face == b.back_face);
    }
  }
  return hits;
}

// Directions that graze what a cone bounds: exactly at vertices, edge midpoints and centroids (the
// rays that lie on or next to a cone's boundary), scaled off unit length.
std::vector<glm::dvec3> directions_at(const std::vector<triangle>& tris, std::size_t count, const glm::dvec3& origin) {
  std::vector<glm::dvec3> dirs = sphere_directions(256);
  for (std::size_t i = 0; i < std::min(count, tris.size()); ++i) {
    const glm::dvec3 a(tris[i].p[0]), b(tris[i].p[1]), c(tris[i].p[2]);
    for (const glm::dvec3& q : {a, b, c, 0.5 * (a + b), 0.5 * (b + c), 0.5 * (c + a), (a + b + c) / 3.0})
      dirs.push_back(3.7 * (q - origin));
  }
  dirs.push_back(glm::dvec3(0.0));
  return dirs;
}

}  // namespace

TEST_CASE("rays from one point: the cone-skipping caster answers as cast_ray, bit for bit") {
  SECTION("the built-in rooms, from the light, a corner, a wall and a vertex") {
    for (const char* name : {"cornell", "open"}) {
      INFO(name);
      const scene s = make_builtin_scene(name);
      const glm::dvec3 vertex(s.triangles[3].p[1]);
      for (const glm::dvec3& o : {glm::dvec3(s.light.position), glm::dvec3(0.3, 0.2, 0.1), vertex,
                                  glm::dvec3(0.0, 1.0, 0.0) + 0.25 * (vertex - glm::dvec3(0.0, 1.0, 0.0))}) {
        CHECK(check_same_answers(s.triangles, o, directions_at(s.triangles, s.triangles.size(), o)) > 100);
      }
    }
  }
  SECTION("a random soup: slivers, tiny and huge triangles, origins on planes and edges") {
    std::mt19937_64 rng(20261127);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    auto point = [&](double scale) { return vec3(glm::dvec3(u(rng), u(rng), u(rng)) * scale); };
    std::vector<triangle> tris;
    for (int i = 0; i < 300; ++i) {
      triangle t;
      const vec3 c = point(1.0);
      const double size = i % 3 == 0 ? 1e-4 : (i % 3 == 1 ? 0.2 : 5.0);
      t.p = {c + point(size), c + point(size), c + point(size)};
      if (i % 7 == 0) t.p[2] = t.p[0] + 1e-6f * (t.p[1] - t.p[0]) + point(1e-7);  // a sliver
      const vec3 n = glm::normalize(glm::cross(t.p[1] - t.p[0], t.p[2] - t.p[0]));
      t.n = {n, n, n};
      tris.push_back(t);
    }
    std::vector<glm::dvec3> origins = {glm::dvec3(0.0), glm::dvec3(point(2.0)), glm::dvec3(tris[1].p[0]),
                                       0.5 * (glm::dvec3(tris[4].p[0]) + glm::dvec3(tris[4].p[1])),
                                       (glm::dvec3(tris[5].p[0]) + glm::dvec3(tris[5].p[1]) + glm::dvec3(tris[5].p[2])) / 3.0};
    for (const glm::dvec3& o : origins) {
      CHECK(check_same_answers(tris, o, directions_at(tris, 120, o)) > 50);
    }
  }
  SECTION("origins in a triangle's plane, rays in that plane (the determinant is rounding noise)") {
    std::mt19937_64 rng(7);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::size_t hits = 0;
    for (int i = 0; i < 200; ++i) {
      triangle t;
      for (vec3& p : t.p) p = vec3(u(rng), u(rng), u(rng));
      const vec3 n = glm::normalize(glm::cross(t.p[1] - t.p[0], t.p[2] - t.p[0]));
      t.n = {n, n, n};
      const glm::dvec3 a(t.p[0]), b(t.p[1]), c(t.p[2]);
      // Exact in double: float vertices combined with small integer weights.
      for (const glm::dvec3& o : {a + 2.0 * (b - a), a - (c - a), b + (b - a) + (c - a)}) {
        std::vector<glm::dvec3> dirs;
        for (const glm::dvec3& e : {b - a, c - a, c - b, a - o, b - o, c - o})
          for (double k : {1.0, -1.0, 0.5}) dirs.push_back(k * e);
        for (int j = 0; j < 20; ++j) dirs.push_back(u(rng) * (b - a) + u(rng) * (c - a));
        hits += check_same_answers({t}, o, dirs);
      }
    }
    CHECK(hits > 0);
  }
}

TEST_CASE("points inside a block, on a wall, and free are told apart") {
  const scene s = make_cornell_scene();
  CHECK(classify_point(s.triangles, glm::dvec3(0.0, 1.9, 0.0), 1e-4).kind == point_class::free);
  // Inside the short block (base centre (0.35, 0, 0.25), half size 0.3).
  CHECK(classify_point(s.triangles, glm::dvec3(0.35, 0.3, 0.25), 1e-4).kind == point_class::inside_solid);
  CHECK(classify_point(s.triangles, glm::dvec3(0.0, 0.0, 2.0), 1e-4).kind == point_class::on_surface);
  // Outside the closed room: every ray that hits sees a back face.
  CHECK(classify_point(s.triangles, glm::dvec3(0.0, 1.0, 10.0), 1e-4).kind == point_class::inside_solid);

  scene moved = s;
  moved.light.position = vec3(0.35f, 0.3f, 0.25f);
  CHECK_THROWS_WITH(check_light_position(moved, "--light"), Catch::Contains("--light: light position") &&
                                                                 Catch::Contains("is inside geometry"));
  moved.light.position = vec3(0.0f, 2.0f, 0.0f);
  CHECK_THROWS_WITH(check_light_position(moved, "--light"), Catch::Contains("lies on a surface"));
}

TEST_CASE("camera frame and primary rays") {
  camera c;
  c.eye = vec3(0.0f, 0.0f, 5.0f);
  c.target = vec3(0.0f);
  c.up = vec3(0.0f, 2.0f, 0.0f);  // need not be unit or orthogonal
  c.vfov_deg = 90.0f;
  const camera_frame f = make_camera_frame(c);
  CHECK(f.forward.z == Approx(-1.0f));
  CHECK(f.right.x == Approx(1.0f));
  CHECK(f.up.y == Approx(1.0f));
  CHECK(f.tan_half_vfov == Approx(1.0f));
  // Centre of a 2x2 image is the pixel corner shared by all four pixels: the view axis.
  const vec3 mid = primary_ray_direction(f, 2, 2, 1.0f, 1.0f);
  CHECK(mid.z == Approx(-1.0f));
  // Top edge at 45 degrees up (y down in image space), right edge at 45 degrees * aspect.
  const vec3 top = primary_ray_direction(f, 200, 100, 100.0f, 0.0f);
  CHECK(top.y == Approx(std::sqrt(0.5f)));
  const vec3 right = primary_ray_direction(f, 200, 100, 200.0f, 50.0f);
  CHECK(right.x / -right.z == Approx(2.0f));  // aspect 2, tan(45) = 1
  CHECK(glm::length(primary_ray_direction(f, 7, 3, 0.5f, 2.5f)) == Approx(1.0f));
}

TEST_CASE("validate_scene names the first offence") {
  scene s = make_cornell_scene();
  s.triangles[3].p[1].x = std::nanf("");
  CHECK_THROWS_WITH(validate_scene(s), Catch::Contains("triangle 3 has a non-finite position"));
  s = make_cornell_scene();
  s.triangles[5].n[0] = vec3(0.0f, 2.0f, 0.0f);
  CHECK_THROWS_WITH(validate_scene(s), Catch::Contains("triangle 5 has a normal that is not unit"));
  s = make_cornell_scene();
  s.triangles[0].material = 99;
  CHECK_THROWS_WITH(validate_scene(s), Catch::Contains("uses material 99"));
  s = make_cornell_scene();
  s.light.intensity = vec3(1.0f, -1.0f, 1.0f);
  CHECK_THROWS_WITH(validate_scene(s), Catch::Contains("light intensity"));
  s = make_cornell_scene();
  s.cam.target = s.cam.eye;
  CHECK_THROWS_WITH(validate_scene(s), Catch::Contains("eye and target coincide"));
  s = make_cornell_scene();
  s.materials[1].kd = vec3(1.5f, 0.0f, 0.0f);
  CHECK_THROWS_WITH(validate_scene(s), Catch::Contains("outside [0,1]"));
  s = make_cornell_scene();
  s.triangles.clear();
  CHECK_THROWS_WITH(validate_scene(s), Catch::Contains("no triangles"));
  s = make_cornell_scene();
  for (triangle& t : s.triangles) t.p = {vec3(1.0f), vec3(1.0f), vec3(1.0f)};
  CHECK_THROWS_WITH(validate_scene(s), Catch::Contains("degenerate scene"));
  s = make_cornell_scene();
  s.triangles[0].p[0] = vec3(3e38f);
  s.triangles[0].p[1] = vec3(-3e38f);
  CHECK_THROWS_WITH(validate_scene(s), Catch::Contains("not finite"));
}
