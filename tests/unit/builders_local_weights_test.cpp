// SPDX-License-Identifier: MIT
// Local CDF: the region grid partitions the image, subsets stay in their region, and each region's
// weights are the global weights of its own subset.
#include <vplkit/builders/global_weights.hpp>
#include <vplkit/builders/local_weights.hpp>
#include <vplkit/builders/vpl_distribution.hpp>
#include <vplkit/core/error.hpp>

#include <synthetic_scene.hpp>

#include <catch2/catch.hpp>

#include <set>
#include <vector>

using vplkit::vec3;

TEST_CASE("builders: regions partition every image exactly once", "[builders]") {
  const int sizes[][2] = {{1, 1}, {2, 3}, {7, 5}, {16, 16}, {17, 9}, {33, 1}, {1, 31}, {101, 63}};
  const int grids[][2] = {{1, 1}, {2, 2}, {3, 1}, {1, 3}, {3, 3}, {4, 2}, {5, 7}, {2, 5}};
  int checked = 0;
  for (const auto& sz : sizes)
    for (const auto& gr : grids) {
      const int W = sz[0], H = sz[1], rx = gr[0], ry = gr[1];
      if (rx > W || ry > H) {
        CHECK_THROWS_AS(vplkit::image_regions(W, H, rx, ry), vplkit::invalid_input);
        continue;
      }
      ++checked;
      const vplkit::image_regions regions(W, H, rx, ry);
      INFO(W << "x" << H << " image, " << rx << "x" << ry << " regions");
      REQUIRE(regions.count() == rx * ry);
      std::vector<int> seen(std::size_t(W * H), -1);
      for (int i = 0; i < regions.count(); ++i) {
        const vplkit::pixel_rect r = regions.region_rect(i);
        REQUIRE(r.width >= 1);
        REQUIRE(r.height >= 1);
        // sizes differ by at most one pixel between regions
        REQUIRE(std::abs(r.width - W / rx) <= 1);
        REQUIRE(std::abs(r.height - H / ry) <= 1);
        for (int y = r.y0; y < r.y0 + r.height; ++y)
          for (int x = r.x0; x < r.x0 + r.width; ++x) {
            REQUIRE(x < W);
            REQUIRE(y < H);
            int& s = seen[std::size_t(y * W + x)];
            REQUIRE(s == -1);
            s = i;
          }
      }
      for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
          REQUIRE(seen[std::size_t(y * W + x)] == regions.region_of_pixel(x, y));
          REQUIRE(vplkit::region_of_pixel(x, y, W, H, rx, ry) == regions.region_of_pixel(x, y));
        }
    }
  REQUIRE(checked == 39);  // the rest were too many regions for the image
}

TEST_CASE("builders: the default region grid is the paper's 2 x 2", "[builders]") {
  const vplkit::image_regions r(640, 480);
  REQUIRE(r.count() == 4);
  CHECK(r.region_of_pixel(0, 0) == 0);
  CHECK(r.region_of_pixel(639, 0) == 1);
  CHECK(r.region_of_pixel(0, 479) == 2);
  CHECK(r.region_of_pixel(320, 240) == 3);
  CHECK(r.region_of_pixel(319, 239) == 0);
}

TEST_CASE("builders: local subsets lie in their region and are deterministic", "[builders]") {
  const vplkit_test::synthetic_scene<double> s;
  const auto gb = s.make_gbuffer(23, 17);
  const vplkit::image_regions regions = vplkit::make_image_regions(gb.view(), 3, 2);
  const auto a = vplkit::local_gather_subsets(gb.view(), regions, 12, 99u);
  const auto b = vplkit::local_gather_subsets(gb.view(), regions, 12, 99u);
  const auto c = vplkit::local_gather_subsets(gb.view(), regions, 12, 100u);
  REQUIRE(a == b);
  REQUIRE(a != c);
  REQUIRE(a.size() == 6);
  std::set<int> all;
  for (int i = 0; i < 6; ++i) {
    REQUIRE(a[std::size_t(i)].size() == 12);
    for (int p : a[std::size_t(i)]) {
      REQUIRE(regions.region_of_pixel(p % 23, p / 23) == i);
      all.insert(p);
    }
  }
  REQUIRE(all.size() == 72);  // distinct across regions too
  // regions are stratified with disjoint streams: the same subset as calling the primitive
  for (int i = 0; i < 6; ++i)
    REQUIRE(a[std::size_t(i)] == vplkit::stratified_gather_subset(
                                     gb.view(), regions.region_rect(i), 12, 99u,
                                     std::uint32_t(i * 12)));
}

