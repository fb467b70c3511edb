// SPDX-License-Identifier: MIT
// Unit tests of the DDA (include/vplkit/visibility/dda.hpp).
#include <vplkit/visibility/dda.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <random>

using vplkit::ivec3;

namespace {

template <class T>
vplkit::voxel_grid<T> unit_grid(int n) {
  return vplkit::voxel_grid<T>(vplkit::vec3<T>(T(0)), vplkit::vec3<T>(T(n)), ivec3(n));
}

}  // namespace

TEMPLATE_TEST_CASE("DDA: entry distance of a single occupied voxel", "[visibility][dda]", float, double) {
  using T = TestType;
  using v3 = vplkit::vec3<T>;
  auto g = unit_grid<T>(8);
  g.set(ivec3(5, 3, 2));
  // From inside the grid, along +x through the voxel's centre line: enters at x = 5.
  auto h = vplkit::dda_first_hit(g.view(), v3(T(0.5), T(3.5), T(2.5)), v3(T(1), T(0), T(0)));
  REQUIRE(h.hit);
  REQUIRE(h.voxel == ivec3(5, 3, 2));
  REQUIRE(h.t == Approx(4.5));
  // Oblique: from (1.5, 1.5, 0.5) towards the voxel centre (5.5, 3.5, 2.5); enters through x = 5.
  const v3 o(T(1.5), T(1.5), T(0.5)), c(T(5.5), T(3.5), T(2.5));
  h = vplkit::dda_first_hit(g.view(), o, c - o);
  REQUIRE(h.hit);
  REQUIRE(h.voxel == ivec3(5, 3, 2));
  const T len = glm::length(c - o);
  REQUIRE(h.t == Approx(double(len) * 3.5 / 4.0).epsilon(1e-5));
  // The origin inside the occupied voxel: t = 0.
  h = vplkit::dda_first_hit(g.view(), v3(T(5.2), T(3.9), T(2.1)), v3(T(-1), T(2), T(0.5)));
  REQUIRE(h.hit);
  REQUIRE(h.t == T(0));
  REQUIRE(h.voxel == ivec3(5, 3, 2));
  // Missing it.
  h = vplkit::dda_first_hit(g.view(), v3(T(0.5), T(3.5), T(3.5)), v3(T(1), T(0), T(0)));
  REQUIRE_FALSE(h.hit);
  REQUIRE(h.t == T(0));
  REQUIRE(h.voxel == ivec3(-1));
}

TEMPLATE_TEST_CASE("DDA: t_max is a closed bound", "[visibility][dda]", float, double) {
  using T = TestType;
  using v3 = vplkit::vec3<T>;
  auto g = unit_grid<T>(8);
  g.set(ivec3(6, 0, 0));
  const v3 o(T(0.5), T(0.5), T(0.5)), d(T(1), T(0), T(0));
  REQUIRE(vplkit::dda_first_hit(g.view(), o, d, T(5.5)).hit);  // entered exactly at t_max
  REQUIRE_FALSE(vplkit::dda_first_hit(g.view(), o, d, T(5.49)).hit);
  REQUIRE_FALSE(vplkit::dda_first_hit(g.view(), o, d, T(0)).hit);
  REQUIRE_FALSE(vplkit::dda_first_hit(g.view(), o, d, T(-1)).hit);
  REQUIRE_FALSE(vplkit::dda_first_hit(g.view(), o, d, std::numeric_limits<T>::quiet_NaN()).hit);
  // t_max = 0 inside an occupied voxel still reports it (t = 0 <= t_max).
  REQUIRE(vplkit::dda_first_hit(g.view(), v3(T(6.5), T(0.5), T(0.5)), d, T(0)).hit);
  // Starting outside: t_max counts from the origin, not from the grid entry.
  const v3 far(T(-10), T(0.5), T(0.5));
  REQUIRE(vplkit::dda_first_hit(g.view(), far, d, T(16)).hit);
  REQUIRE(vplkit::dda_first_hit(g.view(), far, d, T(16)).t == Approx(16.0));
  REQUIRE_FALSE(vplkit::dda_first_hit(g.view(), far, d, T(15.9)).hit);
  REQUIRE_FALSE(vplkit::dda_first_hit(g.view(), far, d, T(9)).hit);  // never reaches the grid
}

