// SPDX-License-Identifier: MIT
// The CPU backend's distribution builders make the flux weights and the defensive mixture's
// fallback over the workers (render/cpu/cpu_builders.cpp); they must be the library's serial
// build_flux_weights and make_vpl_distribution(weights, view, eps) bit for bit, whatever the worker
// count. DPRSM 2x256^2: 131072 texels, 8 blocks of the builders' texel loop, so 2 and 3 workers
// split it unevenly.
#include "renderer_gl_fixture.hpp"

#include "cli/render_options.hpp"
#include "render/cpu/cpu_builders.hpp"

#include <vplkit/builders/flux_weights.hpp>
#include <vplkit/builders/vpl_distribution.hpp>

#include <catch2/catch.hpp>

#include <cstring>
#include <vector>

using namespace vplrender;

namespace {

bool same_bits(const std::vector<float>& a, const std::vector<float>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(float)) == 0;
}

bool same_cdf(const vplkit::discrete_cdf<float>& a, const vplkit::discrete_cdf<float>& b) {
  return same_bits(a.cdf(), b.cdf()) && a.guide() == b.guide() && a.sum() == b.sum();
}

}  // namespace

TEST_CASE("CPU builders: flux weights and the mixture's fallback over the workers equal the library's") {
  const vplrender_test::gl_fixture f =
      vplrender_test::make_gl_fixture(vplrender_test::small_options("cornell", 24, 16, 256, 32));
  const vplkit::dprsm_view<float> view = f.b.dprsm.view();
  REQUIRE(view.texel_count() == 2 * 256 * 256);
  const std::vector<float> flux = vplkit::build_flux_weights(view);
  int lit = 0;
  for (float w : flux) lit += w > 0.0f ? 1 : 0;
  REQUIRE(lit > 1000);  // the comparison covers many texels with a VPL and many without
  REQUIRE(lit < view.texel_count() - 1000);
  for (method m : {method::ris_mis, method::global}) {
    for (double eps : {0.0, 0.1}) {
      for (int threads : {1, 2, 3}) {
        INFO(to_string(m) << " eps " << eps << " threads " << threads);
        options o = f.o;
        o.meth = m;
        o.eps = eps;
        o.candidate_source = ris_source_choice::flux;
        render_settings s = make_render_settings(o, f.p.s);
        s.threads = threads;
        stage_timer t;
        nlohmann::json det;
        const cpu_distributions built = build_distributions_cpu(f.b, s, t, {}, det);
        REQUIRE(built.dists.size() == 1);
        if (m == method::ris_mis) CHECK(same_bits(built.weights, flux));
        const vplkit::defensive_mixture<float> ref = vplkit::make_vpl_distribution(built.weights, view, float(eps));
        const vplkit::defensive_mixture<float>& d = built.dists[0];
        CHECK(same_cdf(d.learned(), ref.learned()));
        CHECK(same_cdf(d.fallback(), ref.fallback()));
        CHECK(d.fallback().size() == (eps > 0.0 ? flux.size() : 0u));
        CHECK(d.effective_eps() == ref.effective_eps());
        CHECK(d.fallback_scale() == ref.fallback_scale());
        CHECK(d.learned_scale() == ref.learned_scale());
      }
    }
  }
}
