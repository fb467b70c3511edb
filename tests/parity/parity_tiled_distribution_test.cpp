// SPDX-License-Identifier: MIT
// CPU/GPU parity of builders/tiled_distribution.glsl with include/vplkit/builders/
// tiled_distribution.hpp (T = float) on the synthetic room's DPRSM (R = 20, blocks of 6: the edge
// blocks cut), given the same block CDF, fallback CDF and shares: the index of sample(u) exact and
// its pmf, and pmf(i) of every texel, exact. The draw uses no division (the u split with the host's
// scales, the guided search, the block's running shares compared with d against w c under
// `precise`) and the pmf is one product and the mixture's `precise` sum, so a conforming GPU gives
// the C++ bits. Tiles: one weighed by the room's gather points (eps 0.1), the same without a
// fallback (eps 0), and one whose blocks all weigh 0 (the fallback alone). The u include grid
// values, values at and around every block's CDF edges, and around eps.
#include "parity_distribution_support.hpp"

#include <synthetic_scene.hpp>

#include <vplkit/builders/tile_blocks.hpp>
#include <vplkit/builders/tiled_distribution.hpp>
#include <vplkit/builders/vpl_distribution.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <iostream>
#include <vector>

using namespace vplkit::parity;
using namespace vplkit::parity::dist;

TEST_CASE("tiled_distribution.glsl: the C++ index and pmf, bit for bit, for three tiles") {
  const vplkit_test::synthetic_scene<float> scene;
  const auto dprsm = scene.make_dprsm(20);
  const vplkit::dprsm_view<float> view = dprsm.view();
  const vplkit::tile_blocks<float> tb = vplkit::make_tile_blocks(view, 6);
  const vplkit::discrete_cdf<float> fallback = vplkit::make_vpl_fallback(view);
  const vplkit::discrete_cdf<float> no_fallback;
  const auto gb = scene.make_gbuffer(8, 8);
  std::vector<vplkit::gather_point<float>> pts;
  for (int p = 0; p < 64; p += 3) pts.push_back(gb.view().at(p));
  std::vector<float> w(std::size_t(tb.count()), 0.0f);
  for (int b = 0; b < tb.count(); ++b)
    w[std::size_t(b)] = vplkit::tile_block_weight(pts.data(), pts.size(), tb.proxy[std::size_t(b)], 0.01f);
  const std::vector<float> zero(w.size(), 0.0f);
  const std::vector<vplkit::tiled_distribution<float>> tiles = {
      vplkit::tiled_distribution<float>(tb, w.data(), w.size(), fallback, 0.1f),
      vplkit::tiled_distribution<float>(tb, w.data(), w.size(), no_fallback, 0.0f),
      vplkit::tiled_distribution<float>(tb, zero.data(), zero.size(), fallback, 0.1f)};
  REQUIRE_FALSE(tiles[0].block_cdf().empty());
  REQUIRE(tiles[2].block_cdf().empty());

  packed_cdfs packed;
  std::vector<gpu_mixture> gm;
  for (const auto& t : tiles) {
    const u32 l = packed.add(t.block_cdf());
    const u32 f = packed.add(t.split().effective_eps() > 0.0f ? fallback : no_fallback);
    gm.push_back({packed.descs[l], packed.descs[f], t.split().effective_eps(), t.split().fallback_scale(),
                  t.split().learned_scale()});
  }
  struct q3 {
    float u;
    u32 i, d;
  };
  std::vector<q3> q;
  const u32 n = u32(tb.share.size());
  splitmix_rng g(77);
  for (u32 d = 0; d < tiles.size(); ++d) {
    for (int k = 0; k < 20000; ++k) q.push_back({g.grid_float(), u32(g.next() % (n + 2)), d});
    const float e = tiles[d].split().effective_eps();
    for (float u : {e, std::nextafter(e, 0.0f), std::nextafter(e, 1.0f)}) q.push_back({u, 0, d});
    // Around every block's bin edges, mapped back through the split: the within-block position
    // at its ends.
    const std::vector<float>& cdf = tiles[d].block_cdf().cdf();
    for (std::size_t b = 0; b + 1 < cdf.size(); ++b)
      for (float c : {cdf[b], cdf[b + 1]}) {
        const float u = e + c * (1.0f - e);
        for (float v : {u, std::nextafter(u, 0.0f), std::nextafter(u, 1.0f)})
          if (v >= 0.0f && v < 1.0f) q.push_back({v, u32(b), d});
      }
    for (u32 t = 0; t < n; ++t) q.push_back({g.grid_float(), t, d});
  }
  const kernel_call call = cdf_kernel(packed, "vplkit/builders/tiled_distribution.glsl", R"(
layout(std430, binding = 6) readonly buffer Shares { float shares[]; };
float vplkit_load_tile_share(int texel) { return shares[texel]; }
// The sampler reads no DPRSM: tile_blocks.glsl's accessors are declared, so they are defined.
vec3 vplkit_load_dprsm_position(int texel) { return vec3(0.0); }
vec3 vplkit_load_dprsm_normal(int texel) { return vec3(0.0); }
vec3 vplkit_load_dprsm_albedo(int texel) { return vec3(0.0); }
struct Q { float u; uint i; uint d; };
struct R { uint index; float pmf; float pmf_of_i; };
)",
      {input(0, q, "Q queries"), input(6, tb.share), input(7, gm, "vplkit_defensive_mixture mixtures")}, "R results",
      R"(
  vplkit_defensive_mixture m = mixtures[queries[i].d];
  vplkit_tile_block_grid grid = vplkit_make_tile_block_grid(20, 6);
  vplkit_discrete_sample s = vplkit_tiled_distribution_sample(m, grid, queries[i].u);
  results[i] = R(s.index, s.pmf, vplkit_tiled_distribution_pmf(m, grid, queries[i].i));)");
  struct r3 {
    u32 index;
    float pmf, pmf_of_i;
  };
  const auto gpu = run_compute<r3>(call, q.size());
  series<u32> gi;
  series<float> gp, gpi;
  for (std::size_t k = 0; k < q.size(); ++k) {
    const auto& t = tiles[q[k].d];
    const auto s = t.sample(q[k].u);
    gi.add(gpu[k].index, u32(s.index));
    gp.add(gpu[k].pmf, s.pmf);
    gpi.add(gpu[k].pmf_of_i, t.pmf(q[k].i));
    CHECK(s.pmf > 0.0f);
  }
  const char* names[] = {"weighed, eps 0.1", "weighed, no fallback", "blocks all 0 (fallback alone)"};
  auto describe = [&](std::size_t k) {
    return std::string(names[q[k].d]) + ", u = " + show(q[k].u) + ", i = " + show(q[k].i);
  };
  std::cout << "parity: " << q.size() << " tiled-distribution queries" << std::endl;
  VPLKIT_CHECK_PARITY(compare_exact(gi, describe, "tiled sample index"));
  VPLKIT_CHECK_PARITY(compare_floats(gp, within_ulps(0), describe, "tiled sample pmf"));
  VPLKIT_CHECK_PARITY(compare_floats(gpi, within_ulps(0), describe, "tiled pmf(i)"));
}
