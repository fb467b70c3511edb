// SPDX-License-Identifier: MIT
#include "render/pipeline.hpp"

#include "io/errors.hpp"
#include "raster/gl_raster.hpp"
#include "raster/gpu_bvh.hpp"
#include "raster/gpu_scene_buffers.hpp"
#include "raster/tessellate.hpp"
#include "raster/voxels.hpp"
#include "raster/voxels_gpu.hpp"
#include "render/frame_buffers.hpp"
#include "render/cpu/cpu_backend.hpp"
#include "render/light_range.hpp"
#include "render/method_traits.hpp"
#include "render/cpu/ray_scene.hpp"
#include "render/gpu/gpu_allocating.hpp"
#include "render/gpu/gpu_backend.hpp"
#include "render/gpu/gpu_dprsm_planes.hpp"
#include "render/gpu/dprsm_view_uniforms.hpp"

#include <headless_gl/compute.hpp>

#include <vplkit/core/error.hpp>

#include <glm/geometric.hpp>
#include <glm/vec4.hpp>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <memory>
#include <optional>
#include <stdexcept>
#include <utility>
#include <vector>

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

namespace {

namespace gl = vplkit::gl;

#ifndef VPLRENDER_SHADER_DIR
#error "VPLRENDER_SHADER_DIR must name examples/vplrender/shaders (set by core.cmake)"
#endif

// shaders/frame_facts.comp over a GPU frame's surfels: four uints, read back (16 bytes).
frame_facts gpu_frame_facts(const gpu_scene_buffers& scene, const gbuffer_data& g, const dprsm_data& d) {
  const std::uint32_t start[4] = {0u, 0u, 0u, 0x7F800000u};  // the distance starts at +Inf
  gl::buffer facts = gl::buffer::from_bytes(start, sizeof start);
  const gl::program& prog = gl::cached_kernel(std::string(VPLRENDER_SHADER_DIR) + "/frame_facts.comp");
  set_dprsm_view_uniforms(prog, d.resolution, d.light);
  glUniform1i(prog.uniform_location("u_pixels"), g.width * g.height);
  gl::check_gl("frame_facts.comp uniforms");
  scene.gbuffer.bind(0);
  scene.dprsm.bind(1);
  facts.bind(2);
  const std::size_t n = std::max(static_cast<std::size_t>(g.width) * static_cast<std::size_t>(g.height),
                                 2 * static_cast<std::size_t>(d.resolution) * static_cast<std::size_t>(d.resolution));
  gl::dispatch_linear(prog, gl::groups_for(n, 64));
  std::uint32_t c[4];
  facts.read_bytes(c, 0, sizeof c);
  frame_facts f;
  f.known = true;
  f.valid_pixels = c[0];
  f.gather_points = c[1];
  f.directly_lit_pixels = c[2];
  std::memcpy(&f.nearest_lit_distance, &c[3], sizeof(float));
  return f;
}

}  // namespace

struct frame_pipeline::impl {
  const scene* s = nullptr;
  frame_settings f;
  std::unique_ptr<gl_rasterizer> raster;
  std::shared_ptr<gpu_scene_buffers> scene_gpu;  // the GPU backend's buffers (also frame->gpu)
  std::optional<frame_buffers> frame;             // made once the voxel grid exists
  tessellation_params tp;
};

