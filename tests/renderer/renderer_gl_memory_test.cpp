// SPDX-License-Identifier: MIT
// GPU memory accounting (the results' memory table): vplkit::gl::track_gpu_bytes counts every SSBO of
// the `buffer` class and what the rasteriser allocates; run_estimator reports what a method's
// builders, CDFs and estimator held at their peak, per texel and per pixel, and nothing on the CPU
// backend.
#include "cli/render_options.hpp"
#include "cli/scene_setup.hpp"

#include <headless_gl/compute.hpp>

#include <catch2/catch.hpp>

#include <utility>

using namespace vplrender;

TEST_CASE("buffer allocations move the live and peak GPU byte counters") {
  pipeline_gl_context();
  const vplkit::gl::gpu_memory start = vplkit::gl::gpu_memory_usage();
  vplkit::gl::reset_gpu_memory_peak();
  {
    vplkit::gl::buffer a = vplkit::gl::buffer::filled(1000);
    vplkit::gl::buffer b = vplkit::gl::buffer::filled(24);
    CHECK(vplkit::gl::gpu_memory_usage().live_bytes == start.live_bytes + 1024);
    vplkit::gl::buffer c = std::move(a);  // a move transfers, it does not count twice
    CHECK(vplkit::gl::gpu_memory_usage().live_bytes == start.live_bytes + 1024);
    c = vplkit::gl::buffer::filled(0);  // an empty buffer keeps one word; the 1000 bytes are freed
    CHECK(vplkit::gl::gpu_memory_usage().live_bytes == start.live_bytes + 28);
  }
  const vplkit::gl::gpu_memory end = vplkit::gl::gpu_memory_usage();
  CHECK(end.live_bytes == start.live_bytes);
  CHECK(end.peak_bytes == start.live_bytes + 1024 + 4);  // a, b and c's one word, briefly together
  vplkit::gl::reset_gpu_memory_peak();
  CHECK(vplkit::gl::gpu_memory_usage().peak_bytes == end.live_bytes);
}

TEST_CASE("run_estimator reports the method's GPU memory and it scales with the DPRSM, not the samples") {
  pipeline_gl_context();
  bool split = false;  // the last GPU run split its samples over dispatches (llvmpipe's loop budget)
  const auto peak_for = [&split](backend back, method m, int dprsm, int vpls) {
    options o;
    o.scene = "cornell";
    o.back = back;
    o.meth = m;
    o.width = 24;
    o.height = 16;
    o.dprsm = dprsm;
    o.voxels = 16;
    o.vpls = vpls;
    o.dirs = 4;
    o.progress = progress_mode::never;
    const prepared_scene p = prepare_scene(o);
    stage_timer t;
    nlohmann::json det;
    const frame_buffers b = prepare_buffers(o, p, t, det);
    CHECK_FALSE(det.contains("memory"));  // prepare_buffers reports no estimator memory
    run_estimator(o, p, b, t, {}, det);
    REQUIRE(det.contains("memory"));
    // The G-buffer and DPRSM are rasterised on GL on both backends.
    CHECK(det["memory"]["gpu_peak_bytes_prepare"].get<long long>() > 0);
    split = back == backend::gpu && det["estimator"]["gpu"]["passes"].get<int>() > 1;
    return det["memory"]["gpu_peak_bytes_estimator"].get<long long>();
  };
  for (method m : {method::global, method::gbg, method::mis}) {
    INFO(to_string(m));
    const long long small = peak_for(backend::gpu, m, 16, 4);
    const long long big = peak_for(backend::gpu, m, 32, 4);
    const long long bigger = peak_for(backend::gpu, m, 64, 4);
    CHECK(small > 0);
    // The estimator's buffers are per pixel (fixed here), per texel (weights, CDFs, guides) and a few
    // fixed ones; the frame's scene buffers (G-buffer, DPRSM, voxels) were made before it and are
    // not counted. 4x the texels per step: the per-texel part dominates the growth (at least 3x the
    // previous step's; not exactly 4x, the CDF build's per-block arrays start at one block), and
    // stays within 64 bytes per texel plus 128 per pixel.
    CHECK(big > small);
    CHECK(bigger - big >= 3 * (big - small));
    CHECK(bigger <= 64LL * 2 * 64 * 64 + 128LL * 24 * 16);
    CHECK_FALSE(split);
    // The sample count changes no buffer size, except that a render split over dispatches keeps
    // each pixel's state in a buffer between them (48 bytes per pixel; where the loop budget
    // applies: llvmpipe, render/gpu/loop_budget.hpp). That buffer may overlap the peak of the
    // builders' temporaries (the share trees' sums are freed before the estimate): at most 48 bytes
    // per pixel more.
    const long long many = peak_for(backend::gpu, m, 16, 64);
    CHECK(many >= small);
    CHECK(many <= small + (split ? 48LL * 24 * 16 : 0));
    CHECK(peak_for(backend::cpu, m, 16, 4) == 0);
  }
}
