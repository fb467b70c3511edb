// SPDX-License-Identifier: MIT
// Hard cases of builders/tile_blocks.hpp and builders/tiled_distribution.hpp, one per test case:
// bad inputs get a clear error naming what; a tile whose blocks all weigh 0 draws from the
// fallback alone; without a fallback (eps 0) from the blocks alone; with neither there is nothing
// to draw; a texel's share is 0, never NaN, for a zero or NaN flux.
#include <vplkit/builders/tile_blocks.hpp>
#include <vplkit/builders/tiled_distribution.hpp>
#include <vplkit/builders/vpl_distribution.hpp>

#include <synthetic_scene.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <vector>

namespace {

struct room {
  vplkit_test::synthetic_scene<float> s;
  vplkit_test::dprsm_data<float> d = s.make_dprsm(12);
  vplkit::tile_blocks<float> tb = vplkit::make_tile_blocks(d.view(), 4);
  vplkit::discrete_cdf<float> fallback = vplkit::make_vpl_fallback(d.view());
};

const room& shared() {
  static const room r;
  return r;
}

std::vector<float> uniform_weights(const vplkit::tile_blocks<float>& tb) {
  std::vector<float> w(std::size_t(tb.count()), 0.0f);
  for (int b = 0; b < tb.count(); ++b) w[std::size_t(b)] = vplkit::vpl_has_flux(tb.proxy[std::size_t(b)]) ? 1.0f : 0.0f;
  return w;
}

}  // namespace

TEST_CASE("tile blocks: a block side or resolution below 1 is refused, naming both", "[hardcases]") {
  CHECK_THROWS_WITH(vplkit::make_tile_block_grid(16, 0), Catch::Contains("resolution 16 and block 0"));
  CHECK_THROWS_WITH(vplkit::make_tile_block_grid(0, 4), Catch::Contains("must both be >= 1"));
  CHECK_THROWS_WITH(vplkit::make_tile_blocks(shared().d.view(), -3), Catch::Contains("block -3"));
}

TEST_CASE("tiled distribution: block weights of the wrong count are refused", "[hardcases]") {
  const room& r = shared();
  const std::vector<float> w(std::size_t(r.tb.count()) - 1, 1.0f);
  CHECK_THROWS_WITH(vplkit::tiled_distribution<float>(r.tb, w.data(), w.size(), r.fallback, 0.1f),
                    Catch::Contains("block weights for"));
}

TEST_CASE("tiled distribution: a NaN or negative block weight is refused, naming it", "[hardcases]") {
  const room& r = shared();
  std::vector<float> w = uniform_weights(r.tb);
  w[3] = std::numeric_limits<float>::quiet_NaN();
  CHECK_THROWS_WITH(vplkit::tiled_distribution<float>(r.tb, w.data(), w.size(), r.fallback, 0.1f),
                    Catch::Contains("[3]"));
  w[3] = -1.0f;
  CHECK_THROWS_AS(vplkit::tiled_distribution<float>(r.tb, w.data(), w.size(), r.fallback, 0.1f), vplkit::invalid_input);
}

TEST_CASE("tiled distribution: eps outside [0, 1] is refused", "[hardcases]") {
  const room& r = shared();
  const std::vector<float> w = uniform_weights(r.tb);
  CHECK_THROWS_WITH(vplkit::tiled_distribution<float>(r.tb, w.data(), w.size(), r.fallback, 1.5f),
                    Catch::Contains("eps"));
  CHECK_THROWS_AS(vplkit::tiled_distribution<float>(r.tb, w.data(), w.size(), r.fallback,
                                                    std::numeric_limits<float>::quiet_NaN()),
                  vplkit::invalid_input);
}

TEST_CASE("tiled distribution: a fallback over another DPRSM's texels is refused", "[hardcases]") {
  const room& r = shared();
  const std::vector<float> w = uniform_weights(r.tb);
  const std::vector<float> ones(10, 1.0f);
  const vplkit::discrete_cdf<float> other(ones.data(), ones.size());
  CHECK_THROWS_WITH(vplkit::tiled_distribution<float>(r.tb, w.data(), w.size(), other, 0.1f),
                    Catch::Contains("a fallback over 10 texels"));
}

