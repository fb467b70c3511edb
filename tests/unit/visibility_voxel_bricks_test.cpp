// SPDX-License-Identifier: MIT
// Unit tests of the brick level (include/vplkit/visibility/voxel_bricks.hpp): the brick words
// against brute force, dda_walk_leave_brick against stepping with dda_walk_next (the same state,
// bit for bit, including at exact edge and corner crossings, rays parallel to an axis, partial
// bricks and t_max inside a brick), and the triangle voxel queries with and without the brick level
// (the same answers, bit for bit).
#include <vplkit/visibility/dda.hpp>
#include <vplkit/visibility/triangle_voxel_query.hpp>
#include <vplkit/visibility/voxel_bricks.hpp>
#include <vplkit/visibility/voxel_grid.hpp>
#include <vplkit/visibility/voxelize_triangles.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

using vplkit::ivec3;

namespace {

template <class T>
bool same_bits(T a, T b) {
  return std::memcmp(&a, &b, sizeof(T)) == 0;
}

template <class T>
bool same_walk(const vplkit::dda_walk<T>& a, const vplkit::dda_walk<T>& b) {
  if (a.running != b.running) return false;
  if (!a.running) return true;  // an ended walk's other fields are never read
  return a.voxel == b.voxel && same_bits(a.t, b.t) && same_bits(a.t_next.x, b.t_next.x) &&
         same_bits(a.t_next.y, b.t_next.y) && same_bits(a.t_next.z, b.t_next.z);
}

ivec3 brick_of(ivec3 v) { return v / vplkit::voxel_brick_edge; }

// Rays that stress the walk's ties: origins and directions on a dyadic lattice (exact plane and
// corner crossings on a grid whose voxel edges are powers of two), directions with zero
// components, origins outside the grid, t_max inside the grid.
template <class T>
void random_ray(std::mt19937& rng, int kind, vplkit::vec3<T>& o, vplkit::vec3<T>& d, T& t_max) {
  std::uniform_real_distribution<double> u(-0.2, 1.2), s(-1.0, 1.0), w(0.0, 1.0);
  std::uniform_int_distribution<int> lattice(-2, 34), small(-2, 2);
  using v3 = vplkit::vec3<T>;
  if (kind % 3 == 0) {  // corners and edges of the lattice: exact ties
    o = v3(T(lattice(rng)), T(lattice(rng)), T(lattice(rng))) / T(32);
    d = v3(T(small(rng)), T(small(rng)), T(small(rng)));
    if (d == v3(T(0))) d = v3(T(1), T(1), T(1));
  } else {
    o = v3(T(u(rng)), T(u(rng)), T(u(rng)));
    d = v3(T(s(rng)), T(s(rng)), T(s(rng)));
    if (kind % 5 == 1) d.y = T(0);
    if (kind % 7 == 2) d.x = d.z = T(0);
  }
  t_max = kind % 4 == 0 ? T(w(rng) * 1.5) : std::numeric_limits<T>::infinity();
}

template <class T>
void check_leave_brick(ivec3 res) {
  std::vector<std::uint32_t> words(vplkit::voxel_word_count(res), 0u);
  // Bounds [0, 1]^3 on the 32-lattice: voxel planes at multiples of 1/32 for res 32.
  const vplkit::voxel_grid_view<T> g{vplkit::vec3<T>(T(0)), vplkit::vec3<T>(T(1)), res, words.data()};
  std::mt19937 rng(res.x * 131 + res.y * 17 + res.z);
  long jumps = 0, ended_inside = 0;
  for (int i = 0; i < 3000; ++i) {
    vplkit::vec3<T> o, d;
    T t_max;
    random_ray<T>(rng, i, o, d, t_max);
    vplkit::dda_walk<T> w = vplkit::dda_walk_begin(g, o, d, t_max);
    // At every voxel of the fine walk: the jump from here equals stepping out of the brick.
    for (int it = 0; w.running && it < vplkit::dda_max_iterations(res); ++it) {
      vplkit::dda_walk<T> jumped = w, stepped = w;
      vplkit::dda_walk_leave_brick(g, jumped);
      const ivec3 b = brick_of(w.voxel);
      while (stepped.running && brick_of(stepped.voxel) == b) vplkit::dda_walk_next(g, stepped);
      INFO("ray " << i << " from voxel (" << w.voxel.x << ", " << w.voxel.y << ", " << w.voxel.z << ")");
      REQUIRE(same_walk(jumped, stepped));
      ++jumps;
      ended_inside += jumped.running ? 0 : 1;
      vplkit::dda_walk_next(g, w);
    }
  }
  INFO("jumps " << jumps << ", walks ended inside a brick " << ended_inside);
  REQUIRE(jumps > 4000);
  REQUIRE(ended_inside > 1000);
}

template <class T>
struct mesh {
  std::vector<vplkit::vec3<T>> p;
  std::vector<std::uint32_t> idx;
};

template <class T>
mesh<T> random_mesh(std::mt19937& rng, int n) {
  std::uniform_real_distribution<double> u(0.0, 1.0), s(-0.15, 0.15);
  mesh<T> m;
  for (int i = 0; i < n; ++i) {
    const auto b = std::uint32_t(m.p.size());
    const double cx = u(rng), cy = u(rng), cz = u(rng);
    for (int k = 0; k < 3; ++k)
      m.p.push_back(vplkit::vec3<T>(T(cx + s(rng)), T(cy + s(rng)), T(cz + s(rng))));
    m.idx.insert(m.idx.end(), {b, b + 1, b + 2});
  }
  return m;
}

}  // namespace

