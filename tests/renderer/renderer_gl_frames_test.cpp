// SPDX-License-Identifier: MIT
// Frames (render/frames.hpp, render/pipeline.hpp frame_pipeline): a GPU frame keeps its G-buffer and
// DPRSM on the GPU and still gives what the read-back gave, bit for bit; frame k of `--frames N`
// is, bit for bit, the single render with the light at the path's position k, on both backends;
// the "frames" report has its fields.
#include "cli/options.hpp"
#include "cli/render_options.hpp"
#include "cli/scene_setup.hpp"
#include "raster/gpu_scene_buffers.hpp"
#include "render/frames.hpp"
#include "render/light_path.hpp"
#include "render/cpu/cpu_backend.hpp"
#include "render/pipeline.hpp"

#include <catch2/catch.hpp>

#include <glm/geometric.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <string>
#include <vector>

using namespace vplrender;

namespace {

options small(method m, backend b) {
  options o;
  o.scene = "cornell";
  o.meth = m;
  o.back = b;
  o.width = 32;
  o.height = 24;
  o.dprsm = 16;
  o.voxels = 16;
  o.vpls = 4;
  o.dirs = 4;
  o.progress = progress_mode::never;
  return o;
}

bool same_bits(const image_rgb& a, const image_rgb& b) {
  return a.width == b.width && a.height == b.height && a.rgb.size() == b.rgb.size() &&
         std::memcmp(a.rgb.data(), b.rgb.data(), a.rgb.size() * sizeof(float)) == 0;
}

bool same_bits(const std::vector<vec3>& a, const std::vector<vec3>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(vec3)) == 0;
}

// Frame k of run_frames against run_pipeline on the scene with its light moved to path.at(k).
void frames_equal_single_renders(method m, backend back) {
  pipeline_gl_context();
  const options o = small(m, back);
  const prepared_scene p = prepare_scene(o);
  const frame_settings f = make_frame_settings(o);
  render_settings rs = make_render_settings(o, p.s);
  rs.threads = 2;
  const light_path path = make_light_path(p.s, 3);
  std::map<int, image_rgb> frames;
  stage_timer setup;
  const frames_run run =
      run_frames(p.s, f, rs, path, setup, [&](int k, const image_rgb& img) { frames.emplace(k, img); });
  REQUIRE(frames.size() == 3);
  REQUIRE(run.frame_ms.size() == 3);
  CHECK(same_bits(run.last_image, frames.at(2)));
  for (int k = 0; k < 3; ++k) {
    scene moved = p.s;
    moved.light.position = path.at(k);
    stage_timer t;
    const pipeline_result single = run_pipeline(moved, f, rs, t);
    INFO(to_string(m) << " on " << to_string(back) << ", frame " << k);
    CHECK(same_bits(frames.at(k), single.image));
  }
  // The light moved: the frames differ.
  CHECK_FALSE(same_bits(frames.at(0), frames.at(1)));
}

}  // namespace

TEST_CASE("a GPU frame keeps the G-buffer and the DPRSM on the GPU, the bits of the read-back") {
  pipeline_gl_context();
  const prepared_scene p = prepare_scene(small(method::global, backend::gpu));
  stage_timer t;
  nlohmann::json dg, dc;
  frame_buffers g = prepare_buffers(p.s, make_frame_settings(small(method::global, backend::gpu)), t, dg);
  const frame_buffers c = prepare_buffers(p.s, make_frame_settings(small(method::global, backend::cpu)), t, dc);
  REQUIRE(g.gpu);
  CHECK_FALSE(g.has_host_copies());
  CHECK(dg["scene_buffers"]["host_copies"] == false);
  CHECK(dc["scene_buffers"]["host_copies"] == true);
  REQUIRE(c.has_host_copies());
  CHECK(g.gbuf.width == 32);
  CHECK(g.dprsm.resolution == 16);
  // The facts counted on the GPU are the host's.
  const frame_facts host = host_frame_facts(c.gbuf, c.dprsm);
  CHECK(g.facts.known);
  CHECK(g.facts.valid_pixels == host.valid_pixels);
  CHECK(g.facts.gather_points == host.gather_points);
  CHECK(g.facts.directly_lit_pixels == host.directly_lit_pixels);
  CHECK(g.facts.valid_pixels > 0);
  CHECK(g.facts.directly_lit_pixels > 0);
  CHECK(std::abs(g.facts.nearest_lit_distance - host.nearest_lit_distance) <= 1e-6f * host.nearest_lit_distance);
  CHECK(dg["gbuffer"] == dc["gbuffer"]);
  // Read back on demand: the surfels the rasteriser wrote on the GPU are the CPU backend's arrays.
  read_back_host_copies(g);
  REQUIRE(g.has_host_copies());
  CHECK(same_bits(g.gbuf.position, c.gbuf.position));
  CHECK(same_bits(g.gbuf.normal, c.gbuf.normal));
  CHECK(same_bits(g.gbuf.albedo, c.gbuf.albedo));
  CHECK(same_bits(g.gbuf.shading_normal, c.gbuf.shading_normal));
  CHECK(same_bits(g.dprsm.position, c.dprsm.position));
  CHECK(same_bits(g.dprsm.normal, c.dprsm.normal));
  CHECK(same_bits(g.dprsm.albedo, c.dprsm.albedo));
}

