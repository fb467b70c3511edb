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

namespace {

using namespace vplkit::parity::dist;
using vplkit::parity::compare_exact;
using vplkit::parity::compare_floats;
using vplkit::parity::input;
using vplkit::parity::show;
using vplkit::parity::within_ulps;

struct gpu_mixture {
  gpu_desc learned, fallback;
  float effective_eps, fallback_scale, learned_scale;
};
static_assert(sizeof(gpu_mixture) == 44, "std430 vplkit_defensive_mixture");

}  // namespace

TEST_CASE("defensive_mixture.glsl: binary-search sampling returns the C++ index and pmf and the guided index") {
  const u32 n = 30000;
  const std::vector<float> learned_w = zero_run_weights(n, 2000, 71);
  std::vector<float> valid(n);
  test_rng g(72);
  for (float& v : valid) v = (g.next_u32() % 100u) < 78u ? 1.0f : 0.0f;
  const vplkit::discrete_cdf<float> learned(learned_w), fallback(valid), none;
  const vplkit::discrete_cdf<float> zeros(std::vector<float>(n, 0.0f));
  struct named_mixture {
    std::string name;
    vplkit::defensive_mixture<float> m;
  };
  std::vector<named_mixture> mixtures;
  for (float eps : {0.0f, 0.05f, 0.5f, 1.0f})
    mixtures.push_back({"eps = " + show(eps), vplkit::defensive_mixture<float>(learned, fallback, eps)});
  mixtures.push_back({"learned empty, eps = 0.1", vplkit::defensive_mixture<float>(zeros, fallback, 0.1f)});
  mixtures.push_back({"fallback default, eps = 0.1", vplkit::defensive_mixture<float>(learned, none, 0.1f)});
  mixtures.push_back({"both empty", vplkit::defensive_mixture<float>(zeros, none, 0.3f)});

  packed_cdfs packed;
  std::vector<gpu_mixture> gm;
  for (const auto& nm : mixtures) {
    const u32 l = packed.add(nm.m.learned());
    const u32 f = packed.add(nm.m.fallback());
    gm.push_back({packed.descs[l], packed.descs[f], nm.m.effective_eps(), nm.m.fallback_scale(),
                  nm.m.learned_scale()});
  }
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
  const std::string kernel = std::string(R"(
#include "vplkit/distribution/defensive_mixture.glsl"
)") + cdf_accessors() + R"(
struct Q { float u; uint d; };
struct R { uint index; float pmf; uint guided_index; uint pad; };
layout(std430, binding = 0) readonly buffer In { Q queries[]; };
layout(std430, binding = 1) writeonly buffer Out { R results[]; };
layout(std430, binding = 6) readonly buffer Mixtures { vplkit_defensive_mixture mixtures[]; };
void main() {
  uint k = gl_GlobalInvocationID.x;
  if (k >= VPLKIT_PARITY_COUNT) return;
  vplkit_defensive_mixture m = mixtures[queries[k].d];
  vplkit_discrete_sample s = vplkit_defensive_mixture_sample_binary_search(m, queries[k].u);
  vplkit_discrete_sample s_guided = vplkit_defensive_mixture_sample(m, queries[k].u);
  results[k] = R(s.index, s.pmf, s_guided.index, 0u);
})";
  vplkit::parity::kernel_call call;
  call.source = kernel;
  call.inputs = packed.inputs();
  call.inputs.push_back(input(0, q));
  call.inputs.push_back(input(6, gm));
  call.output_binding = 1;
  struct r4 {
    u32 index;
    float pmf;
    u32 guided_index, pad;
  };
  const auto gpu = vplkit::parity::run_compute<r4>(call, q.size());
  std::vector<u32> gi, ci, ggi, cgi;
  std::vector<float> gp, cp;
  for (std::size_t k = 0; k < q.size(); ++k) {
    const auto& m = mixtures[q[k].d].m;
    const auto s = m.sample_binary_search(q[k].u);
    const auto s_guided = m.sample(q[k].u);
    gi.push_back(gpu[k].index);
    ci.push_back(u32(s.index));
    gp.push_back(gpu[k].pmf);
    cp.push_back(s.pmf);
    ggi.push_back(gpu[k].guided_index);
    cgi.push_back(u32(s_guided.index));
  }
  auto describe = [&](std::size_t k) { return mixtures[q[k].d].name + ", u = " + show(q[k].u); };
  std::cout << "parity: " << q.size() << " binary-search mixture queries" << std::endl;
  VPLKIT_CHECK_PARITY(compare_exact(gi, ci, describe, "binary-search mixture index vs C++"));
  VPLKIT_CHECK_PARITY(compare_floats(gp, cp, within_ulps(1), describe, "binary-search mixture pmf vs C++"));
  // The two searches agree (C++ guided index as the reference, GPU binary index compared to it).
  VPLKIT_CHECK_PARITY(compare_exact(gi, cgi, describe, "GPU binary-search index vs C++ guided index"));
  VPLKIT_CHECK_PARITY(compare_exact(ggi, cgi, describe, "GPU guided index vs C++ guided index"));
}
