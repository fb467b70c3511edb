// SPDX-License-Identifier: MIT
// --candidate-source tiles' distributions (render/cpu/tiled_candidates.hpp) on cornell's DPRSM
// (2x64^2, blocks of 8x8 texels): the blocks' flux shares sum to 1; per tile the pmf sums to 1 over
// the texels, is positive on every texel with a VPL (the fallback's eps) and 0 elsewhere; sample(u)
// returns pmf(index); over N evenly spaced u every texel is drawn N pmf(t) times up to the two ends
// of its two intervals (one in the blocks' part, one in the fallback's), which fails for any
// mismatch between sample and pmf; a tile without gather points draws from the fallback alone,
// and without a fallback (eps 0) from the blocks alone.
#include "renderer_gl_fixture.hpp"

#include "render/cpu/tiled_candidates.hpp"

#include <vplkit/builders/flux_weights.hpp>
#include <vplkit/builders/vpl_distribution.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

using namespace vplrender;

namespace {

struct tiled_fixture {
  vplrender_test::gl_fixture f;
  std::vector<float> flux;
  vplkit::defensive_mixture<float> mixture;
  tile_blocks blocks;
  std::vector<std::vector<vplkit::gather_point<float>>> points;  // tile 0: a row of pixels; tile 1: none
};

const tiled_fixture& shared() {
  static const tiled_fixture t = [] {
    tiled_fixture x{vplrender_test::make_gl_fixture(vplrender_test::small_options("cornell", 24, 16, 64, 32)), {},
                    {}, {}, {}};
    const vplkit::dprsm_view<float> view = x.f.b.dprsm.view();
    x.flux = vplkit::build_flux_weights(view);
    x.mixture = vplkit::make_vpl_distribution(x.flux, view, 0.1f);
    x.blocks = vplkit::make_tile_blocks(view, 8);
    const vplkit::gbuffer_view<float> g = x.f.b.gbuf.view();
    x.points.resize(2);
    for (int p = 8 * g.width; p < 9 * g.width; p += 3)
      if (vplkit::gather_point_valid(g.at(p))) x.points[0].push_back(g.at(p));
    return x;
  }();
  return t;
}

double pmf_sum(const tiled_distribution& d, std::size_t n) {
  double s = 0.0;
  for (std::size_t t = 0; t < n; ++t) s += d.pmf(t);
  return s;
}

// Draws N evenly spaced u and checks every draw and every texel's count against N pmf(t).
void check_draws(const tiled_distribution& d, const std::vector<float>& flux) {
  constexpr int N = 400000;
  std::vector<int> count(flux.size(), 0);
  int mismatched_pmf = 0, without_vpl = 0;
  for (int k = 0; k < N; ++k) {
    const float u = (float(k) + 0.5f) / float(N);
    const vplkit::discrete_sample<float> s = d.sample(u);
    REQUIRE(s.index < flux.size());
    if (s.pmf != d.pmf(s.index)) ++mismatched_pmf;
    if (!(flux[s.index] > 0.0f)) ++without_vpl;
    ++count[s.index];
  }
  CHECK(mismatched_pmf == 0);
  CHECK(without_vpl == 0);
  double worst = 0.0;
  for (std::size_t t = 0; t < flux.size(); ++t) worst = std::max(worst, std::abs(count[t] - N * double(d.pmf(t))));
  INFO("largest |count - N pmf| over the texels: " << worst);
  CHECK(worst <= 2.5);
}

}  // namespace