TEMPLATE_TEST_CASE("DDA: the direction's length does not matter", "[visibility][dda]", float, double) {
  using T = TestType;
  using v3 = vplkit::vec3<T>;
  auto g = unit_grid<T>(16);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < 400; ++i) g.set(ivec3(int(u(rng) * 16), int(u(rng) * 16), int(u(rng) * 16)));
  for (int r = 0; r < 2000; ++r) {
    const v3 o(T(u(rng) * 20 - 2), T(u(rng) * 20 - 2), T(u(rng) * 20 - 2));
    const v3 d(T(u(rng) - 0.5), T(u(rng) - 0.5), T(u(rng) - 0.5));
    const auto ref = vplkit::dda_first_hit(g.view(), o, d);
    // Power-of-two scales keep the normalised direction bit-identical.
    for (T s : {T(std::ldexp(1.0, -60)), T(std::ldexp(1.0, 60)), T(0.125)}) {
      const auto h = vplkit::dda_first_hit(g.view(), o, d * s);
      REQUIRE(h.hit == ref.hit);
      REQUIRE(h.voxel == ref.voxel);
      REQUIRE(h.t == ref.t);
    }
    // Any other length: same voxel, same t up to rounding.
    const auto h = vplkit::dda_first_hit(g.view(), o, d * T(3.7));
    REQUIRE(h.hit == ref.hit);
    if (h.hit) REQUIRE(h.t == Approx(ref.t).margin(1e-4));
  }
}

TEMPLATE_TEST_CASE("DDA: the trace point is the entry point on the hit voxel's boundary", "[visibility][dda]", float,
                   double) {
  using T = TestType;
  using v3 = vplkit::vec3<T>;
  vplkit::voxel_grid<T> g(v3(T(-1), T(-2), T(0.5)), v3(T(3), T(1), T(2.5)), ivec3(20, 15, 10));
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  for (int i = 0; i < 300; ++i) g.set(ivec3(int(u(rng) * 20), int(u(rng) * 15), int(u(rng) * 10)));
  const v3 size = g.voxel_size();
  const T tol = T(1e-4) * g.voxel_length();
  int hits = 0;
  for (int r = 0; r < 3000; ++r) {
    const v3 o(T(-2 + 6 * u(rng)), T(-3 + 5 * u(rng)), T(0 + 3 * u(rng)));
    const v3 d(T(u(rng) - 0.5), T(u(rng) - 0.5), T(u(rng) - 0.5));
    const auto tr = vplkit::dda_trace_hit_point(g.view(), o, d);
    const auto h = vplkit::dda_first_hit(g.view(), o, d);
    REQUIRE(tr.hit == h.hit);
    if (!tr.hit) {
      REQUIRE(tr.point == o);
      continue;
    }
    ++hits;
    REQUIRE(tr.t == h.t);
    REQUIRE(tr.voxel == h.voxel);
    REQUIRE(glm::length(tr.point - o) == Approx(double(tr.t)).margin(1e-4));
    // Inside the hit voxel's closed box...
    const v3 lo = g.voxel_to_world(v3(tr.voxel)), hi = lo + size;
    for (int a = 0; a < 3; ++a) {
      REQUIRE(tr.point[a] >= lo[a] - tol);
      REQUIRE(tr.point[a] <= hi[a] + tol);
    }
    // ... and on its boundary unless the origin was inside it.
    if (tr.t > T(0)) {
      T nearest = std::numeric_limits<T>::max();
      for (int a = 0; a < 3; ++a) nearest = std::min(nearest, std::min(std::abs(tr.point[a] - lo[a]), std::abs(tr.point[a] - hi[a])));
      REQUIRE(nearest <= tol);
    }
  }
  CHECK(hits > 500);
}

TEST_CASE("DDA: a grid read back as raw words works through a view", "[visibility][dda]") {
  // Words a GPU pass would have written: voxel (3, 2, 1) of an 8^3 grid, flat index 3 + 16 + 64 = 83.
  std::vector<std::uint32_t> words(vplkit::voxel_word_count(ivec3(8)), 0u);
  words[83 >> 5] |= 1u << (83 & 31);
  const auto view = vplkit::make_voxel_grid_view(vplkit::vec3<float>(0.0f), vplkit::vec3<float>(1.0f), ivec3(8),
                                                 words.data(), words.size());
  const auto h = vplkit::dda_first_hit(view, vplkit::vec3<float>(0.01f, 0.3f, 0.2f), vplkit::vec3<float>(1, 0, 0));
  REQUIRE(h.hit);
  REQUIRE(h.voxel == ivec3(3, 2, 1));
  REQUIRE(h.t == Approx(0.375 - 0.01));
}
