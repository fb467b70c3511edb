// SPDX-License-Identifier: MIT
#include "raster/gl_mesh.hpp"

#include <headless_gl/compute.hpp>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cstddef>
#include <numeric>

namespace vplrender {

gl_mesh::~gl_mesh() {
  if (vbo_) glDeleteBuffers(1, &vbo_);
  if (vao_) glDeleteVertexArrays(1, &vao_);
  vplkit::gl::track_gpu_bytes(-bytes_);
}

void mesh_vertices(const triangle& t, gl_mesh_vertex out[3]) {
  const glm::dvec3 e1 = glm::dvec3(t.p[1]) - glm::dvec3(t.p[0]), e2 = glm::dvec3(t.p[2]) - glm::dvec3(t.p[0]);
  glm::dvec3 g = glm::cross(e1, e2);
  const double gl = glm::length(g);
  g = gl > 0.0 ? g / gl : glm::dvec3(0.0);
  const double w = glm::dot(g, (glm::dvec3(t.p[0]) + glm::dvec3(t.p[1]) + glm::dvec3(t.p[2])) / 3.0);
  for (int c = 0; c < 3; ++c) {
    const std::size_t ci = static_cast<std::size_t>(c);
    gl_mesh_vertex v{};
    for (int a = 0; a < 3; ++a) {
      v.p[a] = t.p[ci][a];
      v.n[a] = t.n[ci][a];
      v.plane[a] = static_cast<float>(g[a]);
    }
    v.uv[0] = t.uv[ci].x;
    v.uv[1] = t.uv[ci].y;
    v.plane[3] = static_cast<float>(w);
    out[c] = v;
  }
}

void gl_mesh::upload(const std::vector<triangle>& tris) {
  auto by_material = [&](std::size_t a, std::size_t b) { return tris[a].material < tris[b].material; };
  std::vector<std::size_t> order(tris.size());
  std::iota(order.begin(), order.end(), std::size_t(0));
  if (!std::is_sorted(order.begin(), order.end(), by_material)) std::stable_sort(order.begin(), order.end(), by_material);
  std::vector<std::vector<gl_mesh_vertex>> parts(1);
  std::vector<gl_mesh_vertex>& verts = parts[0];
  verts.resize(tris.size() * 3);
  std::vector<range> ranges;
  for (std::size_t k = 0; k < order.size(); ++k) {
    const triangle& t = tris[order[k]];
    if (ranges.empty() || ranges.back().material != t.material)
      ranges.push_back({t.material, static_cast<GLint>(3 * k), 0});
    mesh_vertices(t, &verts[3 * k]);
    ranges.back().count += 3;
  }
  upload_vertices(parts, std::move(ranges));
}

void gl_mesh::ensure_storage(long long bytes, long long headroom) {
  const bool first = !vao_;
  if (!vao_) glGenVertexArrays(1, &vao_);
  if (!vbo_) glGenBuffers(1, &vbo_);
  glBindVertexArray(vao_);
  glBindBuffer(GL_ARRAY_BUFFER, vbo_);
  if (first || bytes > bytes_) {
    const long long storage = bytes + headroom;
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(storage), nullptr, GL_DYNAMIC_DRAW);
    vplkit::gl::track_gpu_bytes(storage - bytes_);
    bytes_ = storage;
  }
  if (first) {
    // Locations 0-3 as shaders/raster_inputs.glsl declares them.
    const GLsizei stride = sizeof(gl_mesh_vertex);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(offsetof(gl_mesh_vertex, p)));
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(offsetof(gl_mesh_vertex, n)));
    glEnableVertexAttribArray(2);
    glVertexAttribPointer(2, 2, GL_FLOAT, GL_FALSE, stride, reinterpret_cast<const void*>(offsetof(gl_mesh_vertex, uv)));
    glEnableVertexAttribArray(3);
    glVertexAttribPointer(3, 4, GL_FLOAT, GL_FALSE, stride,
                          reinterpret_cast<const void*>(offsetof(gl_mesh_vertex, plane)));
  }
}

void gl_mesh::upload_vertices(const std::vector<std::vector<gl_mesh_vertex>>& parts, std::vector<range> ranges) {
  std::size_t n = 0;
  for (const std::vector<gl_mesh_vertex>& p : parts) n += p.size();
  const long long bytes = static_cast<long long>(n * sizeof(gl_mesh_vertex));
  // A scene's mesh is uploaded once (no headroom); a light's grows by a quarter when it outgrows.
  ensure_storage(bytes, bytes_ > 0 ? bytes / 4 : 0);
  std::size_t at = 0;
  for (const std::vector<gl_mesh_vertex>& p : parts) {
    if (p.empty()) continue;
    glBufferSubData(GL_ARRAY_BUFFER, static_cast<GLintptr>(at * sizeof(gl_mesh_vertex)),
                    static_cast<GLsizeiptr>(p.size() * sizeof(gl_mesh_vertex)), p.data());
    at += p.size();
  }
  ranges_ = std::move(ranges);
  glBindVertexArray(0);
  vplkit::gl::check_gl("vplrender: mesh upload");
}

}  // namespace vplrender
