// SPDX-License-Identifier: MIT
#pragma once
// The DPRSM pass's mesh, rebuilt for every light position: the scene's triangles split for the
// paraboloid projection (tessellate_for_light's output, raster/tessellate.hpp) as the vertex array
// the pass draws. The same vertices, in the same order, as gl_mesh::upload(tessellate_on_all_cores(
// ...)) gives, built the way a frame loop needs it:
//   - the scene is put in material order once (stable), so the split output is in draw order as it
//     comes and needs no sort per frame;
//   - min_edge is fixed once from the scene, not per frame;
//   - each core splits its chunks and writes their vertices itself; the chunks go to the GPU
//     buffer as they are (no concatenated copy), and every host and GPU buffer keeps its storage
//     from frame to frame (a frame after the first allocates nothing unless the mesh grows).
#include "raster/gl_mesh.hpp"
#include "raster/tessellate.hpp"
#include "scene/scene.hpp"

#include <vector>

namespace vplrender {

class dprsm_mesh {
public:
  explicit dprsm_mesh(const std::vector<triangle>& scene_triangles);

  // Splits for the light at `light` (params.min_edge <= 0: the scene's, tessellation_min_edge) and
  // uploads; needs the GL context the first call ran in.
  void build(vec3 light, const tessellation_params& params, tessellation_stats* stats = nullptr);

  const gl_mesh& mesh() const { return mesh_; }

private:
  std::vector<triangle> sorted_;  // the scene's triangles, stably sorted by material
  double min_edge_ = 0.0;
  std::vector<std::vector<triangle>> split_;         // per chunk, storage kept
  std::vector<std::vector<gl_mesh_vertex>> verts_;   // per chunk, storage kept
  gl_mesh mesh_;
};

}  // namespace vplrender
