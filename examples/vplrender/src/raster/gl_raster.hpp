// SPDX-License-Identifier: MIT
#pragma once
// The GPU rasterisation stages on a headless OpenGL 4.3+ context (vplkit::gl::headless_context
// must be current): the camera G-buffer and the two paraboloid maps of the DPRSM, rendered into
// float render targets, then either read back into CPU arrays (the CPU backend, the tests) or
// copied on the GPU into the surfel buffers the GPU backend's kernels read (nothing comes back).
// See docs/renderer.md for the projection, the clipping at the paraboloid rim and the
// tessellation rule; the passes' shaders are examples/vplrender/shaders/gbuffer.{vert,frag} and
// dprsm.{vert,frag}, the vertex array raster/gl_mesh.hpp, the targets raster/gl_target.hpp. The
// render targets are kept from one call to the next (frames of one size reuse them).
#include "raster/render_data.hpp"
#include "raster/tessellate.hpp"
#include "scene/scene.hpp"

#include <headless_gl/compute.hpp>

#include <memory>
#include <string>

namespace vplrender {

struct raster_timing {
  double ms = 0.0;           // GPU time of the draws, and of the copy into the surfels (timer query;
                             // glFinish + wall on llvmpipe)
  std::string clock = "gpu";
  double readback_ms = 0.0;  // wall time of reading the targets back into the CPU arrays (0 for surfels)
  double tessellation_ms = 0.0;  // DPRSM: wall time of tessellating for the light and uploading the mesh
                                 // (with a split ahead: of waiting for it and uploading)
  double split_ahead_ms = -1.0;  // DPRSM: the split ahead's own wall time, beside the caller (< 0: none)
};

class gl_rasterizer {
public:
  // Uploads the scene's textures and meshes. Throws vplkit::gl::gl_error when a shader cannot be
  // read or does not compile.
  explicit gl_rasterizer(const scene& s);
  ~gl_rasterizer();
  gl_rasterizer(const gl_rasterizer&) = delete;
  gl_rasterizer& operator=(const gl_rasterizer&) = delete;

  gbuffer_data render_gbuffer(const camera& cam, int width, int height, raster_timing* t = nullptr);

  // tess.max_angle <= 0: the triangles as they are (for the error measurement).
  dprsm_data render_dprsm(const vplkit::point_light<float>& light, int R, const tessellation_params& tess,
                          raster_timing* t = nullptr, tessellation_stats* ts = nullptr);

  // The same G-buffer and DPRSM written on the GPU into `surfels` (at least W H, resp. 2 R^2
  // surfels: raster/gpu_scene_buffers.hpp's layout), bit for bit what upload_surfels makes of
  // render_gbuffer's and render_dprsm's arrays; nothing is read back. The shader is
  // examples/vplrender/shaders/surfels_from_targets.comp.
  void render_gbuffer_surfels(const camera& cam, int width, int height, const vplkit::gl::buffer& surfels,
                              raster_timing* t = nullptr);
  void render_dprsm_surfels(const vplkit::point_light<float>& light, int R, const tessellation_params& tess,
                            const vplkit::gl::buffer& surfels, raster_timing* t = nullptr,
                            tessellation_stats* ts = nullptr);

  // Starts the DPRSM split for the light at `light` on other threads (raster/dprsm_mesh.hpp): the
  // next render_dprsm(_surfels) for that light and `tess` only waits for it and uploads. For a
  // frame loop that knows its next light, to call once this frame's DPRSM is drawn.
  void split_dprsm_ahead(const vplkit::point_light<float>& light, const tessellation_params& tess);

  struct impl;

private:
  std::unique_ptr<impl> impl_;
};

}  // namespace vplrender
