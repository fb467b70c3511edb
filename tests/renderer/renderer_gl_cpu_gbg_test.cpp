// SPDX-License-Identifier: MIT
// The CPU backend's GBG weights (build_gbg_weights_cpu: rows handed to worker threads, each
// accumulating into its own vplkit::gbg_partial, merged by vplkit::gbg_merge) against the library's
// serial vplkit::build_gbg_weights on the same G-buffer, DPRSM and voxel grid. One worker merges
// one partial into +0, so its weights are the serial build's bit for bit; more workers only change
// which double partial sums are added together, which moves a float weight by at most an ulp or so.
#include "renderer_gl_fixture.hpp"

#include "render/cpu/cpu_builders.hpp"

#include <vplkit/builders/gbg_weights.hpp>
#include <vplkit/visibility/visibility_callables.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>

using namespace vplrender;

TEST_CASE("the CPU backend's threaded GBG build equals vplkit::build_gbg_weights") {
  for (const char* scene_name : {"cornell", "open"}) {
    options o = vplrender_test::small_options(scene_name);
    o.meth = method::gbg;
    o.dirs = 32;
    const vplrender_test::gl_fixture f = vplrender_test::make_gl_fixture(o);
    render_settings s = make_render_settings(f.o, f.p.s);
    vplkit::gbg_params<float> params;
    params.n_dirs = s.dirs;
    params.dmin = s.dmin;
    params.depth_tolerance = gathering_depth_tolerance(s, f.b.grid.occupancy().view());
    params.seed = builder_seed(s.seed, 2);
    vplkit::gbg_stats serial_stats;
    const std::vector<float> serial = vplkit::build_gbg_weights(
        f.b.gbuf.view(), f.b.dprsm.view(), vplkit::triangle_voxel_tracer<float>{f.b.grid.view()}, params, &serial_stats);
    for (int threads : {1, 2, 3}) {
      INFO(scene_name << ", " << threads << " thread(s)");
      s.threads = threads;
      stage_timer t;
      nlohmann::json det;
      const std::vector<float> w = build_gbg_weights_cpu(f.b, s, t, {}, det);
      REQUIRE(w.size() == serial.size());
      CHECK(det["gbg"]["gather_points"].get<int>() == serial_stats.gather_points);
      CHECK(det["gbg"]["rays"].get<long long>() == serial_stats.rays);
      CHECK(det["gbg"]["hits"].get<long long>() == serial_stats.hits);
      CHECK(det["gbg"]["lit_hits"].get<long long>() == serial_stats.lit_hits);
      CHECK(det["gbg"]["holes"].get<int>() == serial_stats.holes);
      CHECK(det["gbg"]["filled"].get<int>() == serial_stats.filled);
      CHECK(serial_stats.lit_hits > 0);
      if (threads == 1) {
        CHECK(std::memcmp(w.data(), serial.data(), w.size() * sizeof(float)) == 0);
      } else {
        double worst = 0.0;
        for (std::size_t i = 0; i < w.size(); ++i) {
          REQUIRE((w[i] == 0.0f) == (serial[i] == 0.0f));
          if (serial[i] != 0.0f) worst = std::max(worst, std::abs(double(w[i]) - serial[i]) / serial[i]);
        }
        CHECK(worst <= 2.5e-7);  // about two float ulps
      }
    }
  }
}
