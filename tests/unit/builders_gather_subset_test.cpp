// SPDX-License-Identifier: MIT
// Stratified gather-pixel subsets: the stratum grid tiles the rectangle, picks stay inside their
// stratum, are distinct, valid and deterministic, and background strata resample or drop.
#include <synthetic_scene.hpp>

#include <vplkit/builders/gather_subset.hpp>
#include <vplkit/core/error.hpp>
#include <vplkit/core/gather_point.hpp>

#include <catch2/catch.hpp>

#include <set>
#include <vector>

using vplkit::vec3;

namespace {

// A w x h G-buffer whose pixels are all valid except where bg(x, y) says background.
template <class Bg>
vplkit_test::gbuffer_data<double> test_gbuffer(int w, int h, Bg bg) {
  vplkit_test::gbuffer_data<double> g;
  g.width = w;
  g.height = h;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      g.position.emplace_back(double(x), double(y), 0.0);
      g.normal.push_back(bg(x, y) ? vec3<double>(0.0) : vec3<double>(0, 0, 1));
      g.albedo.emplace_back(0.5);
    }
  return g;
}

}  // namespace

TEST_CASE("builders: the stratum grid tiles the rectangle with exactly `count` cells",
          "[builders]") {
  const vplkit::pixel_rect rects[] = {{0, 0, 16, 16}, {3, 5, 17, 9},  {0, 0, 1, 1},
                                      {2, 1, 1, 31},  {0, 0, 40, 1},  {7, 0, 13, 11},
                                      {0, 0, 640, 3}, {1, 2, 5, 700}, {0, 0, 2, 9},
                                      {4, 4, 3, 40}};
  for (const vplkit::pixel_rect& r : rects) {
    for (int count : {1, 2, 3, 5, 7, 16, 31, 64, 100, 257, 1000, 5000}) {
      const vplkit::gather_subset_grid_shape g = vplkit::gather_subset_grid(r, count);
      INFO("rect " << r.x0 << "," << r.y0 << " " << r.width << "x" << r.height << " count "
                   << count);
      const int expected = count < r.width * r.height ? count : r.width * r.height;
      REQUIRE(g.count == expected);
      REQUIRE(g.columns >= 1);
      REQUIRE(g.rows >= 1);
      REQUIRE(g.columns <= r.width);
      REQUIRE(g.rows <= r.height);
      REQUIRE(g.last_columns >= 1);
      REQUIRE(g.last_columns <= g.columns);
      REQUIRE((g.rows - 1) * g.columns + g.last_columns == g.count);
      // every pixel of the rectangle in exactly one cell, every cell non-empty
      std::vector<int> owner(std::size_t(r.width * r.height), -1);
      for (int k = 0; k < g.count; ++k) {
        const vplkit::pixel_rect c = vplkit::gather_subset_stratum(r, g, k);
        REQUIRE(c.width >= 1);
        REQUIRE(c.height >= 1);
        for (int y = c.y0; y < c.y0 + c.height; ++y)
          for (int x = c.x0; x < c.x0 + c.width; ++x) {
            REQUIRE(vplkit::pixel_rect_contains(r, x, y));
            int& o = owner[std::size_t((y - r.y0) * r.width + (x - r.x0))];
            REQUIRE(o == -1);
            o = k;
          }
      }
      for (int o : owner) REQUIRE(o >= 0);
    }
  }
}

TEST_CASE("builders: the stratum grid shape is consistent for every small rectangle and count",
          "[builders]") {
  // Tall thin rectangles (e.g. 2 x 9 with 10 strata) take the "more rows than pixel rows" branch.
  for (int w = 1; w <= 24; ++w)
    for (int h = 1; h <= 24; ++h)
      for (int count = 0; count <= w * h + 2; ++count) {
        const vplkit::gather_subset_grid_shape g = vplkit::gather_subset_grid({0, 0, w, h}, count);
        const int expected = count < w * h ? count : w * h;
        REQUIRE(g.count == expected);
        if (expected == 0) continue;
        INFO(w << " x " << h << ", count " << count);
        REQUIRE(g.columns >= 1);
        REQUIRE(g.columns <= w);
        REQUIRE(g.rows >= 1);
        REQUIRE(g.rows <= h);
        REQUIRE(g.last_columns >= 1);
        REQUIRE(g.last_columns <= g.columns);
        REQUIRE((g.rows - 1) * g.columns + g.last_columns == expected);
      }
}

TEST_CASE("builders: strata are about square", "[builders]") {
  const vplkit::gather_subset_grid_shape g = vplkit::gather_subset_grid({0, 0, 512, 256}, 128);
  CHECK(g.columns == 16);
  CHECK(g.rows == 8);
  CHECK(g.last_columns == 16);
  const vplkit::gather_subset_grid_shape s = vplkit::gather_subset_grid({0, 0, 100, 100}, 4096);
  CHECK(s.columns == 64);
  CHECK(s.rows == 64);
}