TEMPLATE_TEST_CASE("builders: local weights are the global weights of each region's subset",
                   "[builders]", float, double) {
  using T = TestType;
  const vplkit_test::lit_room_gbuffer<T> room(8, 15, 11);
  const vplkit::image_regions regions(15, 11);  // 2 x 2
  const std::vector<T> flat = vplkit::build_local_weights(room.gb.view(), regions, 6, 3u, room.view, T(0.1));
  const std::size_t per = std::size_t(room.view.texel_count());
  REQUIRE(flat.size() == 4 * per);
  const auto subsets = vplkit::local_gather_subsets(room.gb.view(), regions, 6, 3u);
  std::vector<int> used(4, -1);
  std::vector<T> flat2(flat.size(), T(-1));
  vplkit::build_local_weights(room.gb.view(), regions, subsets, room.view, T(0.1), flat2.data(),
                              flat2.size(), used.data());
  REQUIRE(flat2 == flat);
  for (int i = 0; i < 4; ++i) {
    REQUIRE(used[std::size_t(i)] == 6);
    const std::vector<T> g =
        vplkit::build_global_weights(room.gb.view(), subsets[std::size_t(i)], room.view, T(0.1));
    REQUIRE(std::equal(g.begin(), g.end(), flat.begin() + std::ptrdiff_t(i * per)));
  }
  // the regions see the scene differently: their weight arrays differ
  REQUIRE(!std::equal(flat.begin(), flat.begin() + std::ptrdiff_t(per),
                      flat.begin() + std::ptrdiff_t(per)));
  // one distribution per region
  const auto dists = vplkit::make_local_vpl_distributions(flat, 4, room.view, T(0.1));
  REQUIRE(dists.size() == 4);
  for (const auto& m : dists) {
    REQUIRE(!m.empty());
    REQUIRE(m.size() == per);
  }
}

TEST_CASE("builders: local builder rejects bad arguments", "[builders]") {
  const vplkit_test::synthetic_scene<double> s;
  const auto d = s.make_dprsm(4);
  const auto gb = s.make_gbuffer(8, 8);
  const vplkit::image_regions wrong(9, 8);
  CHECK_THROWS_AS(vplkit::local_gather_subsets(gb.view(), wrong, 4, 0u), vplkit::invalid_input);
  const vplkit::image_regions regions(8, 8, 2, 2);
  CHECK_THROWS_AS(vplkit::local_gather_subsets(gb.view(), regions, -2, 0u), vplkit::invalid_input);
  const auto subsets = vplkit::local_gather_subsets(gb.view(), regions, 4, 0u);
  std::vector<double> w(4 * std::size_t(d.view().texel_count()));
  CHECK_THROWS_AS(vplkit::build_local_weights(gb.view(), regions, subsets, d.view(), 0.0, w.data(),
                                              w.size() - 1),
                  vplkit::invalid_input);
  const std::vector<std::vector<int>> three(3);
  CHECK_THROWS_AS(vplkit::build_local_weights(gb.view(), regions, three, d.view(), 0.0, w.data(),
                                              w.size()),
                  vplkit::invalid_input);
  CHECK_THROWS_AS(vplkit::image_regions(0, 4), vplkit::invalid_input);
  CHECK_THROWS_AS(vplkit::image_regions(4, 4, 0, 1), vplkit::invalid_input);
  CHECK_THROWS_AS(vplkit::make_local_vpl_distributions(w, 3, d.view(), 0.0), vplkit::invalid_input);
}
