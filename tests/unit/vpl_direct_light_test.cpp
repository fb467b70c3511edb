// SPDX-License-Identifier: MIT
// Direct light through the DPRSM's shadow test (vpl/direct_light.hpp): at the synthetic scene's
// gather points it is lit exactly where an exact shadow ray says so, and then equals the light's
// reflected radiance; background, back-facing and coincident points give 0.
#include <synthetic_scene.hpp>

#include <vplkit/vpl/direct_light.hpp>

#include <catch2/catch.hpp>

#include <cmath>

using namespace vplkit;
using namespace vplkit_test;

TEMPLATE_TEST_CASE("direct_light: lit where an exact shadow ray is, with the reflected radiance", "[vpl]",
                   float, double) {
  using T = TestType;
  const lit_room<T> room(64);
  int lit = 0;
  for (const auto& g : room.scene.gather_points()) {
    INFO(g.name);
    const vec3<T> e = direct_light(g.gp, room.view);
    if (g.in_shadow) {
      CHECK(e == vec3<T>(T(0)));
    } else {
      ++lit;
      CHECK(e == reflected_radiance(room.view.light.position, room.view.light.intensity, g.gp.position, g.gp.normal,
                                    g.gp.albedo));
      CHECK(e.x > T(0));
    }
    // The same point with a longer normal: the same answer.
    gather_point<T> scaled = g.gp;
    scaled.normal *= T(7);
    CHECK(direct_light(scaled, room.view) == e);
  }
  CHECK(lit >= 3);
}

TEMPLATE_TEST_CASE("direct_light: 0 for background, back-facing points and the light's own position", "[vpl]",
                   float, double) {
  using T = TestType;
  const lit_room<T> room(32);
  const gather_point<T> lit = room.scene.gather_points().front().gp;  // floor_open
  REQUIRE(direct_light(lit, room.view).x > T(0));
  gather_point<T> g = lit;
  g.normal = vec3<T>(T(0));
  CHECK(direct_light(g, room.view) == vec3<T>(T(0)));
  g.normal = -lit.normal;
  CHECK(direct_light(g, room.view) == vec3<T>(T(0)));
  g = lit;
  g.position = room.view.light.position;
  CHECK(direct_light(g, room.view) == vec3<T>(T(0)));
  g = lit;
  g.position.x = std::numeric_limits<T>::quiet_NaN();
  CHECK(direct_light(g, room.view) == vec3<T>(T(0)));
}

TEMPLATE_TEST_CASE("direct_light with two normals: the shading cosine where the geometric surface faces the light",
                   "[vpl]", float, double) {
  using T = TestType;
  const lit_room<T> room(64);
  const gather_point<T> lit = room.scene.gather_points().front().gp;  // floor_open
  const vec3<T> n = glm::normalize(lit.normal);
  const vec3<T> l = glm::normalize(room.view.light.position - lit.position);
  REQUIRE(glm::dot(n, l) > T(0.3));
  // A shading normal turned towards the light: the value uses it, the lit decision does not move.
  gather_point<T> g = lit;
  g.shading_normal = glm::normalize(n + T(0.8) * l);
  const vec3<T> e = direct_light(g, room.view);
  CHECK(e == reflected_radiance(room.view.light.position, room.view.light.intensity, g.position, g.shading_normal,
                                g.albedo));
  CHECK(e.x > direct_light(lit, room.view).x);
  // One turned away from the light while the surface faces it: 0 (the cosine is clamped).
  const vec3<T> side = glm::normalize(l - glm::dot(l, n) * n);
  g.shading_normal = glm::normalize(n - T(3) * side);
  REQUIRE(glm::dot(g.shading_normal, l) < T(0));
  CHECK(direct_light(g, room.view) == vec3<T>(T(0)));
  // The geometric surface facing away: 0 whatever the shading normal says.
  g = lit;
  g.normal = -n;
  g.shading_normal = n;
  CHECK(direct_light(g, room.view) == vec3<T>(T(0)));
  // The shading normal equal to the geometric one is the one-normal result, bit for bit.
  g = lit;
  g.shading_normal = lit.normal;
  CHECK(direct_light(g, room.view) == direct_light(lit, room.view));
}