TEST_CASE("the CPU backend refuses a frame whose arrays are on the GPU only, and says so") {
  pipeline_gl_context();
  const options o = small(method::global, backend::gpu);
  const prepared_scene p = prepare_scene(o);
  stage_timer t;
  nlohmann::json det;
  const frame_buffers g = prepare_buffers(p.s, make_frame_settings(o), t, det);
  CHECK_THROWS_WITH(render_cpu(g, make_render_settings(o, p.s), t), Catch::Contains("on the GPU only"));
}

TEST_CASE("frame k equals the single render with the light at the path's position k: GPU, global") {
  frames_equal_single_renders(method::global, backend::gpu);
}

TEST_CASE("frame k equals the single render with the light at the path's position k: GPU, mis") {
  frames_equal_single_renders(method::mis, backend::gpu);
}

TEST_CASE("frame k equals the single render with the light at the path's position k: CPU, mis") {
  frames_equal_single_renders(method::mis, backend::cpu);
}

TEST_CASE("the light's path: a circle through the scene's light, frame 0 the light itself") {
  pipeline_gl_context();
  const prepared_scene p = prepare_scene(small(method::global, backend::gpu));
  const light_path path = make_light_path(p.s, 4);
  const float r = 0.05f * bounds(p.s).diagonal();
  CHECK(path.radius == Approx(r).epsilon(1e-6));
  CHECK(path.at(0) == p.s.light.position);
  const vec3 centre = p.s.light.position - vec3(path.radius, 0.0f, 0.0f);
  for (int k = 0; k < 4; ++k) {
    CHECK(path.at(k).y == p.s.light.position.y);
    CHECK(glm::length(path.at(k) - centre) == Approx(path.radius).epsilon(1e-5));
  }
  CHECK(path.at(2).x == Approx(p.s.light.position.x - 2.0f * path.radius).epsilon(1e-6));
}

TEST_CASE("the frames report: count, median, per-stage medians, the path and the image written") {
  pipeline_gl_context();
  const options o = small(method::global, backend::gpu);
  const prepared_scene p = prepare_scene(o);
  const light_path path = make_light_path(p.s, 2);
  stage_timer setup;
  const frames_run run = run_frames(p.s, make_frame_settings(o), make_render_settings(o, p.s), path, setup);
  const nlohmann::json j = frames_report(run, path);
  CHECK(j["count"] == 2);
  CHECK(j["median_ms"].get<double>() > 0.0);
  CHECK(j["min_ms"].get<double>() <= j["median_ms"].get<double>());
  CHECK(j["max_ms"].get<double>() >= j["median_ms"].get<double>());
  CHECK(j["warmup_frames"] == 1);
  std::vector<std::string> names;
  for (const auto& s : j["stages"]) {
    names.push_back(s["name"]);
    CHECK(s["median_ms"].get<double>() >= 0.0);
  }
  for (const char* want : {"gbuffer (gpu)", "dprsm (gpu)", "global weights (gpu)", "cdf (gpu)", "estimate (gpu)",
                           "read-back (cpu)"})
    CHECK(std::find(names.begin(), names.end(), want) != names.end());
  // A GPU frame reads nothing back but the image.
  CHECK(std::find(names.begin(), names.end(), "gbuffer read-back (cpu)") == names.end());
  CHECK(std::find(names.begin(), names.end(), "dprsm read-back (cpu)") == names.end());
  const vec3 last = path.at(1);
  CHECK(j["light_path"]["last_position"] == nlohmann::json::array({last.x, last.y, last.z}));
  CHECK(run.last_details["scene_buffers"]["host_copies"] == false);
  bool warm = false;
  for (const stage_time& s : setup.stages()) warm = warm || s.name == "warm-up frame";
  CHECK(warm);
}
