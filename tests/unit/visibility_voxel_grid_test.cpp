// SPDX-License-Identifier: MIT
// Unit tests of the packed binary voxel grid (include/vplkit/visibility/voxel_grid.hpp).
#include <vplkit/visibility/voxel_grid.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

using vplkit::ivec3;

TEST_CASE("voxel grid bit layout: index x + y nx + z nx ny, word i >> 5, bit i & 31", "[visibility]") {
  vplkit::voxel_grid<float> g(vplkit::vec3<float>(0.0f), vplkit::vec3<float>(1.0f), ivec3(5, 3, 4));
  REQUIRE(g.word_count() == (5u * 3u * 4u + 31u) / 32u);  // 60 voxels -> 2 words
  g.set(ivec3(0, 0, 0));
  REQUIRE(g.words()[0] == 1u);
  g.set(ivec3(1, 2, 1));  // 1 + 2*5 + 1*15 = 26
  REQUIRE(g.words()[0] == (1u | (1u << 26)));
  g.set(ivec3(2, 0, 2));  // 2 + 0 + 30 = 32 -> word 1, bit 0
  REQUIRE(g.words()[1] == 1u);
  g.set(ivec3(4, 2, 3));  // 4 + 10 + 45 = 59 -> word 1, bit 27
  REQUIRE(g.words()[1] == (1u | (1u << 27)));
  REQUIRE(vplkit::voxel_flat_index(g.resolution(), ivec3(4, 2, 3)) == 59);
  REQUIRE(g.count() == 4);
}

TEST_CASE("voxel grid set / test / clear / count", "[visibility]") {
  vplkit::voxel_grid<double> g(vplkit::vec3<double>(-1.0), vplkit::vec3<double>(1.0), ivec3(7, 6, 5));
  std::int64_t expected = 0;
  for (int z = 0; z < 5; ++z)
    for (int y = 0; y < 6; ++y)
      for (int x = 0; x < 7; ++x)
        if ((x * 3 + y * 5 + z * 7) % 4 == 0) {
          g.set(ivec3(x, y, z));
          ++expected;
        }
  REQUIRE(g.count() == expected);
  for (int z = 0; z < 5; ++z)
    for (int y = 0; y < 6; ++y)
      for (int x = 0; x < 7; ++x) REQUIRE(g.test(ivec3(x, y, z)) == ((x * 3 + y * 5 + z * 7) % 4 == 0));
  g.set(ivec3(0, 0, 0));  // setting twice changes nothing
  REQUIRE(g.count() == expected);
  g.clear(ivec3(0, 0, 0));
  REQUIRE_FALSE(g.test(ivec3(0, 0, 0)));
  REQUIRE(g.count() == expected - 1);
  // Outside the grid: test() is false, set()/clear() throw.
  REQUIRE_FALSE(g.test(ivec3(-1, 0, 0)));
  REQUIRE_FALSE(g.test(ivec3(0, 6, 0)));
  REQUIRE_FALSE(g.test(ivec3(0, 0, 5)));
  REQUIRE_THROWS_AS(g.set(ivec3(7, 0, 0)), vplkit::invalid_input);
  REQUIRE_THROWS_AS(g.clear(ivec3(0, -1, 0)), vplkit::invalid_input);
  g.clear_all();
  REQUIRE(g.count() == 0);
}

TEST_CASE("voxel grid validates bounds and resolution", "[visibility]") {
  using v3 = vplkit::vec3<float>;
  const v3 lo(0.0f), hi(1.0f);
  REQUIRE_THROWS_AS(vplkit::voxel_grid<float>(lo, hi, ivec3(0, 4, 4)), vplkit::invalid_input);
  REQUIRE_THROWS_AS(vplkit::voxel_grid<float>(lo, hi, ivec3(4, -2, 4)), vplkit::invalid_input);
  REQUIRE_THROWS_AS(vplkit::voxel_grid<float>(lo, hi, ivec3(4, 4, 4097)), vplkit::invalid_input);
  REQUIRE_THROWS_AS(vplkit::voxel_grid<float>(lo, hi, ivec3(4096, 4096, 129)), vplkit::invalid_input);
  REQUIRE_THROWS_AS(vplkit::voxel_grid<float>(hi, lo, ivec3(4)), vplkit::invalid_input);
  REQUIRE_THROWS_AS(vplkit::voxel_grid<float>(v3(0, 0, 1), v3(1, 1, 1), ivec3(4)), vplkit::invalid_input);
  REQUIRE_THROWS_AS(vplkit::voxel_grid<float>(v3(0, std::nanf(""), 0), hi, ivec3(4)), vplkit::invalid_input);
  const float inf = std::numeric_limits<float>::infinity();
  REQUIRE_THROWS_AS(vplkit::voxel_grid<float>(lo, v3(1, inf, 1), ivec3(4)), vplkit::invalid_input);
  // max - min overflows to infinity.
  const float big = std::numeric_limits<float>::max();
  REQUIRE_THROWS_AS(vplkit::voxel_grid<float>(v3(-big), v3(big), ivec3(4)), vplkit::invalid_input);
  REQUIRE_NOTHROW(vplkit::voxel_grid<float>(lo, hi, ivec3(1)));
  REQUIRE_NOTHROW(vplkit::voxel_grid<float>(lo, hi, ivec3(4096, 1, 1)));
}

