// SPDX-License-Identifier: MIT
// Automatic camera and light for OBJ scenes, the --camera/--light overrides, and the light
// position checks of prepare_scene.
#include <catch2/catch.hpp>

#include "cli/scene_setup.hpp"
#include "io/errors.hpp"
#include "renderer_test_util.hpp"
#include "scene/builtin_scenes.hpp"
#include "scene/camera.hpp"
#include "scene/framing.hpp"
#include "scene/raycast.hpp"

#include <glm/geometric.hpp>

#include <cmath>

using namespace vplrender;
using vplrender_test::temp_dir;

namespace {

// A closed room 4 x 3 x 5 (faces inward) with a closed box inside, as OBJ; optional emitter.
std::string room_obj(bool emitter) {
  std::string s =
      "mtllib room.mtl\n"
      "v 0 0 0\nv 4 0 0\nv 4 0 5\nv 0 0 5\nv 0 3 0\nv 4 3 0\nv 4 3 5\nv 0 3 5\n"
      "usemtl wall\n"
      "f 1 4 3 2\n"   // floor, +y
      "f 5 6 7 8\n"   // ceiling, -y
      "f 1 2 6 5\n"   // back z=0, +z
      "f 4 8 7 3\n"   // front z=5, -z
      "f 1 5 8 4\n"   // left x=0, +x
      "f 2 3 7 6\n";  // right x=4, -x
  // Box [1.5,2.5] x [0,2.4] x [2,3], outward.
  s += "v 1.5 0 2\nv 2.5 0 2\nv 2.5 0 3\nv 1.5 0 3\nv 1.5 2.4 2\nv 2.5 2.4 2\nv 2.5 2.4 3\nv 1.5 2.4 3\n"
       "f 9 10 11 12\nf 13 16 15 14\nf 9 13 14 10\nf 12 11 15 16\nf 9 12 16 13\nf 10 14 15 11\n";
  if (emitter)
    s += "v 0.5 2.99 0.5\nv 1.5 2.99 0.5\nv 1.5 2.99 1.5\nv 0.5 2.99 1.5\nusemtl lamp\nf 17 18 19 20\n";
  return s;
}

const char* kRoomMtl = "newmtl wall\nKd 0.5 0.5 0.5\nnewmtl lamp\nKd 0.8 0.8 0.8\nKe 10 8 6\n";

options opts_for(const std::string& scene_path, std::vector<std::string> extra = {}) {
  std::vector<std::string> args = {"vplrender", "--scene", scene_path};
  args.insert(args.end(), extra.begin(), extra.end());
  return parse_command_line(args).opts;
}

}  // namespace

TEST_CASE("the automatic camera sees the whole bounding box from outside it") {
  aabb box;
  box.lo = vec3(-3.0f, 1.0f, -10.0f);
  box.hi = vec3(5.0f, 2.0f, 4.0f);
  for (const auto& size : {std::pair<int, int>{512, 512}, {1024, 256}, {200, 800}}) {
    const camera c = auto_camera(box, size.first, size.second);
    REQUIRE_NOTHROW(validate_camera(c, "auto"));
    CHECK(c.eye.z > box.hi.z);  // outside, on the +Z side
    const camera_frame f = make_camera_frame(c);
    const float aspect = static_cast<float>(size.first) / static_cast<float>(size.second);
    for (int i = 0; i < 8; ++i) {
      const vec3 corner((i & 1) ? box.hi.x : box.lo.x, (i & 2) ? box.hi.y : box.lo.y, (i & 4) ? box.hi.z : box.lo.z);
      const vec3 v = corner - f.eye;
      const float z = glm::dot(v, f.forward);
      REQUIRE(z > 0.0f);
      CHECK(std::abs(glm::dot(v, f.up) / z) <= f.tan_half_vfov * 1.0001f);
      CHECK(std::abs(glm::dot(v, f.right) / z) <= aspect * f.tan_half_vfov * 1.0001f);
    }
  }
}

TEST_CASE("without emitters the light goes to a free point on the vertical centre line") {
  temp_dir d;
  d.write("room.mtl", kRoomMtl);
  const prepared_scene p = prepare_scene(opts_for(d.write("room.obj", room_obj(false))));
  // The box occupies the centre line up to y = 2.4 = 0.8 of the height; 3/4 and 1/2 are inside it, so
  // the light must have moved on to the next candidate, 7/8 = 2.625, above the box.
  const vec3 l = p.s.light.position;
  CHECK(l.x == Approx(2.0f));
  CHECK(l.z == Approx(2.5f));
  CHECK(l.y == Approx(0.875f * 3.0f));
  CHECK(classify_point(p.s.triangles, glm::dvec3(l), 1e-3).kind == point_class::free);
  const float diag = bounds(p.s).diagonal();
  CHECK(p.s.light.intensity.x == Approx(0.25f * diag * diag));
  CHECK(p.light_rule.find("automatic") == 0);
  CHECK(p.camera_rule.find("automatic") == 0);
  CHECK_FALSE(p.light_outside_bounds);
}

