// SPDX-License-Identifier: MIT
// The rendering pipeline end to end on headless GL (llvmpipe here): G-buffer, DPRSM against a CPU
// ray cast, the voxel grid, and every method on both built-in scenes at tiny sizes.
#include "cli/render_options.hpp"
#include "cli/scene_setup.hpp"
#include "raster/dprsm_check.hpp"
#include "raster/gl_raster.hpp"
#include "raster/voxels.hpp"
#include "raster/voxels_gpu.hpp"
#include "render/cpu/cpu_backend.hpp"
#include "render/gpu/gpu_backend.hpp"
#include "scene/builtin_scenes.hpp"
#include "scene/camera.hpp"
#include "scene/raycast.hpp"

#include <headless_gl/context.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <iostream>
#include <memory>

using namespace vplrender;

namespace {

// One context per process (each TEST_CASE runs in its own process under ctest, but a plain run of
// the program runs them all).
vplkit::gl::headless_context& gl_context() { return pipeline_gl_context(); }

options tiny(const std::string& scene_name, method m) {
  options o;
  o.scene = scene_name;
  o.meth = m;
  o.width = 32;
  o.height = 32;
  o.dprsm = 16;
  o.voxels = 32;
  o.vpls = 8;
  o.dirs = 8;
  o.progress = progress_mode::never;
  return o;
}

void check_image(const image_rgb& img, const std::string& what) {
  INFO(what);
  REQUIRE(img.width > 0);
  REQUIRE(img.rgb.size() == static_cast<std::size_t>(img.width * img.height * 3));
  REQUIRE_FALSE(find_non_finite(img).has_value());
  double sum = 0.0;
  for (float v : img.rgb) {
    REQUIRE(v >= 0.0f);
    sum += v;
  }
  CHECK(sum > 0.0);  // every method lights something in both scenes
}

}  // namespace

TEST_CASE("G-buffer matches primary ray casts") {
  gl_context();
  const prepared_scene p = prepare_scene(tiny("cornell", method::gbg));
  gl_rasterizer r(p.s);
  const int W = 40, H = 30;
  const gbuffer_data g = r.render_gbuffer(p.s.cam, W, H);
  REQUIRE(g.valid_count() == static_cast<std::size_t>(W * H));  // closed room: every pixel sees a wall
  const camera_frame f = make_camera_frame(p.s.cam);
  const double diag = bounds(p.s).diagonal();
  int far_off = 0;
  for (int y = 0; y < H; ++y)
    for (int x = 0; x < W; ++x) {
      const vec3 d = primary_ray_direction(f, W, H, x + 0.5f, y + 0.5f);
      const ray_hit h = cast_ray(p.s.triangles, glm::dvec3(p.s.cam.eye), glm::dvec3(d));
      REQUIRE(h.hit);
      const glm::dvec3 hp = glm::dvec3(p.s.cam.eye) + h.t * glm::dvec3(d);
      const std::size_t i = static_cast<std::size_t>(y * W + x);
      if (glm::length(hp - glm::dvec3(g.position[i])) > 1e-3 * diag) ++far_off;  // silhouettes only
      CHECK(std::abs(glm::length(g.normal[i]) - 1.0f) < 1e-4f);
      CHECK(glm::dot(g.normal[i], p.s.cam.eye - g.position[i]) > 0.0f);  // faces the camera
    }
  // Row order: row 0 is the top (the ceiling is white, y = 2; the camera's top row sees it).
  CHECK(g.position[0].y > 1.5f);
  CHECK(g.position[static_cast<std::size_t>((H - 1) * W)].y < 0.5f);
  std::cout << "G-buffer vs ray cast: " << far_off << " of " << W * H << " pixels differ by > 1e-3 diagonal\n";
  CHECK(far_off <= W * H / 50);
}

