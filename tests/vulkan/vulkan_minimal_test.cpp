// SPDX-License-Identifier: MIT
// docs/glsl.md's minimal example on Vulkan: examples/glsl_minimal/pick_vpls.comp, compiled to
// SPIR-V at build time, picks 4096 VPLs from a CDF the C++ built; every pick must be the C++ pick
// (vplkit::discrete_cdf<float>::sample with the same counter RNG stream): exact, integer results.
#include "vulkan_test_support.hpp"

#include <vplkit/vplkit.hpp>

#include <cstdint>
#include <vector>

using namespace vplkit::vk_test;

TEST_CASE("pick_vpls.comp (the minimal example): every pick equals the C++ discrete_cdf pick") {
  std::vector<float> weights(1000);
  for (std::size_t i = 0; i < weights.size(); ++i) weights[i] = (i % 7 == 0) ? 0.0f : float(i % 13);
  const vplkit::discrete_cdf<float> cdf(weights);
  const std::uint32_t count = 4096;
  struct params {
    std::uint32_t n, guide_size;
    float total;
    std::uint32_t count;
  } p{std::uint32_t(cdf.size()), std::uint32_t(cdf.guide_size()), cdf.total(), count};

  with_vulkan([&](context& ctx) {
    // The shader's own bindings (pick_vpls.comp declares them: four storage buffers).
    const kernel k(ctx, "pick_vpls",
                   {{0, slot_kind::storage}, {1, slot_kind::storage}, {2, slot_kind::storage}, {3, slot_kind::storage}});
    const buffer cdf_buf = buffer::from_vector(ctx, cdf.cdf());
    const buffer guide_buf = buffer::from_vector(ctx, cdf.guide());
    const buffer picks = buffer(ctx, count * sizeof(std::uint32_t), 0xFF);
    const buffer params_buf = buffer::from_bytes(ctx, &p, sizeof p);
    run(ctx, k, {{0, &cdf_buf}, {1, &guide_buf}, {2, &picks}, {3, &params_buf}}, groups_for(count, 64));

    const std::vector<std::uint32_t> gpu = picks.read<std::uint32_t>();
    std::vector<std::uint32_t> cpu(count);
    for (std::uint32_t i = 0; i < count; ++i) {
      vplkit::counter_rng rng = vplkit::make_counter_rng(42u, i);
      cpu[i] = std::uint32_t(cdf.sample(vplkit::rng_next_float(rng)).index);
    }
    const std::ptrdiff_t first = first_difference(gpu, cpu);
    INFO("first differing pick: " << first);
    CHECK(first == -1);
    std::cout << "  " << count << " picks, GPU == CPU: " << (first == -1 ? "all" : "NOT all") << "\n";
  });
}