TEST_CASE("voxel bricks: the brick words equal brute force", "[visibility][bricks]") {
  std::mt19937 rng(3);
  for (const ivec3 res : {ivec3(4), ivec3(13, 7, 9), ivec3(33, 1, 5), ivec3(32, 32, 32), ivec3(1, 1, 1)}) {
    vplkit::voxel_grid<float> grid(vplkit::vec3<float>(0.0f), vplkit::vec3<float>(1.0f), res);
    std::bernoulli_distribution sparse(0.01);
    for (int z = 0; z < res.z; ++z)
      for (int y = 0; y < res.y; ++y)
        for (int x = 0; x < res.x; ++x)
          if (sparse(rng)) grid.set(ivec3(x, y, z));
    grid.set(res - 1);  // the last voxel, in a partial brick for odd resolutions
    const auto v = grid.view();
    const std::vector<std::uint32_t> bricks = vplkit::voxel_brick_words(v);
    REQUIRE(bricks.size() == vplkit::voxel_brick_word_count(res));
    const ivec3 br = vplkit::voxel_brick_resolution(res);
    REQUIRE(br == (res + 3) / 4);
    for (int bz = 0; bz < br.z; ++bz)
      for (int by = 0; by < br.y; ++by)
        for (int bx = 0; bx < br.x; ++bx) {
          bool any = false;
          for (int z = 4 * bz; z < 4 * bz + 4; ++z)
            for (int y = 4 * by; y < 4 * by + 4; ++y)
              for (int x = 4 * bx; x < 4 * bx + 4; ++x) any = any || vplkit::voxel_test(v, ivec3(x, y, z));
          INFO("brick (" << bx << ", " << by << ", " << bz << ")");
          REQUIRE(vplkit::voxel_brick_occupied(res, bricks.data(), 4 * ivec3(bx, by, bz)) == any);
        }
    // Unused bits of the last word stay 0.
    const std::size_t n = std::size_t(br.x) * std::size_t(br.y) * std::size_t(br.z);
    if (n % 32 != 0) REQUIRE((bricks.back() >> (n % 32)) == 0u);
  }
}

TEMPLATE_TEST_CASE("voxel bricks: leaving a brick in one move equals stepping out of it", "[visibility][bricks]", float,
                   double) {
  check_leave_brick<TestType>(ivec3(32));          // cubic voxels on the dyadic lattice: exact ties
  check_leave_brick<TestType>(ivec3(13, 30, 7));   // partial bricks, unequal voxel edges
  check_leave_brick<TestType>(ivec3(3, 5, 2));     // smaller than a brick on two axes
}

TEMPLATE_TEST_CASE("voxel bricks: the triangle voxel queries give the same answers with and without the brick level",
                   "[visibility][bricks][triangle_voxels]", float, double) {
  using T = TestType;
  using v3 = vplkit::vec3<T>;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-0.1, 1.1);
  long visible = 0, hits = 0, n = 0;
  for (const ivec3 res : {ivec3(30, 26, 33), ivec3(64)}) {
    const mesh<T> m = random_mesh<T>(rng, 40);
    const auto grid = vplkit::voxelize_triangles(v3(T(-0.2)), v3(T(1.2)), res, m.p.data(), m.p.size(), m.idx.data(),
                                                 m.idx.size());
    const auto with = grid.view();
    auto without = with;
    without.bricks = nullptr;
    for (int i = 0; i < 4000; ++i) {
      const v3 x(T(u(rng)), T(u(rng)), T(u(rng)));
      const v3 y = i % 2 == 0 ? v3(T(u(rng)), T(u(rng)), T(u(rng))) : m.p[std::size_t(i) % m.p.size()];
      const bool a = vplkit::triangle_voxel_visible(with, x, y), b = vplkit::triangle_voxel_visible(without, x, y);
      REQUIRE(a == b);
      visible += a ? 1 : 0;
      const auto h1 = vplkit::triangle_voxel_first_hit(with, x, y - x);
      const auto h2 = vplkit::triangle_voxel_first_hit(without, x, y - x);
      REQUIRE(h1.hit == h2.hit);
      REQUIRE(h1.triangle == h2.triangle);
      REQUIRE(same_bits(h1.t, h2.t));
      hits += h1.hit ? 1 : 0;
      ++n;
    }
  }
  REQUIRE(visible > n / 10);
  REQUIRE(visible < n * 9 / 10);
  REQUIRE(hits > n / 10);
}