TEST_CASE("tiled distribution: blocks that all weigh 0 leave the fallback alone", "[hardcases]") {
  const room& r = shared();
  const std::vector<float> w(std::size_t(r.tb.count()), 0.0f);
  const vplkit::tiled_distribution<float> d(r.tb, w.data(), w.size(), r.fallback, 0.1f);
  CHECK(d.block_cdf().empty());
  CHECK(d.split().effective_eps() == 1.0f);
  for (std::size_t t = 0; t < r.tb.share.size(); ++t) CHECK(d.pmf(t) == r.fallback.pmf(t));
  for (float u : {0.0f, 0.3f, 0.999f}) CHECK(d.sample(u).index == r.fallback.sample(u).index);
}

TEST_CASE("tiled distribution: without a fallback (eps 0) the blocks alone, every draw in a weighed block", "[hardcases]") {
  const room& r = shared();
  const vplkit::discrete_cdf<float> none;
  std::vector<float> w(std::size_t(r.tb.count()), 0.0f);
  int lit = -1;
  for (int b = 0; b < r.tb.count() && lit < 0; ++b)
    if (vplkit::vpl_has_flux(r.tb.proxy[std::size_t(b)])) lit = b;
  REQUIRE(lit >= 0);
  w[std::size_t(lit)] = 2.0f;
  const vplkit::tiled_distribution<float> d(r.tb, w.data(), w.size(), none, 0.0f);
  CHECK(d.split().effective_eps() == 0.0f);
  for (int k = 0; k < 100; ++k) {
    const vplkit::discrete_sample<float> s = d.sample((float(k) + 0.5f) / 100.0f);
    CHECK(r.tb.block_of(int(s.index)) == lit);
    CHECK(s.pmf == r.tb.share[s.index]);
  }
}

TEST_CASE("tiled distribution: no weighed block and no fallback: nothing to draw", "[hardcases]") {
  const room& r = shared();
  const vplkit::discrete_cdf<float> none;
  const std::vector<float> w(std::size_t(r.tb.count()), 0.0f);
  const vplkit::tiled_distribution<float> d(r.tb, w.data(), w.size(), none, 0.0f);
  CHECK(d.empty());
  CHECK(d.sample(0.5f).pmf == 0.0f);
  CHECK(d.pmf(0) == 0.0f);
  const vplkit::tiled_distribution<float> defaulted;
  CHECK(defaulted.empty());
  CHECK(defaulted.sample(0.25f).pmf == 0.0f);
}

TEST_CASE("tile blocks: a texel's share is 0 for a zero, negative or NaN flux or block flux", "[hardcases]") {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  CHECK(vplkit::tile_texel_share(0.0f, 2.0f) == 0.0f);
  CHECK(vplkit::tile_texel_share(-1.0f, 2.0f) == 0.0f);
  CHECK(vplkit::tile_texel_share(nan, 2.0f) == 0.0f);
  CHECK(vplkit::tile_texel_share(1.0f, 0.0f) == 0.0f);
  CHECK(vplkit::tile_texel_share(1.0f, nan) == 0.0f);
  CHECK(vplkit::tile_texel_share(1.0f, 4.0f) == 0.25f);
}

TEST_CASE("tile blocks: a texel in the middle of its block's bin, at w = 0, takes the block's first texel", "[hardcases]") {
  const room& r = shared();
  int b = -1;
  for (int k = 0; k < r.tb.count() && b < 0; ++k)
    if (r.tb.begin[std::size_t(k) + 1] - r.tb.begin[std::size_t(k)] > 1) b = k;
  REQUIRE(b >= 0);
  const int first = r.tb.texels[std::size_t(r.tb.begin[std::size_t(b)])];
  CHECK(r.tb.texel_in_block(std::size_t(b), 0.5f, 0.0f) == first);
  CHECK(r.tb.texel_in_block(std::size_t(b), 0.5f, std::numeric_limits<float>::quiet_NaN()) == first);
  CHECK(r.tb.texel_in_block(std::size_t(b), 0.0f, 1.0f) == first);
  // d at or past w: the block's last texel.
  const int last = r.tb.texels[std::size_t(r.tb.begin[std::size_t(b) + 1] - 1)];
  CHECK(r.tb.texel_in_block(std::size_t(b), 1.0f, 1.0f) == last);
}
