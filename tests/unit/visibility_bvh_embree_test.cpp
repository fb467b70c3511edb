// SPDX-License-Identifier: MIT
// The C++ BVH (include/vplkit/visibility/bvh_*.hpp) against Embree 3 (robust mode) on the same
// triangle arrays: closest hits on random soups and on a closed room, occlusion of random
// segments, and the visibility callable with Embree behind the same end-point offsets.
//
// What must agree, and what may not:
// - Both answers are judged by an independent double-precision reference (bvh_test_scenes.hpp,
//   eps = 1e-5 of the scene's size): a ray passing within eps of a triangle's edge may hit or
//   miss it, and a triangle hit within eps of the closest hit may be reported instead of it. Where
//   vplkit and Embree differ, both answers must be acceptable to the reference (a "tie"); a
//   difference that is not a tie fails. The ties are counted and printed, and bounded.
// - Where both report the same triangle, t agrees within |dt| |d| <= 1e-5 * scene size (both
//   compute t in float from the same vertices by different formulas; the worst case is printed).
// - vplkit's answer alone is also checked against the reference on a subset of rays (the
//   reference is brute force).
#include <bvh_test_scenes.hpp>
#include <embree_scene.hpp>

#include <vplkit/visibility/bvh_build.hpp>
#include <vplkit/visibility/bvh_traverse.hpp>
#include <vplkit/visibility/bvh_visibility.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

namespace {

using vplkit_test::random_source;
using vplkit_test::tri_mesh;
using vplkit_test::v3d;
using vplkit_test::v3f;

constexpr double eps = 1e-5;

struct ray_case {
  v3f o, d;
  float t_max;
};

// Origins in and around [lo, hi], directions of any length, a third with a finite t_max, some
// along an axis or in an axis plane.
std::vector<ray_case> random_rays(random_source& rnd, int n, v3d lo, v3d hi) {
  std::vector<ray_case> rays;
  const v3d pad = 0.2 * (hi - lo);
  for (int i = 0; i < n; ++i) {
    ray_case r;
    r.o = rnd.point_in(lo - pad, hi + pad);
    r.d = v3f(rnd.direction() * std::pow(10.0, rnd.uniform(-2.0, 2.0)));
    if (i % 17 == 0) r.d[rnd.integer(0, 2)] = 0.0f;
    if (i % 23 == 0) {
      const int a = rnd.integer(0, 2);
      r.d = v3f(0.0f);
      r.d[a] = rnd.unit() < 0.5 ? -1.0f : 1.0f;
    }
    const double len = std::sqrt(glm::dot(v3d(r.d), v3d(r.d)));
    r.t_max = i % 3 == 0 ? float(rnd.uniform(0.0, 1.5) * glm::length(hi - lo) / len) : INFINITY;
    rays.push_back(r);
  }
  return rays;
}

struct tally {
  std::size_t rays = 0, hits = 0, same = 0, ties = 0, wrong = 0, checked = 0, ours_wrong = 0;
  double worst_dt = 0.0;  // |dt| |d| / scene size, same triangle
  std::string first_wrong;
};

void compare_closest(const tri_mesh& m, const vplkit::bvh<float>& b, const vplkit_test::embree_scene& e,
                     const std::vector<ray_case>& rays, std::size_t reference_every, tally& s) {
  const double scale = vplkit_test::mesh_scale(m);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    const ray_case& r = rays[i];
    const auto ours = vplkit::bvh_closest_hit(b.view(), r.o, r.d, 0.0f, r.t_max);
    const auto theirs = e.intersect(r.o, r.d, 0.0f, r.t_max);
    ++s.rays;
    s.hits += ours.hit;
    if (i % reference_every == 0) {
      ++s.checked;
      const auto ref = vplkit_test::reference_closest(m, r.o, r.d, 0.0, r.t_max, eps, scale);
      s.ours_wrong += !ref.acceptable(ours.hit, int(ours.triangle));
    }
    if (ours.hit == theirs.hit && (!ours.hit || ours.triangle == theirs.triangle)) {
      ++s.same;
      if (ours.hit) {
        const double dt = std::abs(double(ours.t) - double(theirs.t)) * std::sqrt(glm::dot(v3d(r.d), v3d(r.d))) / scale;
        s.worst_dt = std::max(s.worst_dt, dt);
      }
      continue;
    }
    const auto ref = vplkit_test::reference_closest(m, r.o, r.d, 0.0, r.t_max, eps, scale);
    if (ref.acceptable(ours.hit, int(ours.triangle)) && ref.acceptable(theirs.hit, int(theirs.triangle))) {
      ++s.ties;
    } else {
      if (s.wrong == 0)
        s.first_wrong = "ray " + std::to_string(i) + ": vplkit " + (ours.hit ? std::to_string(ours.triangle) : "miss") +
                        ", Embree " + (theirs.hit ? std::to_string(theirs.triangle) : "miss") + ", reference " +
                        (ref.sure >= 0 ? std::to_string(ref.sure) : "miss");
      ++s.wrong;
    }
  }
}

