// SPDX-License-Identifier: MIT
#include "scene/builtin_scenes.hpp"

#include "io/errors.hpp"

#include <glm/geometric.hpp>

#include <cmath>

namespace vplrender {

namespace {

// A parallelogram centred at c spanned by the half-edges u and v, facing cross(u, v).
void add_rect(std::vector<triangle>& out, vec3 c, vec3 u, vec3 v, std::uint32_t mat) {
  const vec3 n = glm::normalize(glm::cross(u, v));
  const vec3 a = c - u - v, b = c + u - v, d = c + u + v, e = c - u + v;
  triangle t1{{a, b, d}, {n, n, n}, {vec2(0, 0), vec2(1, 0), vec2(1, 1)}, mat};
  triangle t2{{a, d, e}, {n, n, n}, {vec2(0, 0), vec2(1, 1), vec2(0, 1)}, mat};
  out.push_back(t1);
  out.push_back(t2);
}

// A closed box standing on y = base, rotated by `deg` about +Y, faces pointing outwards. The
// bottom face is kept so the block is a closed solid (inside/outside tests stay meaningful).
void add_block(std::vector<triangle>& out, vec3 base_centre, vec3 half, float deg, std::uint32_t mat) {
  const float r = deg * 3.14159265358979f / 180.0f;
  const vec3 x(std::cos(r), 0.0f, -std::sin(r)), y(0.0f, 1.0f, 0.0f), z(std::sin(r), 0.0f, std::cos(r));
  const vec3 c = base_centre + y * half.y;
  const vec3 hx = x * half.x, hy = y * half.y, hz = z * half.z;
  add_rect(out, c + hx, hy, hz, mat);  // +x
  add_rect(out, c - hx, hz, hy, mat);  // -x
  add_rect(out, c + hy, hz, hx, mat);  // +y
  add_rect(out, c - hy, hx, hz, mat);  // -y
  add_rect(out, c + hz, hx, hy, mat);  // +z
  add_rect(out, c - hz, hy, hx, mat);  // -z
}

material mat(const char* name, vec3 kd) {
  material m;
  m.name = name;
  m.kd = kd;
  return m;
}

}  // namespace

scene make_cornell_scene() {
  scene s;
  s.name = "cornell";
  // Albedos of the Cornell box data set (as in McGuire's archive).
  s.materials = {mat("white", vec3(0.725f, 0.71f, 0.68f)), mat("red", vec3(0.63f, 0.065f, 0.05f)),
                 mat("green", vec3(0.14f, 0.45f, 0.091f))};
  const std::uint32_t white = 0, red = 1, green = 2;
  // Room: x in [-1, 1], y in [0, 2], z in [-1, 3]; every face looks into the room.
  auto& t = s.triangles;
  add_rect(t, vec3(0, 0, 1), vec3(0, 0, 2), vec3(1, 0, 0), white);   // floor, +y
  add_rect(t, vec3(0, 2, 1), vec3(1, 0, 0), vec3(0, 0, 2), white);   // ceiling, -y
  add_rect(t, vec3(0, 1, -1), vec3(1, 0, 0), vec3(0, 1, 0), white);  // back wall, +z
  add_rect(t, vec3(0, 1, 3), vec3(0, 1, 0), vec3(1, 0, 0), white);   // front wall, -z
  add_rect(t, vec3(-1, 1, 1), vec3(0, 1, 0), vec3(0, 0, 2), red);    // left wall, +x
  add_rect(t, vec3(1, 1, 1), vec3(0, 0, 2), vec3(0, 1, 0), green);   // right wall, -x
  add_block(t, vec3(0.35f, 0.0f, 0.25f), vec3(0.3f, 0.3f, 0.3f), -17.0f, white);   // short block
  add_block(t, vec3(-0.35f, 0.0f, -0.4f), vec3(0.3f, 0.6f, 0.3f), 17.0f, white);   // tall block
  s.light.position = vec3(0.0f, 1.9f, 0.0f);  // 0.1 below the ceiling, above the blocks
  s.light.intensity = vec3(4.0f);
  s.cam.eye = vec3(0.0f, 1.0f, 2.9f);  // 0.1 inside the front wall
  s.cam.target = vec3(0.0f, 1.0f, -1.0f);
  s.cam.up = vec3(0.0f, 1.0f, 0.0f);
  s.cam.vfov_deg = 45.0f;
  return s;
}

scene make_open_scene() {
  scene s;
  s.name = "open";
  s.materials = {mat("grey", vec3(0.6f)), mat("white", vec3(0.725f, 0.71f, 0.68f)),
                 mat("blue", vec3(0.15f, 0.3f, 0.7f)), mat("yellow", vec3(0.8f, 0.7f, 0.2f))};
  const std::uint32_t grey = 0, white = 1, blue = 2, yellow = 3;
  auto& t = s.triangles;
  add_rect(t, vec3(0, 0, 0), vec3(0, 0, 4), vec3(4, 0, 0), grey);             // floor 8 x 8, +y
  add_rect(t, vec3(0, 2, -2), vec3(4, 0, 0), vec3(0, 2, 0), white);           // back wall, +z
  add_rect(t, vec3(-3, 1.5f, 0), vec3(0, 1.5f, 0), vec3(0, 0, 2), blue);      // side wall, +x
  add_rect(t, vec3(-1.5f, 3.2f, -1), vec3(1.5f, 0, 0), vec3(0, 0, 1), yellow); // overhang, -y
  add_block(t, vec3(1.3f, 0.0f, -0.8f), vec3(0.35f, 0.9f, 0.35f), 25.0f, white);
  add_block(t, vec3(-1.0f, 0.0f, 0.5f), vec3(0.4f, 0.4f, 0.4f), -10.0f, white);
  s.light.position = vec3(0.3f, 1.6f, 0.6f);
  s.light.intensity = vec3(5.0f);
  s.cam.eye = vec3(0.5f, 2.2f, 6.0f);
  s.cam.target = vec3(-0.2f, 1.1f, -0.5f);
  s.cam.up = vec3(0.0f, 1.0f, 0.0f);
  s.cam.vfov_deg = 50.0f;
  return s;
}

bool is_builtin_scene_name(const std::string& name) { return name == "cornell" || name == "open"; }

scene make_builtin_scene(const std::string& name) {
  if (name == "cornell") return make_cornell_scene();
  if (name == "open") return make_open_scene();
  throw input_error("unknown built-in scene '" + name + "' (built-ins: cornell, open)");
}

}  // namespace vplrender
