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
//     from frame to frame (a frame after the first allocates nothing unless the mesh grows);
//   - split_ahead: a frame loop that knows the next light starts its split on other threads while
//     the GPU renders the current frame, and the next build only waits for it and uploads.
#include "raster/gl_mesh.hpp"
#include "raster/tessellate.hpp"
#include "scene/scene.hpp"

#include <future>
#include <vector>

namespace vplrender {

class dprsm_mesh {
public:
  explicit dprsm_mesh(const std::vector<triangle>& scene_triangles);
  ~dprsm_mesh();  // waits for a split started ahead
  dprsm_mesh(const dprsm_mesh&) = delete;
  dprsm_mesh& operator=(const dprsm_mesh&) = delete;

  // What build did: whether the split was the one started ahead, and that split's wall time on
  // its own threads (ms, beside the caller; 0 when it was not ahead).
  struct build_report {
    bool ahead = false;
    double ahead_ms = 0.0;
  };

  // Splits for the light at `light` (params.min_edge <= 0: the scene's, tessellation_min_edge) and
  // uploads; needs the GL context the first call ran in. Takes the split started ahead when it was
  // for this light and these parameters (then waits for it; rethrows what it threw), else splits
  // now (a split ahead for another light is waited for and dropped).
  build_report build(vec3 light, const tessellation_params& params, tessellation_stats* stats = nullptr);

  // Starts the split for `light` on other threads and returns (no GL: the upload waits for build).
  void split_ahead(vec3 light, const tessellation_params& params);

  const gl_mesh& mesh() const { return mesh_; }

private:
  struct split_set {
    std::vector<std::vector<triangle>> split;        // per chunk, storage kept
    std::vector<std::vector<gl_mesh_vertex>> verts;  // per chunk, storage kept
    std::vector<gl_mesh::range> ranges;
    tessellation_stats stats;
  };
  void split_into(split_set& out, vec3 light, const tessellation_params& params) const;
  void drop_ahead();

  std::vector<triangle> sorted_;  // the scene's triangles, stably sorted by material
  double min_edge_ = 0.0;
  split_set now_, ahead_;
  std::future<double> ahead_job_;  // the split ahead's wall ms
  vec3 ahead_light_{0.0f};
  tessellation_params ahead_params_;
  gl_mesh mesh_;
};

}  // namespace vplrender
