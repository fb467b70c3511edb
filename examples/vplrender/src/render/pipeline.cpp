#include "render/pipeline.hpp"

#include "io/errors.hpp"
#include "raster/gl_raster.hpp"
#include "raster/tessellate.hpp"
#include "raster/voxels.hpp"
#include "raster/voxels_gpu.hpp"
#include "render/gpu/gpu_backend.hpp"

#include <headless_gl/compute.hpp>
#include <headless_gl/context.hpp>

#include <vplkit/core/error.hpp>

#include <memory>
#include <stdexcept>

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

pipeline_buffers prepare_buffers(const options& o, const prepared_scene& p, stage_timer& timer, nlohmann::json& det) {
  const scene& s = p.s;

  vplkit::gl::headless_context* gl = nullptr;
  {
    auto t = timer.scoped("gl context");
    gl = &pipeline_gl_context();
  }
  std::string gl_renderer = gl->describe();

  gbuffer_data gbuf;
  dprsm_data dprsm;
  {
    gl_rasterizer raster(s);
    raster_timing tg;
    gbuf = raster.render_gbuffer(s.cam, o.width, o.height, &tg);
    timer.add("gbuffer (gpu)", tg.ms, tg.clock);
    tessellation_params tp;
    tp.max_angle = tessellation_angle_for_resolution(o.dprsm);
    tessellation_stats ts;
    raster_timing td;
    dprsm = raster.render_dprsm(dprsm_light(s), o.dprsm, tp, &td, &ts);
    timer.add("dprsm (gpu)", td.ms, td.clock);
    det["gbuffer"] = {{"valid_pixels", gbuf.valid_count()}};
    det["dprsm"] = {{"resolution", o.dprsm},
                    {"front_axis", {0, -1, 0}},
                    {"tessellation_max_angle_deg", tp.max_angle * 180.0 / 3.14159265358979323846},
                    {"triangles_in", ts.input},
                    {"triangles_out", ts.output},
                    {"triangles_capped", ts.capped}};
  }

  // --backend gpu: the pack's voxelize.comp (equal to the CPU grid on the built-in scenes, see
  // renderer_gl_pipeline_test); --backend cpu: vplkit::voxelize.
  const bool gpu_voxels = o.back == backend::gpu;
  vplkit::voxel_grid<float> grid = [&] {
    if (gpu_voxels) {
      double ms = 0.0;
      vplkit::voxel_grid<float> g = voxelize_gpu(s, o.voxels, &ms);
      timer.add("voxelize (gpu)", ms, "gpu");
      return g;
    }
    auto t = timer.scoped("voxelize (cpu)");
    return voxelize_cpu(s, o.voxels);
  }();
  det["voxels"] = {{"resolution", o.voxels},
                   {"occupied", grid.count()},
                   {"bounds_min", {grid.bounds_min().x, grid.bounds_min().y, grid.bounds_min().z}},
                   {"bounds_max", {grid.bounds_max().x, grid.bounds_max().y, grid.bounds_max().z}},
                   {"builder", gpu_voxels ? "gpu (voxelize.comp)" : "cpu (vplkit::voxelize)"}};
  return pipeline_buffers{std::move(gl_renderer), std::move(gbuf), std::move(dprsm), std::move(grid)};
}

cpu_render_result run_estimator(const options& o, const prepared_scene& p, const pipeline_buffers& b,
                                stage_timer& timer, const progress_fn& progress, nlohmann::json& det) {
  const estimator_settings es = make_estimator_settings(o, p.s);
  // --backend gpu: the estimator as a compute shader (gpu_backend.cpp) where this build has one;
  // --backend cpu, or a method without a kernel: the C++ templates (cpu_backend.cpp).
  const bool gpu_estimator = o.back == backend::gpu && gpu_estimator_available(es.meth);
  // GPU memory of this estimator alone: the peak restarts from what is live now (the prepare
  // stages' GL objects are gone by then; their peak is kept as gpu_peak_bytes_prepare).
  const vplkit::gl::gpu_memory before = vplkit::gl::gpu_memory_usage();
  vplkit::gl::reset_gpu_memory_peak();
  cpu_render_result cr;
  try {
    cr = gpu_estimator ? render_gpu(b.gbuf, b.dprsm, b.grid.view(), es, timer, progress)
                       : render_cpu(b.gbuf, b.dprsm, b.grid.view(), es, timer, progress);
  } catch (const vplkit::invalid_input& e) {
    throw input_error(e.what());
  }
  det["estimator"] = cr.details;
  det["estimator_backend"] = gpu_estimator ? "gpu" : "cpu";
  const vplkit::gl::gpu_memory after = vplkit::gl::gpu_memory_usage();
  det["memory"] = {{"gpu_peak_bytes_prepare", before.peak_bytes},
                   {"gpu_live_bytes_before_estimator", before.live_bytes},
                   {"gpu_peak_bytes_estimator", after.peak_bytes - before.live_bytes}};
  det["builders_backend"] = gpu_estimator && gpu_builder_available(es.meth) ? "gpu" : "cpu";
  return cr;
}

pipeline_result run_pipeline(const options& o, const prepared_scene& p, stage_timer& timer, const progress_fn& progress) {
  pipeline_result r;
  const pipeline_buffers b = prepare_buffers(o, p, timer, r.details);
  r.gl_renderer = b.gl_renderer;
  r.image = std::move(run_estimator(o, p, b, timer, progress, r.details).image);
  return r;
}

}  // namespace vplrender