TEST_CASE("rasterised DPRSM agrees with a ray-cast DPRSM, tessellation reduces the error") {
  gl_context();
  for (const char* name : {"cornell", "open"}) {
    const prepared_scene p = prepare_scene(tiny(name, method::gbg));
    gl_rasterizer r(p.s);
    const int R = 64;
    const auto light = dprsm_light(p.s);
    const dprsm_data ref = raycast_dprsm(p.s, light, R);
    const double tol = 1e-3 * bounds(p.s).diagonal();
    tessellation_params none;
    tessellation_params tess;
    tess.max_angle = tessellation_angle_for_resolution(R);
    const dprsm_difference e0 = compare_dprsm(r.render_dprsm(light, R, none), ref, tol);
    tessellation_stats ts;
    const dprsm_data gpu = r.render_dprsm(light, R, tess, nullptr, &ts);
    const dprsm_difference e1 = compare_dprsm(gpu, ref, tol);
    std::cout << name << " R=" << R << ": texels differing (coverage + position > " << tol << "): untessellated "
              << e0.coverage_diff << "+" << e0.position_diff << " = " << 100.0 * e0.fraction() << "%, tessellated ("
              << ts.output << " triangles) " << e1.coverage_diff << "+" << e1.position_diff << " = "
              << 100.0 * e1.fraction() << "% of " << e1.valid_texels << "\n";
    CHECK(e1.fraction() < 0.005);  // measured: 0.25% (cornell), see docs/renderer.md
    CHECK(e1.fraction() <= e0.fraction());
    // Texels outside the unit disk never hold a surface.
    for (int i = 0; i < 2 * R * R; ++i) {
      const glm::ivec2 xy = vplkit::texel_coords(i, R);
      if (!vplkit::texel_is_valid(xy.x, xy.y, R)) REQUIRE(gpu.albedo[static_cast<std::size_t>(i)] == vec3(0.0f));
    }
    REQUIRE_NOTHROW(gpu.view().validate());
  }
}

TEST_CASE("every method renders finite, non-negative images on both built-in scenes") {
  gl_context();
  for (const char* name : {"cornell", "open"})
    for (method m : {method::reference, method::global, method::local, method::gbg, method::gather, method::mis,
                     method::mis_as_published}) {
      options o = tiny(name, m);
      const prepared_scene p = prepare_scene(o);
      stage_timer timer;
      const pipeline_result r = run_pipeline(o, p, timer);
      check_image(r.image, std::string(name) + " " + to_string(m));
      CHECK(r.gl_renderer.find("OpenGL") != std::string::npos);
      // --backend gpu (the default) runs the estimator as a compute shader where one exists.
      CHECK(r.details["estimator_backend"] == "gpu");
      bool has_gpu_stage = false, gpu_estimate = false;
      for (const stage_time& s : timer.stages()) {
        has_gpu_stage = has_gpu_stage || s.clock == "gpu";
        gpu_estimate = gpu_estimate || s.name == "estimate (gpu)";
      }
      CHECK(has_gpu_stage);
      CHECK(gpu_estimate);
    }
}

TEST_CASE("direct light adds a positive term and keeps images finite") {
  gl_context();
  options o = tiny("cornell", method::gather);
  const prepared_scene p = prepare_scene(o);
  stage_timer t1, t2;
  const pipeline_result a = run_pipeline(o, p, t1);
  o.direct = true;
  const pipeline_result b = run_pipeline(o, p, t2);
  check_image(b.image, "direct");
  double sa = 0.0, sb = 0.0;
  for (std::size_t i = 0; i < a.image.rgb.size(); ++i) {
    sa += a.image.rgb[i];
    sb += b.image.rgb[i];
    REQUIRE(b.image.rgb[i] >= a.image.rgb[i] - 1e-6f);  // same random numbers, plus direct light
  }
  CHECK(sb > 1.5 * sa);  // the room's direct light dominates its one-bounce light
}