TEST_CASE("tile candidates: each block's flux shares sum to 1, and its proxy carries its flux") {
  const tiled_fixture& x = shared();
  const tile_blocks& b = x.blocks;
  REQUIRE(b.count() == 2 * 8 * 8);
  int with_vpl = 0;
  for (int k = 0; k < b.count(); ++k) {
    const int first = b.begin[std::size_t(k)], end = b.begin[std::size_t(k) + 1];
    if (first == end) {
      CHECK_FALSE(vplkit::vpl_has_flux(b.proxy[std::size_t(k)]));
      continue;
    }
    ++with_vpl;
    double share = 0.0, lum = 0.0;
    for (int e = first; e < end; ++e) {
      const int t = b.texels[std::size_t(e)];
      CHECK(b.block_of(t) == k);
      CHECK(x.flux[std::size_t(t)] > 0.0f);
      share += b.share[std::size_t(t)];
      lum += x.flux[std::size_t(t)];
    }
    CHECK(share == Approx(1.0).epsilon(1e-5));
    CHECK(b.cumulative[std::size_t(end - 1)] == Approx(1.0f).epsilon(1e-5));
    CHECK(vplkit::luminance(b.proxy[std::size_t(k)].flux) == Approx(lum).epsilon(1e-4));
  }
  CHECK(with_vpl > 10);
  int texels_with_vpl = 0;
  for (float w : x.flux) texels_with_vpl += w > 0.0f ? 1 : 0;
  CHECK(int(b.texels.size()) == texels_with_vpl);
}

TEST_CASE("tile candidates: the pmf sums to 1, keeps every VPL, and sample(u) draws it") {
  const tiled_fixture& x = shared();
  REQUIRE(x.points[0].size() >= 5);
  const std::vector<tiled_distribution> d =
      make_tiled_distributions(x.blocks, x.points, 0.01f, x.mixture.fallback(), 0.1f, 2);
  REQUIRE(d.size() == 2);
  const std::size_t n = x.flux.size();
  for (const tiled_distribution& td : d) CHECK(pmf_sum(td, n) == Approx(1.0).epsilon(1e-4));
  // Tile 0 weighs its blocks: a learned part that is not the flux distribution.
  CHECK_FALSE(d[0].block_cdf().empty());
  CHECK(d[0].split().effective_eps() == 0.1f);
  int zero_on_vpl = 0, positive_off_vpl = 0, differs_from_flux = 0;
  for (std::size_t t = 0; t < n; ++t) {
    const float p = d[0].pmf(t);
    if (x.flux[t] > 0.0f && !(p > 0.0f)) ++zero_on_vpl;
    if (!(x.flux[t] > 0.0f) && p != 0.0f) ++positive_off_vpl;
    if (std::abs(p - x.mixture.pmf(t)) > 1e-3f * x.mixture.pmf(t)) ++differs_from_flux;
  }
  CHECK(zero_on_vpl == 0);
  CHECK(positive_off_vpl == 0);
  CHECK(differs_from_flux > 100);
  check_draws(d[0], x.flux);
  // Tile 1 has no gather points: the fallback alone.
  CHECK(d[1].block_cdf().empty());
  CHECK(d[1].split().effective_eps() == 1.0f);
  for (std::size_t t = 0; t < n; t += 97) CHECK(d[1].pmf(t) == x.mixture.fallback().pmf(t));
  check_draws(d[1], x.flux);
}

TEST_CASE("tile candidates without a fallback (eps 0): the blocks alone") {
  const tiled_fixture& x = shared();
  const vplkit::defensive_mixture<float> no_eps = vplkit::make_vpl_distribution(x.flux, x.f.b.dprsm.view(), 0.0f);
  REQUIRE(no_eps.fallback().empty());
  const std::vector<tiled_distribution> d =
      make_tiled_distributions(x.blocks, {x.points[0]}, 0.01f, no_eps.fallback(), 0.0f, 1);
  REQUIRE(d.size() == 1);
  CHECK(d[0].split().effective_eps() == 0.0f);
  CHECK(pmf_sum(d[0], x.flux.size()) == Approx(1.0).epsilon(1e-4));
  check_draws(d[0], x.flux);
  // With no points and no fallback there is nothing to draw.
  const std::vector<tiled_distribution> none =
      make_tiled_distributions(x.blocks, {{}}, 0.01f, no_eps.fallback(), 0.0f, 1);
  CHECK(none[0].empty());
  CHECK(none[0].sample(0.5f).pmf == 0.0f);
}