TEST_CASE("voxel grid adopts GPU words, views check their word count", "[visibility]") {
  const ivec3 res(3, 3, 3);  // 27 voxels: bits 27..31 of the only word are unused
  std::vector<std::uint32_t> words = {0xFFFFFFFFu};
  vplkit::voxel_grid<float> g(vplkit::vec3<float>(0.0f), vplkit::vec3<float>(3.0f), res, words);
  REQUIRE(g.count() == 27);  // the unused bits were cleared
  REQUIRE(g.words()[0] == 0x07FFFFFFu);
  REQUIRE_THROWS_AS(vplkit::voxel_grid<float>(vplkit::vec3<float>(0.0f), vplkit::vec3<float>(3.0f), res,
                                              std::vector<std::uint32_t>{0u, 0u}),
                    vplkit::invalid_input);

  // A non-owning view over the caller's words reads the same voxels.
  std::vector<std::uint32_t> raw(vplkit::voxel_word_count(ivec3(8, 8, 8)), 0u);
  raw[3] = 1u << 5;  // flat index 3 * 32 + 5 = 101 = 5 + 4 * 8 + 1 * 64 -> voxel (5, 4, 1)
  const auto view = vplkit::make_voxel_grid_view(vplkit::vec3<double>(0.0), vplkit::vec3<double>(1.0),
                                                 ivec3(8, 8, 8), raw.data(), raw.size());
  REQUIRE(vplkit::voxel_test(view, ivec3(5, 4, 1)));
  REQUIRE_FALSE(vplkit::voxel_test(view, ivec3(4, 4, 1)));
  REQUIRE_FALSE(vplkit::voxel_test(view, ivec3(8, 4, 1)));
  REQUIRE_THROWS_AS(vplkit::make_voxel_grid_view(vplkit::vec3<double>(0.0), vplkit::vec3<double>(1.0),
                                                 ivec3(8, 8, 8), raw.data(), raw.size() - 1),
                    vplkit::invalid_input);
  REQUIRE_THROWS_AS(vplkit::make_voxel_grid_view<double>(vplkit::vec3<double>(0.0), vplkit::vec3<double>(1.0),
                                                         ivec3(8, 8, 8), nullptr, raw.size()),
                    vplkit::invalid_input);
}

TEST_CASE("voxel grid world <-> voxel conversions", "[visibility]") {
  using v3 = vplkit::vec3<double>;
  vplkit::voxel_grid<double> g(v3(-2.0, 0.0, 10.0), v3(2.0, 3.0, 11.0), ivec3(8, 6, 4));
  REQUIRE(g.voxel_size() == v3(0.5, 0.5, 0.25));
  REQUIRE(g.voxel_length() == 0.5);
  for (int z = 0; z < 4; ++z)
    for (int y = 0; y < 6; ++y)
      for (int x = 0; x < 8; ++x) {
        const ivec3 v(x, y, z);
        REQUIRE(g.world_to_voxel(g.voxel_center(v)) == v);
        REQUIRE(g.voxel_to_world(v3(v)) == v3(-2.0 + 0.5 * x, 0.5 * y, 10.0 + 0.25 * z));
      }
  // Points on voxel planes belong to the voxel above (floor); the max face is voxel n (outside).
  REQUIRE(g.world_to_voxel(v3(-2.0, 0.0, 10.0)) == ivec3(0, 0, 0));
  REQUIRE(g.world_to_voxel(v3(-1.5, 1.0, 10.5)) == ivec3(1, 2, 2));
  REQUIRE(g.world_to_voxel(v3(2.0, 3.0, 11.0)) == ivec3(8, 6, 4));
  REQUIRE(g.world_to_voxel_coord(v3(0.0, 1.5, 10.5)) == v3(4.0, 3.0, 2.0));
  // Far away and non-finite points give indices outside the grid, without undefined conversions.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const ivec3 far = g.world_to_voxel(v3(1e300, -1e300, nan));
  REQUIRE(far.x == 1073741824);
  REQUIRE(far.y == -1073741824);
  REQUIRE(far.z == -1073741824);
  REQUIRE_FALSE(g.contains(far));
}
