// SPDX-License-Identifier: MIT
#include "render/pipeline.hpp"

#include "app/lighting_check.hpp"
#include "io/errors.hpp"
#include "raster/gl_raster.hpp"
#include "raster/gpu_bvh.hpp"
#include "raster/gpu_scene_buffers.hpp"
#include "raster/tessellate.hpp"
#include "raster/voxels.hpp"
#include "raster/voxels_gpu.hpp"
#include "render/cpu/cpu_backend.hpp"
#include "render/light_range.hpp"
#include "render/cpu/ray_scene.hpp"
#include "render/gpu/gpu_allocating.hpp"
#include "render/gpu/gpu_backend.hpp"

#include <headless_gl/compute.hpp>

#include <vplkit/core/error.hpp>

#include <memory>
#include <stdexcept>
#include <utility>

namespace vplrender {

vplkit::gl::headless_context& pipeline_gl_context() {
  // Created on first use, kept for the life of the process (one context per process).
  static std::unique_ptr<vplkit::gl::headless_context> ctx;
  if (!ctx) {
    try {
      ctx = std::make_unique<vplkit::gl::headless_context>();
    } catch (const vplkit::gl::gl_error&) {
      throw;
    } catch (const std::runtime_error& e) {
      throw vplkit::gl::gl_error(e.what());
    }
  }
  return *ctx;
}

frame_buffers prepare_buffers(const scene& s, const frame_settings& f, stage_timer& timer, nlohmann::json& det) {
  vplkit::gl::headless_context* gl = nullptr;
  {
    auto t = timer.scoped("gl context");
    gl = &pipeline_gl_context();
  }
  std::string gl_renderer = gl->describe();

  gbuffer_data gbuf;
  dprsm_data dprsm;
  {
    auto gbuffer_running = stage_timer::running("gbuffer (gpu)");
    gl_rasterizer raster(s);
    raster_timing tg;
    gbuf = raster.render_gbuffer(s.cam, f.width, f.height, &tg);
    timer.add("gbuffer (gpu)", tg.ms, tg.clock);
    timer.add("gbuffer read-back (cpu)", tg.readback_ms, "cpu-wall");
    tessellation_params tp;
    tp.max_angle = tessellation_angle_for_resolution(f.dprsm);
    tessellation_stats ts;
    raster_timing td;
    {
      auto running = stage_timer::running("dprsm (gpu)");
      dprsm = raster.render_dprsm(dprsm_light(s), f.dprsm, tp, &td, &ts);
    }
    timer.add("dprsm (gpu)", td.ms, td.clock);
    timer.add("dprsm read-back (cpu)", td.readback_ms, "cpu-wall");
    // Pixels the light reaches directly (with or without --direct): a frame with none gets a
    // warning after the render (app/lighting_check.hpp).
    det["gbuffer"] = {{"valid_pixels", gbuf.valid_count()}, {"directly_lit_pixels", count_directly_lit_pixels(gbuf, dprsm)}};
    det["dprsm"] = {{"resolution", f.dprsm},
                    {"front_axis", {0, -1, 0}},
                    {"tessellation_max_angle_deg", tp.max_angle * 180.0 / 3.14159265358979323846},
                    {"triangles_in", ts.input},
                    {"triangles_out", ts.output},
                    {"triangles_capped", ts.capped}};
  }

  // --backend gpu: the pack's voxelize.comp and prefix_sum.comp (equal to the CPU grid on the
  // built-in scenes, see renderer_gl_pipeline_test); --backend cpu: vplkit::voxelize_triangles.
  const bool gpu = f.back == backend::gpu;
  auto scene_gpu = gpu ? std::make_shared<gpu_scene_buffers>() : nullptr;
  scene_voxels grid = [&] {
    if (gpu) {
      auto running = stage_timer::running("voxelize (gpu)");
      gpu_voxelization v = voxelize_gpu(s, f.voxels);
      timer.add("voxelize (gpu)", v.ms, "gpu");
      return std::move(v.grid);
    }
    auto t = timer.scoped("voxelize (cpu)");
    return voxelize_cpu(s, f.voxels);
  }();
  const vplkit::voxel_grid<float>& occupancy = grid.occupancy();
  det["voxels"] = {{"resolution", f.voxels},
                   {"occupied", occupancy.count()},
                   {"triangle_entries", grid.entries().size()},
                   {"longest_list", grid.max_entries_per_voxel()},
                   {"bytes", grid.memory_bytes()},
                   {"bounds_min", {occupancy.bounds_min().x, occupancy.bounds_min().y, occupancy.bounds_min().z}},
                   {"bounds_max", {occupancy.bounds_max().x, occupancy.bounds_max().y, occupancy.bounds_max().z}},
                   {"builder", gpu ? "gpu (voxelize.comp, prefix_sum.comp)" : "cpu (vplkit::voxelize_triangles)"}};
  // The GPU backend's scene buffers, once for every estimator run on this frame: the G-buffer and
  // the DPRSM packed as surfels, the voxel grid's words and lists, uploaded.
  if (gpu) {
    auto t = timer.scoped("scene upload (cpu)");
    scene_gpu->gbuffer = gpu_allocating(surfel_bytes(gbuf.position.size()), "the G-buffer surfels", [&] {
      return upload_surfels(gbuf.position, gbuf.normal, gbuf.albedo, &gbuf.shading_normal);
    });
    scene_gpu->dprsm = gpu_allocating(surfel_bytes(dprsm.position.size()), "the DPRSM surfels", [&] {
      return upload_surfels(dprsm.position, dprsm.normal, dprsm.albedo);
    });
    scene_gpu->voxels = gpu_allocating(4 * std::max<std::size_t>(occupancy.word_count(), 1), "the voxel words",
                                       [&] { return upload_voxel_words(occupancy.view()); });
    scene_gpu->voxel_triangles = gpu_allocating(triangle_voxels_bytes(grid.view()), "the voxel triangle lists",
                                                [&] { return upload_triangle_voxels(grid.view()); });
  }
  // Exact rays: Embree over the scene for the CPU backend (and the offsets both backends' exact
  // rays use) and, for the GPU backend, the pack's BVH built here and uploaded with the scene
  // buffers, with what --method exact needs to shade its hits (raster/gpu_scene_shading.hpp).
  std::shared_ptr<const ray_scene> rays;
  if (f.exact_rays) {
    {
      auto t = timer.scoped("embree scene (cpu)");
      rays = std::make_shared<const ray_scene>(s);
    }
    if (gpu) {
      auto t = timer.scoped("bvh build and upload (cpu)");
      scene_gpu->bvh = upload_scene_bvh(s);
      scene_gpu->shading = gpu_allocating(scene_shading_bytes(s), "the triangles' shading and the textures",
                                          [&] { return upload_scene_shading(s); });
    }
    det["exact_rays"] = {{"triangles", s.triangles.size()},
                         {"surface_offset", rays->surface_offset()},
                         {"bvh_nodes", gpu ? scene_gpu->bvh.node_count : 0u},
                         {"bvh_depth", gpu ? scene_gpu->bvh.depth : 0}};
  }
  det["scene_buffers"] = {
      {"on_gpu", gpu},
      {"gpu_bytes", gpu ? scene_gpu->gbuffer.size_bytes() + scene_gpu->dprsm.size_bytes() + scene_gpu->voxels.size_bytes() +
                              scene_gpu->voxel_triangles.size_bytes() +
                              scene_gpu->bvh.nodes.size_bytes() + scene_gpu->bvh.triangles.size_bytes() +
                              scene_gpu->shading.size_bytes()
                        : std::size_t(0)}};
  frame_buffers b{f.back, std::move(gl_renderer), std::move(gbuf), std::move(dprsm), std::move(grid), nullptr, nullptr};
  b.gpu = std::move(scene_gpu);
  b.rays = std::move(rays);
  return b;
}

render_result run_estimator(const frame_buffers& b, const render_settings& s, stage_timer& timer,
                            const progress_fn& progress, nlohmann::json& det) {
  const bool gpu = b.back == backend::gpu;
  // GPU memory of this estimator alone: the peak restarts from what is live now (the frame's scene
  // buffers; the prepare stages' peak is kept as gpu_peak_bytes_prepare).
  const vplkit::gl::gpu_memory before = vplkit::gl::gpu_memory_usage();
  vplkit::gl::reset_gpu_memory_peak();
  if (gpu && s.clamp_compensation == clamp_compensation_choice::on)
    throw input_error("clamp compensation: not on the GPU backend yet (use the CPU backend, or turn it off)");
  render_result r;
  try {
    r = gpu ? render_gpu(b, s, timer, progress) : render_cpu(b, s, timer, progress);
  } catch (const vplkit::invalid_input& e) {
    throw input_error(with_light_hint(e.what(), b.dprsm.light.intensity));
  }
  check_image_against_light(r.image, b.dprsm.light.intensity);
  r.details["clamp_compensation"] = to_string(uses_clamp_compensation(s) ? clamp_compensation_choice::on
                                                                         : clamp_compensation_choice::off);
  det["estimator"] = r.details;
  det["estimator_backend"] = to_string(b.back);
  const vplkit::gl::gpu_memory after = vplkit::gl::gpu_memory_usage();
  det["memory"] = {{"gpu_peak_bytes_prepare", before.peak_bytes},
                   {"gpu_live_bytes_before_estimator", before.live_bytes},
                   {"gpu_peak_bytes_estimator", after.peak_bytes - before.live_bytes}};
  det["builders_backend"] = gpu && has_distribution(s.meth) ? "gpu" : "cpu";
  return r;
}

pipeline_result run_pipeline(const scene& sc, const frame_settings& f, const render_settings& s, stage_timer& timer,
                             const progress_fn& progress) {
  pipeline_result r;
  const frame_buffers b = prepare_buffers(sc, f, timer, r.details);
  r.gl_renderer = b.gl_renderer;
  r.image = std::move(run_estimator(b, s, timer, progress, r.details).image);
  return r;
}

}  // namespace vplrender
