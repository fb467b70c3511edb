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

void gl_mesh::upload(const std::vector<triangle>& tris_in) {
  std::vector<std::size_t> order(tris_in.size());
  std::iota(order.begin(), order.end(), std::size_t(0));
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return tris_in[a].material < tris_in[b].material; });
  std::vector<gl_mesh_vertex> verts;
  verts.reserve(tris_in.size() * 3);
  ranges_.clear();
  for (std::size_t k = 0; k < order.size(); ++k) {
    const triangle& t = tris_in[order[k]];
    const glm::dvec3 e1 = glm::dvec3(t.p[1]) - glm::dvec3(t.p[0]), e2 = glm::dvec3(t.p[2]) - glm::dvec3(t.p[0]);
    glm::dvec3 g = glm::cross(e1, e2);
    const double gl = glm::length(g);
    g = gl > 0.0 ? g / gl : glm::dvec3(0.0);
    const double w = glm::dot(g, (glm::dvec3(t.p[0]) + glm::dvec3(t.p[1]) + glm::dvec3(t.p[2])) / 3.0);
    if (ranges_.empty() || ranges_.back().material != t.material)
      ranges_.push_back({t.material, static_cast<GLint>(verts.size()), 0});
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
      verts.push_back(v);
    }
    ranges_.back().count += 3;
  }
  if (!vao_) glGenVertexArrays(1, &vao_);
  if (!vbo_) glGenBuffers(1, &vbo_);
  glBindVertexArray(vao_);
  glBindBuffer(GL_ARRAY_BUFFER, vbo_);
  glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(verts.size() * sizeof(gl_mesh_vertex)), verts.data(),
               GL_STATIC_DRAW);
  const long long vbo_bytes = static_cast<long long>(verts.size() * sizeof(gl_mesh_vertex));
  vplkit::gl::track_gpu_bytes(vbo_bytes - bytes_);
  bytes_ = vbo_bytes;
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
  glBindVertexArray(0);
  vplkit::gl::check_gl("vplrender: mesh upload");
}

}  // namespace vplrender
