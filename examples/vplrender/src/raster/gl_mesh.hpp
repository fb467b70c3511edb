// SPDX-License-Identifier: MIT
#pragma once
// The scene's triangles in a GL vertex array, as both raster passes draw them (the layout that
// shaders/raster_inputs.glsl declares): one vertex per triangle corner with its position, shading
// normal, texcoord, and the plane of its triangle (unit geometric normal n and n . p, computed in
// double from the corners, the same at all three corners). The triangles are sorted by material
// (stable), so a pass draws one range per material. Needs the context that was current at the
// first upload; the vertex buffer's bytes are counted with vplkit::gl::track_gpu_bytes.
#include "scene/scene.hpp"

#include <epoxy/gl.h>

#include <cstdint>
#include <vector>

namespace vplrender {

struct gl_mesh_vertex {
  float p[3], n[3], uv[2], plane[4];
};

// The three vertices of t (its plane computed in double from the corners).
void mesh_vertices(const triangle& t, gl_mesh_vertex out[3]);

class gl_mesh {
public:
  // The vertices [first, first + count) of one material.
  struct range {
    std::uint32_t material;
    GLint first;
    GLsizei count;
  };

  gl_mesh() = default;
  ~gl_mesh();
  gl_mesh(const gl_mesh&) = delete;
  gl_mesh& operator=(const gl_mesh&) = delete;

  // Replaces the mesh's contents with `triangles` (the vertex array and buffer objects are kept).
  void upload(const std::vector<triangle>& triangles);

  // Replaces the mesh's contents with the concatenation of `parts` (mesh_vertices of triangles
  // already in material order), drawn as `ranges` (which must cover it). The buffer's storage is
  // kept while it is large enough (a moving light's mesh changes size a little from frame to
  // frame) and grows by a quarter beyond the need when it is not; each part is copied once.
  void upload_vertices(const std::vector<std::vector<gl_mesh_vertex>>& parts, std::vector<range> ranges);

  GLuint vertex_array() const { return vao_; }
  const std::vector<range>& ranges() const { return ranges_; }

private:
  void ensure_storage(long long bytes, long long headroom);  // the vertex array's layout on first use
  GLuint vao_ = 0, vbo_ = 0;
  long long bytes_ = 0;  // the vertex buffer's storage
  std::vector<range> ranges_;
};

}  // namespace vplrender
