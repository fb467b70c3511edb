// SPDX-License-Identifier: MIT
// docs/glsl.md's minimal example on Vulkan, as the GL example runs it: the pack's cdf_build.comp
// builds the CDF of 1000 VPL weights (the passes cdf_build_pass_needed names, one command buffer),
// then examples/glsl_minimal/pick_vpls.comp (SPIR-V built at build time) picks 4096 VPLs from it
// where cdf_build.comp left it. Every pick must be the C++ pick (vplkit::discrete_cdf<float>::sample
// of the same weights, the same counter RNG stream) except at a tie: cdf_build.comp promises each
// cdf value equal to the C++ one or a float neighbour, so a pick may differ only where u is the C++
// cdf value between the two picks or one float below it.
#include "vulkan_test_support.hpp"

#include <vplkit/distribution/cdf_build_params.h>
#include <vplkit/vplkit.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

using namespace vplkit::vk_test;

TEST_CASE("pick_vpls.comp (the minimal example) after cdf_build.comp: every pick equals the C++ discrete_cdf pick") {
  std::vector<float> weights(1000);
  for (std::size_t i = 0; i < weights.size(); ++i) weights[i] = (i % 7 == 0) ? 0.0f : float(i % 13);
  const vplkit::discrete_cdf<float> cdf(weights);
  const std::uint32_t n = std::uint32_t(weights.size()), count = 4096;
  const std::size_t m = vplkit::discrete_guide_size(n);
  const std::uint32_t blocks = (n + VPLKIT_CDF_BUILD_BLOCK - 1) / VPLKIT_CDF_BUILD_BLOCK;

  with_vulkan([&](context& ctx) {
    INFO("the default cdf_build.comp accumulates in double: the device needs shaderFloat64");
    REQUIRE(ctx.has_float64());
    const kernel build(ctx, "cdf_build",
                       {{VPLKIT_CDF_BUILD_BINDING_WEIGHTS, slot_kind::storage},
                        {VPLKIT_CDF_BUILD_BINDING_CDF, slot_kind::storage},
                        {VPLKIT_CDF_BUILD_BINDING_GUIDE, slot_kind::storage},
                        {VPLKIT_CDF_BUILD_BINDING_BLOCKS, slot_kind::storage},
                        {VPLKIT_CDF_BUILD_BINDING_INFO, slot_kind::storage},
                        {VPLKIT_CDF_BUILD_BINDING_PARAMS, slot_kind::uniform}});
    // pick_vpls.comp's bindings: cdf_build.comp's cdf, guide and info, its picks and parameters.
    const kernel pick(ctx, "pick_vpls",
                      {{VPLKIT_CDF_BUILD_BINDING_CDF, slot_kind::storage},
                       {VPLKIT_CDF_BUILD_BINDING_GUIDE, slot_kind::storage},
                       {VPLKIT_CDF_BUILD_BINDING_INFO, slot_kind::storage},
                       {6, slot_kind::storage},
                       {7, slot_kind::uniform}});
    const buffer w = buffer::from_vector(ctx, weights);
    const buffer c(ctx, (n + 1) * sizeof(float), 0xFF);
    const buffer g(ctx, (m + 1) * sizeof(std::uint32_t), 0xFF);
    const buffer blk(ctx, blocks * sizeof(vplkit::gpu::cdf_build_block), 0xFF);
    const buffer info(ctx, sizeof(vplkit::gpu::cdf_build_info), 0xFF);
    const buffer picks(ctx, count * sizeof(std::uint32_t), 0xFF);
    const std::uint32_t pick_params[4] = {n, count, 0, 0};  // std140 { uint n; uint count; }
    const buffer pick_ub = buffer::from_bytes(ctx, pick_params, sizeof pick_params);
    std::vector<buffer> params;  // one parameter block per pass: one command buffer records them all
    params.reserve(6);
    std::vector<dispatch_step> steps;
    for (std::uint32_t pass = 1; pass <= 6; ++pass) {
      if (!vplkit::gpu::cdf_build_pass_needed(pass, n)) continue;
      vplkit::gpu::cdf_build_params p{};
      p.n = n;
      p.pass = pass;
      params.push_back(buffer::from_bytes(ctx, &p, sizeof p));
      steps.push_back({&build,
                       {{VPLKIT_CDF_BUILD_BINDING_WEIGHTS, &w}, {VPLKIT_CDF_BUILD_BINDING_CDF, &c},
                        {VPLKIT_CDF_BUILD_BINDING_GUIDE, &g}, {VPLKIT_CDF_BUILD_BINDING_BLOCKS, &blk},
                        {VPLKIT_CDF_BUILD_BINDING_INFO, &info}, {VPLKIT_CDF_BUILD_BINDING_PARAMS, &params.back()}},
                       pass == 2 || pass == 4 ? 1u : blocks});
    }
    CHECK(steps.size() == 3);  // passes 1, 3, 5 for n <= 2^20
    steps.push_back({&pick,
                     {{VPLKIT_CDF_BUILD_BINDING_CDF, &c}, {VPLKIT_CDF_BUILD_BINDING_GUIDE, &g},
                      {VPLKIT_CDF_BUILD_BINDING_INFO, &info}, {6, &picks}, {7, &pick_ub}},
                     groups_for(count, 64)});
    run(ctx, steps);

    const std::vector<std::uint32_t> gpu = picks.read<std::uint32_t>();
    std::uint32_t differ = 0, ties = 0;
    std::string first;  // the first pick that differs outside a tie
    for (std::uint32_t i = 0; i < count; ++i) {
      vplkit::counter_rng rng = vplkit::make_counter_rng(42u, i);
      const float u = vplkit::rng_next_float(rng);
      const std::size_t cpu = cdf.sample(u).index;
      if (gpu[i] == cpu) continue;
      const float edge = cdf.cdf()[std::max<std::size_t>(gpu[i], cpu)];
      if (gpu[i] < n && u <= edge && u >= std::nextafter(edge, 0.0f)) {
        ++ties;
      } else {
        if (differ++ == 0)
          first = "pick " + std::to_string(i) + ": u = " + show(u) + ", GPU " + std::to_string(gpu[i]) + ", C++ " +
                  std::to_string(cpu);
      }
    }
    INFO("first differing " << first);
    CHECK(differ == 0);
    std::cout << "  " << count << " picks from the GPU-built CDF, " << differ << " differ from the C++ (+ " << ties
              << " at a tie)\n";
  });
}