void report(const char* what, const tally& s, double max_tie_fraction) {
  std::cout << "  " << what << ": " << s.rays << " rays, " << s.hits << " hits; vplkit = Embree on " << s.same
            << ", ties " << s.ties << ", wrong " << s.wrong << "; worst |dt| |d| / size on equal triangles "
            << s.worst_dt << "; vplkit vs the double reference: " << s.ours_wrong << " wrong of " << s.checked << "\n";
  INFO(s.first_wrong);
  CHECK(s.wrong == 0);
  CHECK(s.ours_wrong == 0);
  CHECK(s.worst_dt <= 1e-5);
  CHECK(double(s.ties) <= max_tie_fraction * double(s.rays));
}

}  // namespace

TEST_CASE("bvh vs Embree: closest hits on random triangle soups") {
  random_source rnd(101);
  const std::vector<tri_mesh> soups = {vplkit_test::random_soup(rnd, 2000, 1e-3, 0.2),
                                       vplkit_test::random_soup(rnd, 500, 0.05, 1.5),
                                       vplkit_test::random_soup(rnd, 4000, 1e-4, 0.02)};
  tally all;
  for (const tri_mesh& m : soups) {
    const auto b = vplkit::build_bvh(m.positions.data(), m.positions.size(), m.indices.data(), m.indices.size());
    const vplkit_test::embree_scene e(m.positions.data(), m.positions.size(), m.indices.data(), m.indices.size());
    compare_closest(m, b, e, random_rays(rnd, 10000, v3d(0.0), v3d(1.0)), 20, all);
  }
  report("random soups (2000, 500, 4000 triangles)", all, 0.005);
  CHECK(all.hits > all.rays / 5);
}

TEST_CASE("bvh vs Embree: closest hits in a closed room, rays aimed at shared vertices and edges") {
  const tri_mesh m = vplkit_test::closed_room();
  const auto b = vplkit::build_bvh(m.positions.data(), m.positions.size(), m.indices.data(), m.indices.size());
  const vplkit_test::embree_scene e(m.positions.data(), m.positions.size(), m.indices.data(), m.indices.size());
  random_source rnd(103);
  std::vector<ray_case> rays;
  for (int i = 0; i < 6000; ++i) {
    const v3f o = rnd.point_in(v3d(-0.98), v3d(0.98));
    const std::size_t t = std::size_t(rnd.integer(0, int(m.triangle_count()) - 1));
    const int k = rnd.integer(0, 2);
    v3f target = o + v3f(rnd.direction());
    if (i % 3 == 0) target = m.vertex(t, k);
    if (i % 3 == 1) target = 0.5f * (m.vertex(t, k) + m.vertex(t, (k + 1) % 3));
    rays.push_back({o, target - o, INFINITY});
  }
  tally s;
  compare_closest(m, b, e, rays, 10, s);
  // Two thirds of the rays are aimed at a shared vertex or edge: ties by design.
  report("closed room (2/3 of the rays aimed at shared vertices and edges)", s, 0.5);
  CHECK(s.hits == s.rays);  // closed: every ray hits (the BVH is watertight)
}

