// SPDX-License-Identifier: MIT
// The DPRSM pass's per-frame mesh (raster/dprsm_mesh.hpp) against the plain path it replaces,
// gl_mesh::upload(tessellate_on_all_cores(...)): the same vertex bytes in the GPU buffer and the
// same draw ranges, frame after frame as the light moves (the mesh grows and shrinks, the buffer
// keeps its storage), on scenes whose materials are not in order.
#include "raster/dprsm_mesh.hpp"
#include "raster/gl_mesh.hpp"
#include "raster/tessellate.hpp"
#include "render/pipeline.hpp"
#include "scene/builtin_scenes.hpp"

#include <catch2/catch.hpp>

#include <epoxy/gl.h>

#include <cstring>
#include <memory>
#include <vector>

using namespace vplrender;

namespace {

std::vector<gl_mesh_vertex> read_vertices(const gl_mesh& m) {
  std::size_t n = 0;
  for (const gl_mesh::range& r : m.ranges()) n += static_cast<std::size_t>(r.count);
  std::vector<gl_mesh_vertex> v(n);
  glBindVertexArray(m.vertex_array());
  GLint vbo = 0;
  glGetVertexAttribiv(0, GL_VERTEX_ATTRIB_ARRAY_BUFFER_BINDING, &vbo);
  glBindBuffer(GL_ARRAY_BUFFER, static_cast<GLuint>(vbo));
  if (n) glGetBufferSubData(GL_ARRAY_BUFFER, 0, static_cast<GLsizeiptr>(n * sizeof(gl_mesh_vertex)), v.data());
  glBindVertexArray(0);
  return v;
}

bool same_ranges(const gl_mesh& a, const gl_mesh& b) {
  if (a.ranges().size() != b.ranges().size()) return false;
  for (std::size_t i = 0; i < a.ranges().size(); ++i)
    if (a.ranges()[i].material != b.ranges()[i].material || a.ranges()[i].first != b.ranges()[i].first ||
        a.ranges()[i].count != b.ranges()[i].count)
      return false;
  return true;
}

// cornell with its triangles in reverse order (materials out of order) and each wall triangle's
// material cycled, so a frame's mesh needs the material sort that dprsm_mesh does once.
scene shuffled_cornell() {
  scene s = make_cornell_scene();
  std::vector<triangle> r(s.triangles.rbegin(), s.triangles.rend());
  for (std::size_t i = 0; i < r.size(); ++i) r[i].material = static_cast<std::uint32_t>((i * 7) % s.materials.size());
  s.triangles = r;
  return s;
}

}  // namespace

TEST_CASE("dprsm_mesh gives gl_mesh::upload(tessellate_on_all_cores(...)) frame after frame") {
  pipeline_gl_context().make_current();
  const scene s = shuffled_cornell();
  REQUIRE(s.materials.size() > 2);
  dprsm_mesh fast(s.triangles);
  // The light on a path: near the ceiling (many splits), mid-room, near a wall, back up.
  const vec3 lights[] = {vec3(0.0f, 1.9f, 0.0f), vec3(0.2f, 1.0f, -0.3f), vec3(0.95f, 0.5f, 0.1f), vec3(-0.5f, 1.95f, 0.4f)};
  for (const int R : {512, 64}) {
    tessellation_params p;
    p.max_angle = tessellation_angle_for_resolution(R);
    for (const vec3& light : lights) {
      INFO("R " << R << ", light " << light.x << " " << light.y << " " << light.z);
      tessellation_stats st_fast, st_plain;
      fast.build(light, p, &st_fast);
      gl_mesh plain;
      plain.upload(tessellate_on_all_cores(s.triangles, light, p, &st_plain));
      CHECK(st_fast.input == st_plain.input);
      CHECK(st_fast.output == st_plain.output);
      CHECK(st_fast.capped == st_plain.capped);
      CHECK(same_ranges(fast.mesh(), plain));
      const std::vector<gl_mesh_vertex> a = read_vertices(fast.mesh()), b = read_vertices(plain);
      REQUIRE(a.size() == 3 * st_plain.output);
      REQUIRE(a.size() == b.size());
      CHECK(std::memcmp(a.data(), b.data(), a.size() * sizeof(gl_mesh_vertex)) == 0);
    }
  }
}

TEST_CASE("dprsm_mesh split ahead: taken for its light, dropped for another, the same mesh either way") {
  pipeline_gl_context().make_current();
  const scene s = shuffled_cornell();
  tessellation_params p;
  p.max_angle = tessellation_angle_for_resolution(256);
  const vec3 a(0.0f, 1.9f, 0.0f), b(0.3f, 1.2f, 0.2f);
  auto plain_for = [&](vec3 light, gl_mesh& m) { m.upload(tessellate_on_all_cores(s.triangles, light, p)); };
  dprsm_mesh mesh(s.triangles);
  SECTION("ahead for the light that comes: taken") {
    mesh.build(b, p);
    mesh.split_ahead(a, p);
    const dprsm_mesh::build_report r = mesh.build(a, p);
    CHECK(r.ahead);
    CHECK(r.ahead_ms > 0.0);
    gl_mesh plain;
    plain_for(a, plain);
    CHECK(same_ranges(mesh.mesh(), plain));
    const std::vector<gl_mesh_vertex> x = read_vertices(mesh.mesh()), y = read_vertices(plain);
    REQUIRE(x.size() == y.size());
    CHECK(std::memcmp(x.data(), y.data(), x.size() * sizeof(gl_mesh_vertex)) == 0);
    // The next frame has no split ahead: split there, from the buffers of two frames ago.
    CHECK_FALSE(mesh.build(b, p).ahead);
    gl_mesh plain_b;
    plain_for(b, plain_b);
    const std::vector<gl_mesh_vertex> u = read_vertices(mesh.mesh()), w = read_vertices(plain_b);
    REQUIRE(u.size() == w.size());
    CHECK(std::memcmp(u.data(), w.data(), u.size() * sizeof(gl_mesh_vertex)) == 0);
  }
  SECTION("ahead for another light, or other parameters: dropped") {
    mesh.split_ahead(a, p);
    CHECK_FALSE(mesh.build(b, p).ahead);
    gl_mesh plain;
    plain_for(b, plain);
    const std::vector<gl_mesh_vertex> x = read_vertices(mesh.mesh()), y = read_vertices(plain);
    REQUIRE(x.size() == y.size());
    CHECK(std::memcmp(x.data(), y.data(), x.size() * sizeof(gl_mesh_vertex)) == 0);
    tessellation_params q = p;
    q.max_depth = 7;
    mesh.split_ahead(a, q);
    CHECK_FALSE(mesh.build(a, p).ahead);
  }
  SECTION("destroyed with a split ahead running: waits for it") {
    auto m = std::make_unique<dprsm_mesh>(s.triangles);
    m->split_ahead(a, p);
    m.reset();
    SUCCEED();
  }
}
