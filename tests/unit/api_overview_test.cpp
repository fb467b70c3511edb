// SPDX-License-Identifier: MIT
// The renderer loop shown in docs/api.md, compiled and run on the synthetic scene so that the
// page cannot drift from the headers.
#include <vplkit/vplkit.hpp>
#include <synthetic_scene.hpp>

#include <catch2/catch.hpp>

#include <cmath>

TEST_CASE("docs/api.md renderer loop compiles and gives finite, positive light", "[api]") {
  using namespace vplkit;
  const vplkit_test::synthetic_scene<float> scene;
  const auto gbuffer = scene.make_gbuffer(8, 8);
  const auto dprsm_data = scene.make_dprsm(32);
  const gbuffer_view<float> gb = gbuffer.view();
  const dprsm_view<float> dprsm = dprsm_data.view();
  const voxel_bounds<float> b = fit_voxel_bounds(scene.positions.data(), scene.positions.size());
  const triangle_voxel_grid<float> grid = voxelize_triangles(b.min, b.max, ivec3(32), scene.positions.data(),
                                                             scene.positions.size(), scene.indices.data(),
                                                             scene.indices.size());
  triangle_voxel_visibility<float> visible{grid.view()};
  triangle_voxel_tracer<float> trace{grid.view()};

  gbg_params<float> params;
  const float scene_diagonal = glm::length(b.max - b.min);
  const int R = dprsm.resolution;
  params.depth_tolerance = 3.0f * scene_diagonal / float(R);
  const std::vector<float> w = build_gbg_weights(gb, dprsm, trace, params);
  const defensive_mixture<float> dist = make_vpl_distribution(w, dprsm, 0.05f);

  const std::uint32_t seed = 7u;
  vec3<float> sum(0.0f);
  for (int pixel = 0; pixel < gb.pixel_count(); ++pixel) {
    counter_rng rng = make_counter_rng(seed, std::uint32_t(pixel));
    const vec3<float> L = estimate_vpl_sampling(gb.at(pixel), dprsm, dist, rng, 16, visible, 0.05f);
    REQUIRE(std::isfinite(L.x));
    REQUIRE(L.x >= 0.0f);
    sum += L;
  }
  REQUIRE(luminance(sum) > 0.0f);
}