frame_pipeline::frame_pipeline(const scene& s, const frame_settings& f, stage_timer& timer, nlohmann::json& det)
    : impl_(std::make_unique<impl>()) {
  impl& d = *impl_;
  d.s = &s;
  d.f = f;
  d.tp.max_angle = tessellation_angle_for_resolution(f.dprsm);
  vplkit::gl::headless_context* glc = nullptr;
  {
    auto t = timer.scoped("gl context");
    glc = &pipeline_gl_context();
  }
  {
    auto t = timer.scoped("raster setup (cpu)");
    d.raster = std::make_unique<gl_rasterizer>(s);
  }
  // --backend gpu: the pack's voxelize.comp and prefix_sum.comp (equal to the CPU grid on the
  // built-in scenes, see renderer_gl_pipeline_test); --backend cpu: vplkit::voxelize_triangles.
  const bool gpu = f.back == backend::gpu;
  scene_voxels voxel_grid = [&] {
    if (gpu) {
      auto running = stage_timer::running("voxelize (gpu)");
      gpu_voxelization v = voxelize_gpu(s, f.voxels);
      timer.add("voxelize (gpu)", v.ms, "gpu");
      return std::move(v.grid);
    }
    auto t = timer.scoped("voxelize (cpu)");
    return voxelize_cpu(s, f.voxels);
  }();
  d.frame.emplace(frame_buffers{f.back, glc->describe(), gbuffer_data{}, dprsm_data{}, std::move(voxel_grid), nullptr,
                                nullptr, exact_ray_frame{}, frame_facts{}, nullptr});
  if (!gpu) d.frame->corners = std::make_shared<const voxel_corners>(make_voxel_corners(s));
  const scene_voxels& grid = d.frame->grid;
  const vplkit::voxel_grid<float>& occupancy = grid.occupancy();
  det["voxels"] = {{"resolution", f.voxels},
                   {"occupied", occupancy.count()},
                   {"triangle_entries", grid.entries().size()},
                   {"longest_list", grid.max_entries_per_voxel()},
                   {"bytes", grid.memory_bytes()},
                   {"bounds_min", {occupancy.bounds_min().x, occupancy.bounds_min().y, occupancy.bounds_min().z}},
                   {"bounds_max", {occupancy.bounds_max().x, occupancy.bounds_max().y, occupancy.bounds_max().z}},
                   {"builder", gpu ? "gpu (voxelize.comp, prefix_sum.comp)" : "cpu (vplkit::voxelize_triangles)"}};
  // The GPU backend's scene buffers, once for every frame and estimator run: the voxel grid's
  // words and lists uploaded, and the G-buffer and DPRSM surfels the rasteriser writes each frame.
  if (gpu) {
    d.scene_gpu = std::make_shared<gpu_scene_buffers>();
    gpu_scene_buffers& g = *d.scene_gpu;
    auto t = timer.scoped("scene upload (cpu)");
    const std::size_t pixels = static_cast<std::size_t>(f.width) * static_cast<std::size_t>(f.height);
    const std::size_t texels = 2 * static_cast<std::size_t>(f.dprsm) * static_cast<std::size_t>(f.dprsm);
    g.gbuffer = gpu_allocating(surfel_bytes(pixels), "the G-buffer surfels",
                               [&] { return gl::buffer::filled(surfel_bytes(pixels), 0); });
    g.dprsm = gpu_allocating(surfel_bytes(texels), "the DPRSM surfels",
                             [&] { return gl::buffer::filled(surfel_bytes(texels), 0); });
    g.voxels = gpu_allocating(4 * std::max<std::size_t>(occupancy.word_count(), 1), "the voxel words",
                              [&] { return upload_voxel_words(occupancy.view()); });
    g.voxel_triangles = gpu_allocating(triangle_voxels_bytes(grid.view()), "the voxel triangle lists",
                                       [&] { return upload_triangle_voxels(grid.view()); });
  }
  // Exact rays: Embree over the scene for the CPU backend (and the offsets both backends' exact
  // rays use) and, for the GPU backend, the pack's BVH built here and uploaded with the scene
  // buffers, with what --method exact needs to shade its hits (raster/gpu_scene_shading.hpp).
  if (f.exact_rays) {
    {
      auto t = timer.scoped("embree scene (cpu)");
      d.frame->rays = std::make_shared<const ray_scene>(s);
      d.frame->ray_frame = {d.frame->rays->surface_offset()};
    }
    if (gpu) {
      auto t = timer.scoped("bvh build and upload (cpu)");
      d.scene_gpu->bvh = upload_scene_bvh(s);
      d.scene_gpu->shading = gpu_allocating(scene_shading_bytes(s), "the triangles' shading and the textures",
                                            [&] { return upload_scene_shading(s); });
    }
    det["exact_rays"] = {{"triangles", s.triangles.size()},
                         {"surface_offset", d.frame->rays->surface_offset()},
                         {"bvh_nodes", gpu ? d.scene_gpu->bvh.node_count : 0u},
                         {"bvh_depth", gpu ? d.scene_gpu->bvh.depth : 0}};
  }
  d.frame->gpu = d.scene_gpu;
}

frame_pipeline::~frame_pipeline() = default;

void frame_pipeline::split_ahead(const vplkit::point_light<float>& next_light) {
  if (impl_->scene_gpu) impl_->raster->split_dprsm_ahead(next_light, impl_->tp);
}

const frame_buffers& frame_pipeline::buffers() const { return *impl_->frame; }

frame_buffers frame_pipeline::release() { return std::move(*impl_->frame); }