TEST_CASE("bvh vs Embree: occlusion of random segments") {
  random_source rnd(107);
  const tri_mesh room = vplkit_test::closed_room();
  const tri_mesh soup = vplkit_test::random_soup(rnd, 1500, 1e-3, 0.3);
  std::size_t segments = 0, occluded = 0, same = 0, ties = 0, wrong = 0;
  for (const tri_mesh* m : std::vector<const tri_mesh*>{&room, &soup}) {
    const auto b = vplkit::build_bvh(m->positions.data(), m->positions.size(), m->indices.data(), m->indices.size());
    const vplkit_test::embree_scene e(m->positions.data(), m->positions.size(), m->indices.data(), m->indices.size());
    const double scale = vplkit_test::mesh_scale(*m);
    const v3d lo = m == &room ? v3d(-0.99) : v3d(0.0), hi = m == &room ? v3d(0.99) : v3d(1.0);
    for (int i = 0; i < 10000; ++i) {
      const v3f p = rnd.point_in(lo, hi), q = rnd.point_in(lo, hi);
      const bool ours = vplkit::bvh_occluded(b.view(), p, q - p, 0.0f, 1.0f);
      const bool theirs = e.occluded(p, q - p, 0.0f, 1.0f);
      ++segments;
      occluded += ours;
      if (ours == theirs) {
        ++same;
        continue;
      }
      const auto ref = vplkit_test::reference_closest(*m, p, q - p, 0.0, 1.0, eps, scale);
      const bool occluded_ok = !ref.miss_ok || !ref.candidates.empty();
      if (ref.miss_ok && occluded_ok) ++ties;
      else ++wrong;
    }
  }
  std::cout << "  occlusion: " << segments << " segments, " << occluded << " occluded; vplkit = Embree on " << same
            << ", ties " << ties << ", wrong " << wrong << "\n";
  CHECK(wrong == 0);
  CHECK(double(ties) <= 0.005 * double(segments));
  CHECK(occluded > segments / 10);
  CHECK(occluded < segments * 9 / 10);
}

TEST_CASE("bvh_visibility vs Embree behind the same end-point offsets") {
  // Pairs of surface points of the closed room with their normals; Embree tests the segment
  // between the very points bvh_visible tests, so any difference is the intersectors'.
  const tri_mesh m = vplkit_test::closed_room();
  const auto b = vplkit::build_bvh(m.positions.data(), m.positions.size(), m.indices.data(), m.indices.size());
  const vplkit_test::embree_scene e(m.positions.data(), m.positions.size(), m.indices.data(), m.indices.size());
  const float offset = vplkit::bvh_surface_offset(b.view());
  random_source rnd(109);
  auto surface_point = [&](v3f& p, v3f& n) { vplkit_test::random_surface_point(rnd, m, p, n, 0.5, 4.0); };
  std::size_t pairs = 0, visible = 0, same = 0, ties = 0, wrong = 0;
  for (int i = 0; i < 20000; ++i) {
    v3f x, nx, y, ny;
    surface_point(x, nx);
    surface_point(y, ny);
    const bool ours = vplkit::bvh_visibility<float>{b.view()}(x, nx, y, ny);
    const v3f o = vplkit::bvh_offset_point(x, nx, offset), p = vplkit::bvh_offset_point(y, ny, offset);
    const bool theirs = !e.occluded(o, p - o, 0.0f, 1.0f);
    ++pairs;
    visible += ours;
    if (ours == theirs) {
      ++same;
      continue;
    }
    const auto ref = vplkit_test::reference_closest(m, o, p - o, 0.0, 1.0, eps, 2.0);
    if (ref.miss_ok && (!ref.candidates.empty())) ++ties;
    else ++wrong;
  }
  std::cout << "  bvh_visibility: " << pairs << " surface point pairs, " << visible << " visible; vplkit = Embree on "
            << same << ", ties " << ties << ", wrong " << wrong << " (offset " << offset << ")\n";
  CHECK(wrong == 0);
  CHECK(double(ties) <= 0.005 * double(pairs));
  CHECK(visible > pairs / 10);
  CHECK(visible < pairs * 9 / 10);
}
