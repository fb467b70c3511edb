// SPDX-License-Identifier: MIT
// Parity of vplkit_defensive_mixture_sample_binary_search (glsl/vplkit/distribution/
// defensive_mixture.glsl) with defensive_mixture<float>::sample_binary_search, and of both with
// the guided sample(): the renderer's --cdf-search binary must draw exactly the indices of
// --cdf-search guide. Same arithmetic as the guided path (comparisons, *, - and the pmf of the
// mixture), so indices are exact and the pmf is the C++ bits (checked within 1 ulp, as the guided
// parity test does).
#include <parity_distribution_support.hpp>

#include <vplkit/distribution/defensive_mixture.hpp>
#include <vplkit/distribution/discrete_cdf.hpp>

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

using namespace vplkit::parity;
using namespace vplkit::parity::dist;

TEST_CASE("defensive_mixture.glsl: binary-search sampling returns the C++ index and pmf and the guided index") {
  const u32 n = 30000;
  splitmix_rng g(72);
  const auto mixtures = test_mixtures(n, 71, g, {0.0f, 0.05f, 0.5f, 1.0f});
  packed_cdfs packed;
  const std::vector<gpu_mixture> gm = packed.add_each(mixtures, &named_mixture::m);
  struct q2 {
    float u;
    u32 d;
  };
  std::vector<q2> q;
  const float u_max = 0x1.fffffep-1f;
  for (u32 d = 0; d < mixtures.size(); ++d) {
    const float e = mixtures[d].m.effective_eps();
    for (int k = 0; k < 40000; ++k) q.push_back({g.grid_float(), d});
    for (int k = 0; k < 4000; ++k) q.push_back({g.any_unit_float(), d});
    for (float u : {e, std::nextafter(e, 0.0f), std::nextafter(e, 1.0f), 0.0f, u_max, 1.0f, -1.0f,
                    std::numeric_limits<float>::quiet_NaN()})
      q.push_back({u, d});
  }
  kernel_call call = cdf_kernel(packed, "vplkit/distribution/defensive_mixture.glsl", R"(
struct Q { float u; uint d; };
struct R { uint index; float pmf; uint guided_index; uint pad; };
)",
                                {input(0, q, "Q queries"), input(6, gm, "vplkit_defensive_mixture mixtures")}, "R results", R"(
  vplkit_defensive_mixture m = mixtures[queries[i].d];
  vplkit_discrete_sample s = vplkit_defensive_mixture_sample_binary_search(m, queries[i].u);
  vplkit_discrete_sample s_guided = vplkit_defensive_mixture_sample(m, queries[i].u);
  results[i] = R(s.index, s.pmf, s_guided.index, 0u);)");
  struct r4 {
    u32 index;
    float pmf;
    u32 guided_index, pad;
  };
  const auto gpu = run_compute<r4>(call, q.size());
  series<u32> binary, binary_vs_guided, guided;
  series<float> pmf;
  for (std::size_t k = 0; k < q.size(); ++k) {
    const auto& m = mixtures[q[k].d].m;
    const auto s = m.sample_binary_search(q[k].u);
    const auto s_guided = m.sample(q[k].u);
    binary.add(gpu[k].index, s.index);
    pmf.add(gpu[k].pmf, s.pmf);
    binary_vs_guided.add(gpu[k].index, s_guided.index);
    guided.add(gpu[k].guided_index, s_guided.index);
  }
  auto describe = [&](std::size_t k) { return mixtures[q[k].d].name + ", u = " + show(q[k].u); };
  std::cout << "parity: " << q.size() << " binary-search mixture queries" << std::endl;
  VPLKIT_CHECK_PARITY(compare_exact(binary, describe, "binary-search mixture index vs C++"));
  VPLKIT_CHECK_PARITY(compare_floats(pmf, within_ulps(1), describe, "binary-search mixture pmf vs C++"));
  // The two searches agree (C++ guided index as the reference, GPU binary index compared to it).
  VPLKIT_CHECK_PARITY(compare_exact(binary_vs_guided, describe, "GPU binary-search index vs C++ guided index"));
  VPLKIT_CHECK_PARITY(compare_exact(guided, describe, "GPU guided index vs C++ guided index"));
}
