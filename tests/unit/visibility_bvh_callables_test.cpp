// SPDX-License-Identifier: MIT
// The BVH visibility callables (include/vplkit/visibility/bvh_visibility.hpp) against the
// synthetic test scene's brute-force exact ray caster (tests/support/synthetic_scene.hpp), which
// the estimator tests use as ground truth: the exhaustive VPL sum with bvh_visibility equals the
// one with exact_visibility; pairwise answers and traced hit points agree except within the two
// implementations' different end-point offsets (2e-4 there, about 4e-4 here); traced points lie
// on the surface.
#include <synthetic_scene.hpp>

#include <vplkit/estimators/vpl_sum.hpp>
#include <vplkit/sampling/cosine_hemisphere.hpp>
#include <vplkit/sampling/orthonormal_basis.hpp>
#include <vplkit/sampling/rng.hpp>
#include <vplkit/visibility/bvh_build.hpp>
#include <vplkit/visibility/bvh_visibility.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <iostream>
#include <random>

namespace {

using v3f = vplkit::vec3<float>;

struct fixture {
  vplkit_test::synthetic_scene<float> scene;
  vplkit::bvh<float> bvh;
  fixture() : bvh(vplkit::build_bvh(scene.positions.data(), scene.positions.size(), scene.indices.data(), scene.indices.size())) {}

  // A random point on a random triangle, with that triangle's (room-facing) normal.
  void surface_point(std::mt19937& g, v3f& p, v3f& n) const {
    std::uniform_real_distribution<float> u01(0.0f, 1.0f);
    const int t = int(g() % std::uint32_t(scene.triangle_count()));
    float u = u01(g), v = u01(g);
    if (u + v > 1.0f) u = 1.0f - u, v = 1.0f - v;
    const v3f a = scene.positions[scene.indices[3 * t]], b = scene.positions[scene.indices[3 * t + 1]],
              c = scene.positions[scene.indices[3 * t + 2]];
    p = a + u * (b - a) + v * (c - a);
    n = scene.tri_normal[std::size_t(t)];
  }
};

}  // namespace

TEST_CASE("bvh callables: the exhaustive VPL sum with bvh_visibility equals the brute-force exact one") {
  const fixture f;
  const auto dprsm = f.scene.make_dprsm(32);
  const vplkit::bvh_visibility<float> bvh_vis{f.bvh.view()};
  const vplkit_test::exact_visibility<float> exact{&f.scene};
  const float dmin = 0.1f;
  for (const auto& g : f.scene.gather_points()) {
    const v3f a = vplkit::exhaustive_vpl_sum(g.gp, dprsm.view(), bvh_vis, dmin);
    const v3f b = vplkit::exhaustive_vpl_sum(g.gp, dprsm.view(), exact, dmin);
    const double rel = std::abs(double(a.x + a.y + a.z) - double(b.x + b.y + b.z)) / std::max(1e-30, double(b.x + b.y + b.z));
    std::cout << "  " << g.name << ": VPL sum (bvh) " << a.x << " " << a.y << " " << a.z << ", exact " << b.x << " "
              << b.y << " " << b.z << ", relative difference " << rel << "\n";
    CHECK(rel <= 2e-3);
    CHECK(b.x + b.y + b.z > 0.0f);
  }
}

TEST_CASE("bvh callables: pairwise visibility and traced hits agree with the brute-force ray caster") {
  const fixture f;
  const vplkit::bvh_visibility<float> vis{f.bvh.view()};
  const vplkit::bvh_tracer<float> trace{f.bvh.view()};
  std::mt19937 g(5);
  int pairs = 0, differ = 0, visible = 0;
  for (int i = 0; i < 20000; ++i) {
    v3f x, nx, y, ny;
    f.surface_point(g, x, nx);
    f.surface_point(g, y, ny);
    const bool a = vis(x, nx, y, ny), b = f.scene.visible(x, nx, y, ny);
    ++pairs;
    visible += a;
    differ += a != b;
  }
  std::cout << "  bvh_visibility vs brute force: " << pairs << " pairs, " << visible << " visible, " << differ
            << " differ (offset " << vplkit::bvh_surface_offset(f.bvh.view()) << " vs "
            << vplkit_test::synthetic_scene<float>::surface_epsilon() << ")\n";
  CHECK(double(differ) <= 1e-3 * pairs);
  CHECK(visible > pairs / 5);

  int rays = 0, hit_differ = 0, far = 0;
  double worst_plane = 0.0;
  for (int i = 0; i < 20000; ++i) {
    v3f x, n;
    f.surface_point(g, x, n);
    vplkit::counter_rng rng = vplkit::make_counter_rng(7u, std::uint32_t(i));
    const float u1 = vplkit::rng_next_float(rng), u2 = vplkit::rng_next_float(rng);
    const v3f local = vplkit::sample_cosine_hemisphere(vplkit::vec2<float>(u1, u2));
    const v3f dir = vplkit::to_world(vplkit::make_orthonormal_basis(n), local);
    const auto a = trace(x, n, dir);
    const auto b = f.scene.trace(x, n, dir);
    ++rays;
    hit_differ += a.hit != b.hit;
    if (!a.hit || !b.hit) continue;
    far += glm::length(a.position - b.position) > 1e-3f;
    // The traced point lies on a surface: the scene is made of axis-aligned boxes, so one of its
    // coordinates equals a wall's or a block face's coordinate.
    double to_plane = 1e30;
    for (int ax = 0; ax < 3; ++ax)
      for (const v3f& c : {f.scene.room_min(), f.scene.room_max(), f.scene.block_min(), f.scene.block_max()})
        to_plane = std::min(to_plane, std::abs(double(a.position[ax]) - double(c[ax])));
    worst_plane = std::max(worst_plane, to_plane);
  }
  std::cout << "  bvh_tracer vs brute force: " << rays << " rays, " << hit_differ << " hit/miss differ, " << far
            << " hit points more than 1e-3 apart; worst distance of a traced point to its surface " << worst_plane << "\n";
  CHECK(hit_differ == 0);  // a closed room
  CHECK(double(far) <= 1e-3 * rays);
  CHECK(worst_plane <= 1e-5);
}