TEST_CASE("builders: one pick per stratum, inside it, distinct and deterministic", "[builders]") {
  const auto gb = test_gbuffer(37, 23, [](int, int) { return false; });
  const auto view = gb.view();
  const vplkit::pixel_rect rect{5, 3, 29, 17};
  const int count = 50;
  const std::vector<int> a = vplkit::stratified_gather_subset(view, rect, count, 7u);
  const std::vector<int> b = vplkit::stratified_gather_subset(view, rect, count, 7u);
  const std::vector<int> c = vplkit::stratified_gather_subset(view, rect, count, 8u);
  REQUIRE(a.size() == std::size_t(count));  // no background: no stratum drops
  REQUIRE(a == b);
  REQUIRE(a != c);
  const vplkit::gather_subset_grid_shape g = vplkit::gather_subset_grid(rect, count);
  for (int k = 0; k < count; ++k) {
    const int p = a[std::size_t(k)];
    const vplkit::pixel_rect cell = vplkit::gather_subset_stratum(rect, g, k);
    REQUIRE(vplkit::pixel_rect_contains(cell, p % view.width, p / view.width));
    REQUIRE(vplkit::gather_subset_pick(view, rect, g, k, 7u, 0u, 4) == p);
  }
  REQUIRE(std::set<int>(a.begin(), a.end()).size() == a.size());
  // stream_offset shifts the streams: stratum k of offset o is stream o + k
  const std::vector<int> shifted = vplkit::stratified_gather_subset(view, rect, count, 7u, 1000u);
  REQUIRE(shifted != a);
}

TEST_CASE("builders: count above the pixel count takes every pixel once", "[builders]") {
  const auto gb = test_gbuffer(5, 3, [](int, int) { return false; });
  const std::vector<int> s = vplkit::stratified_gather_subset(gb.view(), {1, 1, 3, 2}, 100, 1u);
  REQUIRE(s.size() == 6);
  const std::set<int> got(s.begin(), s.end());
  const std::set<int> want{1 * 5 + 1, 1 * 5 + 2, 1 * 5 + 3, 2 * 5 + 1, 2 * 5 + 2, 2 * 5 + 3};
  REQUIRE(got == want);
}

TEST_CASE("builders: the jitter covers the stratum uniformly", "[builders]") {
  // one 4 x 4 stratum, many seeds: every pixel is chosen, about equally often
  const auto gb = test_gbuffer(4, 4, [](int, int) { return false; });
  std::vector<int> hist(16, 0);
  for (std::uint32_t seed = 0; seed < 16000; ++seed) {
    const std::vector<int> s = vplkit::stratified_gather_subset(gb.view(), {0, 0, 4, 4}, 1, seed);
    REQUIRE(s.size() == 1);
    ++hist[std::size_t(s[0])];
  }
  for (int h : hist) {
    CHECK(h > 800);  // expected 1000, sd ~31
    CHECK(h < 1200);
  }
}

TEST_CASE("builders: background strata resample, then drop", "[builders]") {
  // left half background
  const auto gb = test_gbuffer(20, 10, [](int x, int) { return x < 10; });
  const auto view = gb.view();
  const vplkit::pixel_rect rect{0, 0, 20, 10};
  const vplkit::gather_subset_grid_shape g = vplkit::gather_subset_grid(rect, 8);
  REQUIRE(g.columns == 4);
  REQUIRE(g.rows == 2);
  const std::vector<int> s = vplkit::stratified_gather_subset(view, rect, 8, 3u);
  // the four strata in the left half have no valid pixel: they always drop
  REQUIRE(s.size() == 4);
  for (int p : s) REQUIRE(p % 20 >= 10);
  for (int k = 0; k < 8; ++k) {
    const vplkit::pixel_rect cell = vplkit::gather_subset_stratum(rect, g, k);
    const int pick = vplkit::gather_subset_pick(view, rect, g, k, 3u, 0u, 4);
    if (cell.x0 + cell.width <= 10) REQUIRE(pick == -1);
    if (cell.x0 >= 10) REQUIRE(pick >= 0);
  }

  // A stratum straddling the boundary: with one attempt it drops about half the time, with many
  // attempts almost never; every accepted pick is valid.
  const auto half = test_gbuffer(2, 1, [](int x, int) { return x == 0; });
  int kept1 = 0, kept8 = 0;
  for (std::uint32_t seed = 0; seed < 2000; ++seed) {
    const auto s1 = vplkit::stratified_gather_subset(half.view(), {0, 0, 2, 1}, 1, seed, 0u, 1);
    const auto s8 = vplkit::stratified_gather_subset(half.view(), {0, 0, 2, 1}, 1, seed, 0u, 8);
    for (int p : s1) REQUIRE(p == 1);
    for (int p : s8) REQUIRE(p == 1);
    kept1 += int(s1.size());
    kept8 += int(s8.size());
  }
  CHECK(kept1 > 850);
  CHECK(kept1 < 1150);
  CHECK(kept8 > 1980);  // drop probability 2^-8
}

TEST_CASE("builders: gather subset rejects bad arguments", "[builders]") {
  const auto gb = test_gbuffer(8, 8, [](int, int) { return false; });
  const auto v = gb.view();
  CHECK_THROWS_AS(vplkit::stratified_gather_subset(v, {0, 0, 9, 8}, 4, 0u), vplkit::invalid_input);
  CHECK_THROWS_AS(vplkit::stratified_gather_subset(v, {-1, 0, 4, 4}, 4, 0u), vplkit::invalid_input);
  CHECK_THROWS_AS(vplkit::stratified_gather_subset(v, {0, 0, 0, 4}, 4, 0u), vplkit::invalid_input);
  CHECK_THROWS_AS(vplkit::stratified_gather_subset(v, {0, 0, 4, 4}, -1, 0u), vplkit::invalid_input);
  CHECK_THROWS_AS(vplkit::stratified_gather_subset(v, {0, 0, 4, 4}, 4, 0u, 0u, 0),
                  vplkit::invalid_input);
  CHECK(vplkit::stratified_gather_subset(v, {0, 0, 4, 4}, 0, 0u).empty());
  vplkit::gbuffer_view<double> null_view = v;
  null_view.normal = nullptr;
  CHECK_THROWS_AS(vplkit::stratified_gather_subset(null_view, {0, 0, 4, 4}, 4, 0u),
                  vplkit::invalid_input);
}