TEST_CASE("a light outside the voxel grid (above the open scene) renders") {
  gl_context();
  options o = tiny("open", method::mis);
  light_option l;
  l.position = vec3(0.0f, 8.0f, 0.0f);  // above the back wall (y <= 4): outside the scene bounds
  o.light = l;
  const prepared_scene p = prepare_scene(o);
  REQUIRE(p.light_outside_bounds);
  const scene_voxels v = voxelize_cpu(p.s, 32);
  const vplkit::voxel_grid<float>& g = v.occupancy();
  CHECK_FALSE(vplkit::voxel_in_grid(g.resolution(), g.world_to_voxel(p.s.light.position)));
  for (method m : {method::gbg, method::mis, method::reference}) {
    o.meth = m;
    stage_timer t;
    check_image(run_pipeline(o, p, t).image, std::string("light outside, ") + to_string(m));
  }
}

TEST_CASE("same seed, same image, another seed, another image") {
  gl_context();
  options o = tiny("cornell", method::gbg);
  const prepared_scene p = prepare_scene(o);
  stage_timer t1, t2, t3;
  const image_rgb a = run_pipeline(o, p, t1).image;
  const image_rgb b = run_pipeline(o, p, t2).image;
  o.seed = 2;
  const image_rgb c = run_pipeline(o, p, t3).image;
  CHECK(a.rgb == b.rgb);
  CHECK(a.rgb != c.rgb);
}

TEST_CASE("voxel grid covers the scene and its walls") {
  const prepared_scene p = prepare_scene(tiny("cornell", method::gbg));
  const scene_voxels sv = voxelize_cpu(p.s, 32);
  const vplkit::voxel_grid<float>& g = sv.occupancy();
  // Every vertex lies in an occupied voxel.
  for (const triangle& t : p.s.triangles)
    for (const vec3& v : t.p) CHECK(g.test(g.world_to_voxel(v)));
  // The room's interior centre is free.
  CHECK_FALSE(g.test(g.world_to_voxel(vec3(0.0f, 1.5f, 1.5f))));
}

TEST_CASE("GPU voxelisation (voxelize.comp, prefix_sum.comp) equals the CPU grid on both built-in scenes") {
  gl_context();
  for (const char* name : {"cornell", "open"})
    for (int res : {32, 128}) {
      const prepared_scene p = prepare_scene(tiny(name, method::gbg));
      const scene_voxels cv = voxelize_cpu(p.s, res);
      const scene_voxels gv = voxelize_gpu(p.s, res).grid;
      const vplkit::voxel_grid<float>& c = cv.occupancy();
      const vplkit::voxel_grid<float>& g = gv.occupancy();
      std::size_t differ = 0;
      for (std::size_t i = 0; i < c.words().size(); ++i)
        differ += static_cast<std::size_t>(__builtin_popcount(c.words()[i] ^ g.words()[i]));
      // The lists: the same triangles per voxel (the GPU's order is the atomics').
      std::size_t lists_differ = 0;
      if (differ == 0)
        for (std::size_t r = 0; r + 1 < cv.offsets().size(); ++r) {
          std::vector<std::uint32_t> a(cv.entries().begin() + cv.offsets()[r], cv.entries().begin() + cv.offsets()[r + 1]);
          std::vector<std::uint32_t> b(gv.entries().begin() + gv.offsets()[r], gv.entries().begin() + gv.offsets()[r + 1]);
          std::sort(a.begin(), a.end());
          std::sort(b.begin(), b.end());
          lists_differ += a != b;
        }
      std::cout << name << " " << res << "^3: CPU " << c.count() << " voxels, GPU " << g.count() << ", differing "
                << differ << "; " << cv.entries().size() << " triangle entries, lists differing " << lists_differ
                << "\n";
      CHECK(differ == 0);
      CHECK(lists_differ == 0);
      CHECK(cv.entries().size() == gv.entries().size());
      CHECK(cv.rank() == gv.rank());
      CHECK(cv.offsets() == gv.offsets());
    }
}
