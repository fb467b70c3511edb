// SPDX-License-Identifier: MIT
#pragma once
// The inputs most GL renderer tests start from, made the way the pipeline makes them: a scene
// prepared from `o`, its G-buffer and its DPRSM (tessellated for o.dprsm) rasterised on the
// pipeline's GL context, the CPU voxel grid, and the same buffers uploaded to the GPU: a frame that
// both backends take. The tests then run builders or estimators on it with both backends.
#include "cli/options.hpp"
#include "cli/render_options.hpp"
#include "cli/scene_setup.hpp"
#include "raster/gl_raster.hpp"
#include "raster/gpu_scene_buffers.hpp"
#include "raster/tessellate.hpp"
#include "raster/voxels.hpp"
#include "render/frame_buffers.hpp"
#include "render/pipeline.hpp"

#include <memory>
#include <string>
#include <utility>

namespace vplrender_test {

struct gl_fixture {
  vplrender::options o;
  vplrender::prepared_scene p;
  vplrender::frame_buffers b;  // CPU arrays and their GPU copies (b.gpu)
};

// Small test sizes: WxH pixels, DPRSM 2 x dprsm^2, voxels^3, 8 VPLs and 8 directions, no progress.
inline vplrender::options small_options(const std::string& scene, int width = 24, int height = 16, int dprsm = 16,
                                        int voxels = 32) {
  vplrender::options o;
  o.scene = scene;
  o.width = width;
  o.height = height;
  o.dprsm = dprsm;
  o.voxels = voxels;
  o.vpls = 8;
  o.dirs = 8;
  o.progress = vplrender::progress_mode::never;
  return o;
}

inline gl_fixture make_gl_fixture(const vplrender::options& o) {
  vplrender::pipeline_gl_context();
  vplrender::prepared_scene p = vplrender::prepare_scene(o);
  vplrender::gl_rasterizer raster(p.s);
  vplrender::gbuffer_data g = raster.render_gbuffer(p.s.cam, o.width, o.height);
  vplrender::tessellation_params tp;
  tp.max_angle = vplrender::tessellation_angle_for_resolution(o.dprsm);
  vplrender::dprsm_data d = raster.render_dprsm(vplrender::dprsm_light(p.s), o.dprsm, tp);
  vplrender::scene_voxels grid = vplrender::voxelize_cpu(p.s, o.voxels);
  auto gpu = std::make_shared<vplrender::gpu_scene_buffers>(vplrender::upload_scene_buffers(g, d, grid.view()));
  vplrender::frame_buffers b{vplrender::backend::gpu, "", std::move(g), std::move(d), std::move(grid), std::move(gpu), nullptr,
                            vplrender::exact_ray_frame{}, vplrender::frame_facts{}, nullptr};  // facts: counted from the arrays when needed (facts_of)
  return {o, std::move(p), std::move(b)};
}

// The frame as vplrender's pipeline prepares it from `o` (prepare_buffers: on the GPU backend a
// frame without host copies, with its exact rays when o asks for them).
inline gl_fixture make_pipeline_fixture(const vplrender::options& o) {
  vplrender::pipeline_gl_context();
  vplrender::prepared_scene p = vplrender::prepare_scene(o);
  vplrender::stage_timer t;
  nlohmann::json det;
  vplrender::frame_buffers b = vplrender::prepare_buffers(o, p, t, det);
  return {o, std::move(p), std::move(b)};
}

}  // namespace vplrender_test