TEST_CASE("with emitters the light sits just off their centroid with the same flux") {
  temp_dir d;
  d.write("room.mtl", kRoomMtl);
  const scene s = prepare_scene(opts_for(d.write("room.obj", room_obj(true)))).s;
  const vec3 l = s.light.position;
  CHECK(l.x == Approx(1.0f));
  CHECK(l.z == Approx(1.0f));
  // The lamp quad at y = 2.99 faces down (its winding): the light is 1% of the diagonal below.
  CHECK(l.y == Approx(2.99f - 0.01f * bounds(s).diagonal()).epsilon(1e-4));
  // Ke * area / 4 with area 1.
  CHECK(s.light.intensity.x == Approx(2.5f));
  CHECK(s.light.intensity.y == Approx(2.0f));
  CHECK(s.light.intensity.z == Approx(1.5f));
}

TEST_CASE("the --camera and --light flags override the automatic ones -- --light position alone keeps the intensity rule") {
  temp_dir d;
  d.write("room.mtl", kRoomMtl);
  const std::string path = d.write("room.obj", room_obj(false));
  const prepared_scene a = prepare_scene(opts_for(path, {"--camera", "2,1.5,4.5,2,1.5,0,0,1,0,70", "--light", "1,1,1,3,2,1"}));
  CHECK(a.s.cam.eye == vec3(2.0f, 1.5f, 4.5f));
  CHECK(a.s.cam.vfov_deg == 70.0f);
  CHECK(a.camera_rule == "--camera");
  CHECK(a.s.light.position == vec3(1.0f));
  CHECK(a.s.light.intensity == vec3(3.0f, 2.0f, 1.0f));
  CHECK(a.light_rule == "--light");
  const prepared_scene b = prepare_scene(opts_for(path, {"--light", "1,1,1"}));
  CHECK(b.s.light.position == vec3(1.0f));
  const float diag = bounds(b.s).diagonal();
  CHECK(b.s.light.intensity.x == Approx(0.25f * diag * diag));
  CHECK(b.light_rule == "--light position, automatic intensity");
  // Built-in scenes take the overrides too.
  const prepared_scene c = prepare_scene(parse_command_line({"vplrender", "--light", "0,1,2"}).opts);
  CHECK(c.s.light.position == vec3(0.0f, 1.0f, 2.0f));
  CHECK(c.s.light.intensity == make_cornell_scene().light.intensity);
}

TEST_CASE("a light inside a solid, on a surface, or outside the scene") {
  temp_dir d;
  d.write("room.mtl", kRoomMtl);
  const std::string path = d.write("room.obj", room_obj(false));
  CHECK_THROWS_WITH(prepare_scene(opts_for(path, {"--light", "2,1,2.5"})),
                    Catch::StartsWith("--light: light position (2, 1, 2.5) is inside geometry"));
  CHECK_THROWS_WITH(prepare_scene(opts_for(path, {"--light", "2,0,1"})), Catch::Contains("lies on a surface"));
  // Outside the closed room it looks like the inside of a solid (every ray meets a wall's back).
  CHECK_THROWS_WITH(prepare_scene(opts_for(path, {"--light", "2,1,9"})), Catch::Contains("is inside geometry"));
  // In the open scene, a light above everything is well defined: flagged, not refused.
  const prepared_scene p = prepare_scene(parse_command_line({"vplrender", "--scene", "open", "--light", "0,10,0"}).opts);
  CHECK(p.light_outside_bounds);
}

TEST_CASE("a scene where no automatic light position is free is an error asking for --light") {
  temp_dir d;
  // A solid box with outward faces: every candidate on its centre line is inside it.
  const std::string obj =
      "v 0 0 0\nv 1 0 0\nv 1 0 1\nv 0 0 1\nv 0 1 0\nv 1 1 0\nv 1 1 1\nv 0 1 1\n"
      "f 1 2 3 4\nf 5 8 7 6\nf 1 5 6 2\nf 4 3 7 8\nf 1 4 8 5\nf 2 6 7 3\n";
  CHECK_THROWS_WITH(prepare_scene(opts_for(d.write("solid.obj", obj))), Catch::Contains("set one with --light"));
  CHECK_NOTHROW(prepare_scene(opts_for(d.path() + "/solid.obj", {"--light", "0.5,2,0.5"})));
}

TEST_CASE("describe() summarises scene, camera, light and parameters") {
  const options o = parse_command_line({"vplrender", "--scene", "open", "--paper"}).opts;
  const std::string text = describe(prepare_scene(o), o);
  CHECK(text.find("scene     open: 32 triangles") != std::string::npos);
  CHECK(text.find("800 VPLs") != std::string::npos);
  CHECK(text.find("DPRSM 2x512x512") != std::string::npos);
  CHECK(text.find("[built-in]") != std::string::npos);
}
