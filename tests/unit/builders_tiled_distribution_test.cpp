// SPDX-License-Identifier: MIT
// builders/tile_blocks.hpp and builders/tiled_distribution.hpp on the synthetic room's DPRSM, with
// float and double: the blocks (R not a multiple of B, so the edge blocks are cut) hold exactly the
// texels with a VPL, their shares sum to 1 per block and the proxy carries the block's flux; the
// per-block function agrees with make_tile_blocks; a tile's pmf sums to 1, is positive on every
// texel with a VPL and 0 elsewhere; sample(u) returns pmf(index), and over N evenly spaced u each
// texel is drawn N pmf(t) times up to the ends of its intervals, which fails for any mismatch
// between sample and pmf.
#include <vplkit/builders/tile_blocks.hpp>
#include <vplkit/builders/tiled_distribution.hpp>
#include <vplkit/builders/vpl_distribution.hpp>

#include <synthetic_scene.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdlib>
#include <vector>

namespace {

template <class T>
std::vector<T> tile_weights(const vplkit::tile_blocks<T>& tb, const std::vector<vplkit::gather_point<T>>& pts) {
  std::vector<T> w(std::size_t(tb.count()), T(0));
  for (int b = 0; b < tb.count(); ++b)
    w[std::size_t(b)] = vplkit::tile_block_weight(pts.data(), pts.size(), tb.proxy[std::size_t(b)], T(0.01));
  return w;
}

template <class T>
void check_blocks_and_distribution() {
  const vplkit_test::synthetic_scene<T> s;
  const int R = 20, B = 6;  // 4 blocks per face side, the last ones 2 texels wide
  const auto d = s.make_dprsm(R);
  const vplkit::dprsm_view<T> view = d.view();
  const vplkit::tile_blocks<T> tb = vplkit::make_tile_blocks(view, B);
  REQUIRE(tb.grid.per_side == 4);
  REQUIRE(tb.count() == 32);
  const std::vector<T> flux = vplkit::build_flux_weights(view);
  int with_vpl = 0;
  for (std::size_t t = 0; t < flux.size(); ++t) {
    with_vpl += flux[t] > T(0) ? 1 : 0;
    CHECK((tb.share[t] > T(0)) == (flux[t] > T(0)));
  }
  CHECK(int(tb.texels.size()) == with_vpl);
  REQUIRE(with_vpl > R * R / 2);
  int lit_blocks = 0;
  for (int b = 0; b < tb.count(); ++b) {
    const int first = tb.begin[std::size_t(b)], end = tb.begin[std::size_t(b) + 1];
    const vplkit::tile_block_proxy<T> p = vplkit::tile_block_proxy_of(view, tb.grid, b);
    CHECK(p.proxy.position == tb.proxy[std::size_t(b)].position);
    CHECK(p.proxy.flux == tb.proxy[std::size_t(b)].flux);
    if (first == end) {
      CHECK_FALSE(vplkit::vpl_has_flux(tb.proxy[std::size_t(b)]));
      continue;
    }
    ++lit_blocks;
    double share = 0.0, lum = 0.0;
    for (int e = first; e < end; ++e) {
      const int t = tb.texels[std::size_t(e)];
      CHECK(tb.block_of(t) == b);
      share += double(tb.share[std::size_t(t)]);
      lum += double(flux[std::size_t(t)]);
    }
    CHECK(share == Approx(1.0).epsilon(1e-5));
    CHECK(double(tb.cumulative[std::size_t(end - 1)]) == Approx(1.0).epsilon(1e-5));
    CHECK(double(p.flux_luminance) == Approx(lum).epsilon(1e-5));
    CHECK(double(vplkit::luminance(p.proxy.flux)) == Approx(lum).epsilon(1e-4));
  }
  CHECK(lit_blocks > 8);

  // A tile of the room's gather points.
  const auto gb = s.make_gbuffer(8, 8);
  std::vector<vplkit::gather_point<T>> pts;
  for (int p = 0; p < 64; p += 5) pts.push_back(gb.view().at(p));
  const std::vector<T> w = tile_weights(tb, pts);
  const vplkit::discrete_cdf<T> fallback = vplkit::make_vpl_fallback(view);
  const vplkit::tiled_distribution<T> dist(tb, w.data(), w.size(), fallback, T(0.1));
  REQUIRE_FALSE(dist.block_cdf().empty());
  CHECK(dist.split().effective_eps() == T(0.1));
  double sum = 0.0;
  for (std::size_t t = 0; t < flux.size(); ++t) {
    const T p = dist.pmf(t);
    sum += double(p);
    if (flux[t] > T(0)) CHECK(p > T(0));
    else CHECK(p == T(0));
  }
  CHECK(sum == Approx(1.0).epsilon(1e-4));
  constexpr int N = 200000;
  std::vector<int> count(flux.size(), 0);
  int mismatched = 0;
  for (int k = 0; k < N; ++k) {
    const vplkit::discrete_sample<T> smp = dist.sample((T(k) + T(0.5)) / T(N));
    REQUIRE(smp.index < flux.size());
    mismatched += smp.pmf == dist.pmf(smp.index) ? 0 : 1;
    ++count[smp.index];
  }
  CHECK(mismatched == 0);
  double worst = 0.0;
  for (std::size_t t = 0; t < flux.size(); ++t) worst = std::max(worst, std::abs(count[t] - N * double(dist.pmf(t))));
  INFO("largest |count - N pmf| over the texels: " << worst);
  CHECK(worst <= 4.0);  // two intervals per texel, each off by at most one draw per end
}

}  // namespace

TEST_CASE("tile blocks and tiled distributions, float", "[builders]") { check_blocks_and_distribution<float>(); }
TEST_CASE("tile blocks and tiled distributions, double", "[builders]") { check_blocks_and_distribution<double>(); }

TEST_CASE("tile block grid: the block of every texel, edge blocks cut at the face", "[builders]") {
  const vplkit::tile_block_grid g = vplkit::make_tile_block_grid(10, 4);
  CHECK(g.per_side == 3);
  CHECK(g.count() == 18);
  std::vector<int> texels_of(std::size_t(g.count()), 0);
  for (int t = 0; t < vplkit::texel_count(10); ++t) ++texels_of[std::size_t(g.block_of(t))];
  for (int b = 0; b < g.count(); ++b) {
    CHECK(texels_of[std::size_t(b)] == (g.x1(b) - g.x0(b)) * (g.y1(b) - g.y0(b)));
    CHECK(g.x1(b) <= 10);
    CHECK(g.y1(b) <= 10);
  }
  CHECK(g.block_of(vplkit::texel_index(1, 9, 9, 10)) == 17);
}