const frame_buffers& frame_pipeline::render(const vplkit::point_light<float>& light, stage_timer& timer,
                                            nlohmann::json& det) {
  impl& d = *impl_;
  const scene& s = *d.s;
  const frame_settings& f = d.f;
  frame_buffers& b = *d.frame;
  tessellation_stats ts;
  raster_timing tg, td;
  if (d.scene_gpu) {
    // The G-buffer and the DPRSM stay on the GPU: the rasteriser writes the surfels.
    {
      auto running = stage_timer::running("gbuffer (gpu)");
      d.raster->render_gbuffer_surfels(s.cam, f.width, f.height, d.scene_gpu->gbuffer, &tg);
    }
    timer.add("gbuffer (gpu)", tg.ms, tg.clock);
    {
      auto running = stage_timer::running("dprsm (gpu)");
      d.raster->render_dprsm_surfels(light, f.dprsm, d.tp, d.scene_gpu->dprsm, &td, &ts);
    }
    timer.add("dprsm tessellation (cpu)", td.tessellation_ms, "cpu-wall");
    if (td.split_ahead_ms >= 0.0) timer.add("dprsm split ahead (cpu, beside the gpu)", td.split_ahead_ms, "cpu-wall-overlapped");
    timer.add("dprsm (gpu)", td.ms, td.clock);
    {
      // The DPRSM's plane records for this light, read by every estimator run of the frame.
      gl::timer_query tq;
      tq.begin();
      build_dprsm_planes_gpu(*d.scene_gpu, f.dprsm, light);
      tq.end();
      timer.add("dprsm planes (gpu)", tq.milliseconds(), "gpu");
    }
    b.gbuf = gbuffer_data{};
    b.gbuf.width = f.width;
    b.gbuf.height = f.height;
    b.dprsm = dprsm_data{};
    b.dprsm.resolution = f.dprsm;
    b.dprsm.light = light;
    auto t = timer.scoped("frame facts (gpu)");
    b.facts = gpu_frame_facts(*d.scene_gpu, b.gbuf, b.dprsm);
  } else {
    {
      auto running = stage_timer::running("gbuffer (gpu)");
      b.gbuf = d.raster->render_gbuffer(s.cam, f.width, f.height, &tg);
    }
    timer.add("gbuffer (gpu)", tg.ms, tg.clock);
    timer.add("gbuffer read-back (cpu)", tg.readback_ms, "cpu-wall");
    {
      auto running = stage_timer::running("dprsm (gpu)");
      b.dprsm = d.raster->render_dprsm(light, f.dprsm, d.tp, &td, &ts);
    }
    timer.add("dprsm tessellation (cpu)", td.tessellation_ms, "cpu-wall");
    timer.add("dprsm (gpu)", td.ms, td.clock);
    timer.add("dprsm read-back (cpu)", td.readback_ms, "cpu-wall");
    auto t = timer.scoped("frame facts (cpu)");
    b.facts = host_frame_facts(b.gbuf, b.dprsm);
  }
  // Pixels the light reaches directly (with or without --direct): a frame with none gets a
  // warning after the render (app/lighting_check.hpp).
  det["gbuffer"] = {{"valid_pixels", b.facts.valid_pixels}, {"directly_lit_pixels", b.facts.directly_lit_pixels}};
  det["dprsm"] = {{"resolution", f.dprsm},
                  {"front_axis", {0, -1, 0}},
                  {"tessellation_max_angle_deg", d.tp.max_angle * 180.0 / 3.14159265358979323846},
                  {"triangles_in", ts.input},
                  {"triangles_out", ts.output},
                  {"triangles_capped", ts.capped}};
  const gpu_scene_buffers* g = d.scene_gpu.get();
  det["scene_buffers"] = {
      {"on_gpu", g != nullptr},
      {"host_copies", b.has_host_copies()},
      {"gpu_bytes", g ? g->gbuffer.size_bytes() + g->dprsm.size_bytes() + g->dprsm_planes.records.size_bytes() +
                            g->voxels.size_bytes() +
                            g->voxel_triangles.size_bytes() + g->bvh.nodes.size_bytes() +
                            g->bvh.triangles.size_bytes() + g->shading.size_bytes()
                      : std::size_t(0)}};
  return b;
}

frame_buffers prepare_buffers(const scene& s, const frame_settings& f, stage_timer& timer, nlohmann::json& det) {
  frame_pipeline p(s, f, timer, det);
  p.render(dprsm_light(s), timer, det);
  return p.release();
}

void read_back_host_copies(frame_buffers& b) {
  if (b.has_host_copies()) return;
  if (!b.gpu) throw vplkit::invalid_input("read_back_host_copies: the frame has neither host arrays nor GPU buffers");
  b.gbuf = read_back_gbuffer(*b.gpu, b.gbuf.width, b.gbuf.height);
  b.dprsm = read_back_dprsm(*b.gpu, b.dprsm.resolution, b.dprsm.light);
}

render_result run_estimator(const frame_buffers& b, const render_settings& s, stage_timer& timer,
                            const progress_fn& progress, nlohmann::json& det) {
  const bool gpu = b.back == backend::gpu;
  if (gpu && !traits(s.meth).gpu)
    throw input_error(std::string("--method ") + to_string(s.meth) +
                      ": runs on --backend cpu only for now (its GPU kernels are not written yet)");
  // GPU memory of this estimator alone: the peak restarts from what is live now (the frame's scene
  // buffers; the prepare stages' peak is kept as gpu_peak_bytes_prepare).
  const vplkit::gl::gpu_memory before = vplkit::gl::gpu_memory_usage();
  vplkit::gl::reset_gpu_memory_peak();
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
