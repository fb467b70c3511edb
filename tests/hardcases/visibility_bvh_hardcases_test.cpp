// SPDX-License-Identifier: MIT
// Hard cases of the BVH ray queries and visibility callables (include/vplkit/visibility/bvh_*.hpp),
// one TEST_CASE each: empty input, one triangle (exact answers), degenerate triangles,
// axis-parallel rays and rays along shared edges (exact t, watertight), rays in a triangle's
// plane, watertightness on closed meshes (with a naive float Moeller-Trumbore as the control that
// shows the test can fail), ray origins on a surface, power-of-two scaled scenes (bit-identical
// answers), scenes beyond the float range (misses, never false hits or NaN), invalid rays and
// ranges, and T = double.
#include <bvh_test_scenes.hpp>

#include <vplkit/visibility/bvh_build.hpp>
#include <vplkit/visibility/bvh_traverse.hpp>
#include <vplkit/visibility/bvh_visibility.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <iostream>
#include <limits>
#include <vector>

namespace {

using vplkit_test::random_source;
using vplkit_test::tri_mesh;
using vplkit_test::v3d;
using vplkit_test::v3f;

constexpr float inf = std::numeric_limits<float>::infinity();
constexpr float qnan = std::numeric_limits<float>::quiet_NaN();

vplkit::bvh<float> build(const tri_mesh& m) {
  return vplkit::build_bvh(m.positions.data(), m.positions.size(), m.indices.data(), m.indices.size());
}

bool finite_hit(const vplkit::bvh_hit<float>& h) {
  for (float x : {h.t, h.u, h.v, h.position.x, h.position.y, h.position.z, h.normal.x, h.normal.y, h.normal.z})
    if (!std::isfinite(x)) return false;
  return true;
}

// The axis-aligned room [-1, 1]^3 of 16 x 16 quads per face: every vertex is dyadic, so rays
// from dyadic points along the axes have exact answers.
tri_mesh axis_room() {
  tri_mesh m;
  m.box(v3d(0.0), v3d(1.0), glm::dmat3(1.0), 16, true);
  return m;
}

}  // namespace

TEST_CASE("bvh hard case: an empty hierarchy misses everything, the callables see no occluder") {
  const auto b = vplkit::build_bvh<float>(nullptr, 0, nullptr, 0);
  CHECK(b.empty());
  CHECK_FALSE(vplkit::bvh_closest_hit(b.view(), v3f(0.0f), v3f(1.0f, 0.0f, 0.0f)).hit);
  CHECK_FALSE(vplkit::bvh_occluded(b.view(), v3f(0.0f), v3f(1.0f, 0.0f, 0.0f)));
  CHECK(vplkit::bvh_surface_offset(b.view()) == 0.0f);
  CHECK(vplkit::bvh_visibility<float>{b.view()}(v3f(0.0f), v3f(0, 1, 0), v3f(1.0f), v3f(0, 1, 0)));
  CHECK_FALSE(vplkit::bvh_tracer<float>{b.view()}(v3f(0.0f), v3f(0, 1, 0), v3f(0, 1, 0)).hit);
}

TEST_CASE("bvh hard case: one triangle, exact t, barycentrics, position and normal, closed range ends") {
  tri_mesh m;
  m.tri(v3f(0, 0, 1), v3f(1, 0, 1), v3f(0, 1, 1));
  const auto b = build(m);
  const auto h = vplkit::bvh_closest_hit(b.view(), v3f(0.25f, 0.25f, 0.0f), v3f(0.0f, 0.0f, 1.0f));
  REQUIRE(h.hit);
  CHECK(h.t == 1.0f);
  CHECK(h.triangle == 0u);
  CHECK(h.u == 0.25f);
  CHECK(h.v == 0.25f);
  CHECK(h.position == v3f(0.25f, 0.25f, 1.0f));
  CHECK(h.normal == v3f(0.0f, 0.0f, 1.0f));
  // From behind (both windings), with a longer direction: t in units of |dir|.
  const auto back = vplkit::bvh_closest_hit(b.view(), v3f(0.25f, 0.5f, 3.0f), v3f(0.0f, 0.0f, -4.0f));
  REQUIRE(back.hit);
  CHECK(back.t == 0.5f);
  CHECK(back.normal == v3f(0.0f, 0.0f, 1.0f));  // geometric: from the winding, not facing the ray
  // (t_min, t_max]: open at t_min, closed at t_max.
  CHECK(vplkit::bvh_closest_hit(b.view(), v3f(0.25f, 0.25f, 0.0f), v3f(0, 0, 1), 0.0f, 1.0f).hit);
  CHECK_FALSE(vplkit::bvh_closest_hit(b.view(), v3f(0.25f, 0.25f, 0.0f), v3f(0, 0, 1), 0.0f, 0.99999994f).hit);
  CHECK_FALSE(vplkit::bvh_closest_hit(b.view(), v3f(0.25f, 0.25f, 0.0f), v3f(0, 0, 1), 1.0f, 2.0f).hit);
  CHECK(vplkit::bvh_closest_hit(b.view(), v3f(0.25f, 0.25f, 0.0f), v3f(0, 0, 1), 0.99999994f, 2.0f).hit);
  // Just outside each edge and just inside: closed triangle, exact edges.
  CHECK_FALSE(vplkit::bvh_occluded(b.view(), v3f(-1e-7f, 0.5f, 0.0f), v3f(0, 0, 1)));
  CHECK(vplkit::bvh_occluded(b.view(), v3f(0.0f, 0.5f, 0.0f), v3f(0, 0, 1)));    // on the edge x = 0
  CHECK(vplkit::bvh_occluded(b.view(), v3f(0.5f, 0.5f, 0.0f), v3f(0, 0, 1)));    // on the hypotenuse
  CHECK_FALSE(vplkit::bvh_occluded(b.view(), v3f(0.5f, 0.50000006f, 0.0f), v3f(0, 0, 1)));
  CHECK(vplkit::bvh_occluded(b.view(), v3f(1.0f, 0.0f, 0.0f), v3f(0, 0, 1)));    // through a vertex
}

TEST_CASE("bvh hard case: degenerate triangles (points, repeated vertices, collinear) never give NaN") {
  random_source rnd(41);
  tri_mesh m;
  const v3f p(0.3f, 0.2f, 0.1f), q(0.7f, 0.9f, 0.4f);
  m.tri(p, p, p);                                                     // a point
  m.tri(p, q, q);                                                     // repeated vertex
  m.tri(q, p, p);
  m.tri(v3f(0.0f), v3f(0.5f, 0.5f, 0.5f), v3f(1.0f, 1.0f, 1.0f));      // collinear, on the diagonal
  m.tri(p, 0.5f * (p + q), q);                                        // collinear (after rounding, nearly)
  const auto b = build(m);
  int exact_zero_hits = 0, collinear_hits = 0, far_hits = 0;
  for (int i = 0; i < 20000; ++i) {
    // Aim at a point of one of the degenerate shapes from a random direction.
    const int which = i % 3;
    const double s = rnd.unit();
    const v3d target = which == 0 ? v3d(p) : which == 1 ? v3d(p) + s * (v3d(q) - v3d(p)) : v3d(s, s, s);
    const v3d o = target + rnd.direction() * rnd.uniform(0.1, 2.0);
    const auto h = vplkit::bvh_closest_hit(b.view(), v3f(o), v3f(target - o));
    CHECK(finite_hit(h));
    if (!h.hit) continue;
    if (h.triangle <= 2) ++exact_zero_hits;
    else ++collinear_hits;
    // A reported hit lies on the segment the triangle collapses to, to rounding.
    const v3d a(h.triangle == 3 ? v3f(0.0f) : p), c(h.triangle == 3 ? v3f(1.0f) : q), x(h.position);
    const double along = glm::dot(x - a, c - a) / glm::dot(c - a, c - a);
    const double off = glm::length(x - (a + along * (c - a)));
    if (off > 1e-5 || along < -1e-5 || along > 1.0 + 1e-5) ++far_hits;
  }
  std::cout << "  degenerate: 20000 rays at their points/segments: " << exact_zero_hits
            << " hits on points / repeated vertices (must be 0), " << collinear_hits
            << " on collinear ones (allowed on the segment), " << far_hits << " off the segment\n";
  CHECK(exact_zero_hits == 0);
  CHECK(far_hits == 0);
  // Degenerate triangles mixed into a room change no hit on the room's own triangles.
  tri_mesh room = axis_room();
  const auto clean = build(room);
  const std::size_t room_triangles = room.triangle_count();
  for (std::size_t t = 0; t < m.triangle_count(); ++t) room.tri(m.vertex(t, 0), m.vertex(t, 1), m.vertex(t, 2));
  const auto mixed = build(room);
  int differ = 0;
  for (int i = 0; i < 5000; ++i) {
    const v3f o = rnd.point_in(v3d(-0.9), v3d(0.9));
    const v3f d(rnd.direction());
    const auto a = vplkit::bvh_closest_hit(clean.view(), o, d), c = vplkit::bvh_closest_hit(mixed.view(), o, d);
    REQUIRE(a.hit);
    REQUIRE(c.hit);
    if (c.triangle >= room_triangles) continue;  // it hit a collinear one on its segment
    differ += a.triangle != c.triangle || a.t != c.t;
  }
  CHECK(differ == 0);
}

TEST_CASE("bvh hard case: axis-parallel rays, also along shared edges and through vertices: exact t") {
  const tri_mesh m = axis_room();
  const auto b = build(m);
  random_source rnd(43);
  int n = 0;
  for (int i = 0; i < 3000; ++i) {
    // Dyadic origins; a third exactly on grid lines (multiples of 1/8: the walls' vertex lines).
    v3f o;
    for (int a = 0; a < 3; ++a)
      o[a] = i % 3 == 0 ? float(rnd.integer(-7, 7)) / 8.0f : float(rnd.integer(-1000, 1000)) / 1024.0f;
    const int axis = i % 3;
    const float sign = (i / 3) % 2 == 0 ? 1.0f : -1.0f;
    v3f d(0.0f);
    d[axis] = sign * (i % 5 == 0 ? 0.125f : 1.0f);  // scaled directions too
    const auto h = vplkit::bvh_closest_hit(b.view(), o, d);
    REQUIRE(h.hit);  // a closed room: every ray hits, on an edge or a vertex too
    const float expected = (sign > 0 ? 1.0f - o[axis] : o[axis] + 1.0f) / std::abs(d[axis]);
    CHECK(h.t == expected);
    CHECK(std::abs(h.position[axis] - sign) <= 1e-6f);  // w v0 + u v1 + v v2 rounds
    ++n;
  }
  std::cout << "  " << n << " axis-parallel rays, all hit with exact t\n";
}

TEST_CASE("bvh hard case: rays in a triangle's plane pass it (det = 0) and hit the wall they reach") {
  const tri_mesh m = axis_room();
  const auto b = build(m);
  random_source rnd(47);
  for (int i = 0; i < 2000; ++i) {
    // On the floor y = -1, moving within it.
    const v3f o(float(rnd.uniform(-0.9, 0.9)), -1.0f, float(rnd.uniform(-0.9, 0.9)));
    const v3d dd = rnd.direction();
    const v3f d(float(dd.x), 0.0f, float(dd.z));
    const auto h = vplkit::bvh_closest_hit(b.view(), o, d);
    CHECK(finite_hit(h));
    REQUIRE(h.hit);  // the wall it runs into (the floor's own triangles are parallel to it)
    CHECK(std::abs(h.normal.y) == 0.0f);
    CHECK(std::abs(h.position.y + 1.0f) <= 1e-6f);
  }
}

TEST_CASE("bvh hard case: watertight on closed meshes, a naive float Moeller-Trumbore leaks") {
  // A closed rotated box and the closed room; rays from inside aimed exactly at vertices and at
  // edge midpoints (the places a non-watertight test lets rays through), and random rays.
  tri_mesh box;
  box.box(v3d(0.1, -0.2, 0.3), v3d(0.7, 0.5, 0.6), vplkit_test::rotation(0.3, 0.9, -0.4), 8);
  const tri_mesh room = axis_room();
  random_source rnd(53);
  for (const tri_mesh* m : std::vector<const tri_mesh*>{&box, &room}) {
    const auto b = build(*m);
    const v3d centre = m == &box ? v3d(0.1, -0.2, 0.3) : v3d(0.0);
    int rays = 0, misses = 0, naive_misses = 0;
    for (int i = 0; i < 30000; ++i) {
      const v3f o(centre + rnd.uniform(0.0, 0.4) * rnd.direction());
      const std::size_t t = std::size_t(rnd.integer(0, int(m->triangle_count()) - 1));
      const int k = rnd.integer(0, 2);
      v3f target;
      if (i % 3 == 0) target = m->vertex(t, k);                                         // a vertex
      else if (i % 3 == 1) target = 0.5f * (m->vertex(t, k) + m->vertex(t, (k + 1) % 3));  // an edge
      else target = o + v3f(rnd.direction());
      const v3f d = target - o;
      ++rays;
      misses += !vplkit::bvh_occluded(b.view(), o, d);
      if (i >= 3000) continue;  // the control is brute force: 3000 rays are plenty
      // The control: Moeller-Trumbore in float with strict inequalities, no epsilon.
      bool naive = false;
      for (std::size_t s = 0; s < m->triangle_count() && !naive; ++s) {
        const v3f e1 = m->vertex(s, 1) - m->vertex(s, 0), e2 = m->vertex(s, 2) - m->vertex(s, 0);
        const v3f p = glm::cross(d, e2);
        const float det = glm::dot(e1, p);
        if (det == 0.0f) continue;
        const v3f q = o - m->vertex(s, 0);
        const float u = glm::dot(q, p) / det;
        const v3f r = glm::cross(q, e1);
        const float v = glm::dot(d, r) / det;
        naive = u > 0.0f && v > 0.0f && u + v < 1.0f && glm::dot(e2, r) / det > 0.0f;
      }
      naive_misses += !naive;
    }
    std::cout << "  closed " << (m == &box ? "rotated box" : "room") << ": " << rays << " rays from inside, "
              << misses << " escape the BVH test; of the first 3000, " << naive_misses
              << " escape a naive float Moeller-Trumbore\n";
    CHECK(misses == 0);
    CHECK(naive_misses > 0);  // the test can fail: it catches a leaking intersector
  }
}

TEST_CASE("bvh hard case: ray origins on a surface, and why the callables move them off it") {
  const tri_mesh m = axis_room();
  const auto b = build(m);
  // Exactly on the floor: its own triangle is at t = 0, outside (0, t_max].
  const auto up = vplkit::bvh_closest_hit(b.view(), v3f(0.3f, -1.0f, 0.2f), v3f(0, 1, 0));
  REQUIRE(up.hit);
  CHECK(up.t == 2.0f);
  CHECK_FALSE(vplkit::bvh_closest_hit(b.view(), v3f(0.3f, -1.0f, 0.2f), v3f(0, -1, 0)).hit);

  // A tilted plane: points made by barycentric interpolation lie off it by rounding, so raw
  // segments between two of them hit the plane itself (self-intersection) at grazing angles; the
  // callables' normal offset removes every such hit at every angle.
  tri_mesh plane;
  plane.grid(v3d(-1, -0.3, -1), v3d(2, 0.7, 0.1), v3d(0.2, 0.5, 2), 32);
  const auto pb = build(plane);
  const v3f n(glm::normalize(glm::cross(v3d(2, 0.7, 0.1), v3d(0.2, 0.5, 2))));
  random_source rnd(59);
  auto on_plane = [&]() {
    const std::size_t t = std::size_t(rnd.integer(0, int(plane.triangle_count()) - 1));
    double u = rnd.unit(), v = rnd.unit();
    if (u + v > 1) u = 1 - u, v = 1 - v;
    return (1.0f - float(u) - float(v)) * plane.vertex(t, 0) + float(u) * plane.vertex(t, 1) + float(v) * plane.vertex(t, 2);
  };
  int raw_self_hits = 0, callable_blocked = 0, flipped_visible = 0;
  for (int i = 0; i < 20000; ++i) {
    const v3f x = on_plane(), y = on_plane();
    raw_self_hits += vplkit::bvh_occluded(pb.view(), x, y - x, 0.0f, 1.0f);
    callable_blocked += !vplkit::bvh_visible(pb.view(), x, n, y, n);
    callable_blocked += !vplkit::bvh_visible(pb.view(), x, -0.5f * n, y, -3.0f * n);  // either side, any length
    // Normals on opposite sides put the ends on opposite sides of the plane: hidden, as the
    // normals say (a point seen from below is behind one seen from above).
    flipped_visible += vplkit::bvh_visible(pb.view(), x, -n, y, n);
  }
  std::cout << "  coplanar pairs on a tilted plane: " << raw_self_hits << " of 20000 raw segments hit the plane itself; "
            << callable_blocked << " of 40000 callable answers are 'blocked'\n";
  CHECK(raw_self_hits > 0);  // the hazard is real
  CHECK(callable_blocked == 0);
  CHECK(flipped_visible == 0);
  // x == y, zero / non-finite normals, non-finite points.
  const v3f x = on_plane();
  CHECK(vplkit::bvh_visible(pb.view(), x, n, x, n));
  CHECK(vplkit::bvh_visible(pb.view(), x + n, v3f(0.0f), x + 2.0f * n, v3f(qnan)));
  CHECK_FALSE(vplkit::bvh_visible(pb.view(), v3f(qnan, 0, 0), n, x, n));
  CHECK_FALSE(vplkit::bvh_visible(pb.view(), x, n, v3f(0, inf, 0), n));
  CHECK_FALSE(vplkit::bvh_trace(pb.view(), v3f(qnan, 0, 0), n, n).hit);
}

TEST_CASE("bvh hard case: scenes scaled by 2^40 and 2^-40 give bit-identical answers") {
  random_source rnd(61);
  tri_mesh m = vplkit_test::random_soup(rnd, 800, 1e-2, 0.3);
  const auto b = build(m);
  for (float scale : {1099511627776.0f, 9.094947e-13f}) {  // 2^40, 2^-40
    REQUIRE(std::ldexp(1.0f, scale > 1.0f ? 40 : -40) == scale);
    tri_mesh s = m;
    for (v3f& p : s.positions) p *= scale;
    const auto bs = build(s);
    int hits = 0, differ = 0;
    for (int i = 0; i < 4000; ++i) {
      const v3f o = rnd.point_in(v3d(-0.2), v3d(1.2)), d(rnd.direction());
      const auto a = vplkit::bvh_closest_hit(b.view(), o, d);
      const auto c = vplkit::bvh_closest_hit(bs.view(), o * scale, d * scale);
      hits += a.hit;
      differ += a.hit != c.hit || a.triangle != c.triangle || a.t != c.t || a.u != c.u || a.v != c.v ||
                a.position * scale != c.position || a.normal != c.normal;
      differ += vplkit::bvh_occluded(b.view(), o, d, 0.0f, 0.5f) != vplkit::bvh_occluded(bs.view(), o * scale, d, 0.0f, 0.5f * scale);
    }
    std::cout << "  scale " << scale << ": 4000 rays, " << hits << " hits, " << differ << " answers differ from scale 1\n";
    CHECK(differ == 0);
    CHECK(hits > 400);
  }
}

TEST_CASE("bvh hard case: beyond the float range (2^60, 1e30) hits are lost, never invented, never NaN") {
  random_source rnd(67);
  const tri_mesh m = vplkit_test::random_soup(rnd, 300, 1e-2, 0.3);
  for (double scale : {1152921504606846976.0, 1e30}) {  // 2^60, 1e30
    tri_mesh s = m;
    for (v3f& p : s.positions) p = v3f(v3d(p) * scale);
    const auto b = build(s);  // areas in double: the build itself is fine
    CHECK(vplkit::validate_bvh(b.view()) == b.depth());
    int hits = 0, bad = 0, nonfinite = 0;
    for (int i = 0; i < 2000; ++i) {
      const v3f o(v3d(rnd.point_in(v3d(-0.2), v3d(1.2))) * scale), d(rnd.direction());
      const auto h = vplkit::bvh_closest_hit(b.view(), o, d);
      nonfinite += !finite_hit(h);
      if (!h.hit) continue;
      ++hits;
      const auto ref = vplkit_test::reference_closest(s, o, d, 0.0, INFINITY, 1e-5, 1.4 * scale);
      bad += !ref.acceptable(true, int(h.triangle));
    }
    std::cout << "  scale " << scale << ": 2000 rays, " << hits << " hits, " << bad << " of them wrong, "
              << nonfinite << " non-finite results\n";
    CHECK(bad == 0);
    CHECK(nonfinite == 0);
  }
}

TEST_CASE("bvh hard case: invalid rays and ranges give no hit") {
  tri_mesh m;
  m.tri(v3f(-1, -1, 1), v3f(1, -1, 1), v3f(0, 1, 1));
  const auto b = build(m);
  const v3f o(0.0f), d(0, 0, 1);
  for (v3f bad_o : {v3f(qnan, 0, 0), v3f(0, inf, 0), v3f(0, 0, -inf)}) CHECK_FALSE(vplkit::bvh_closest_hit(b.view(), bad_o, d).hit);
  for (v3f bad_d : {v3f(0.0f), v3f(-0.0f), v3f(0, 0, 1e-40f), v3f(qnan, 0, 1), v3f(0, inf, 1)})
    CHECK_FALSE(vplkit::bvh_closest_hit(b.view(), o, bad_d).hit);
  CHECK(vplkit::bvh_closest_hit(b.view(), o, v3f(1e-40f, 0, 1)).hit);  // a denormal component is read as 0
  CHECK_FALSE(vplkit::bvh_occluded(b.view(), o, d, 0.0f, qnan));
  CHECK_FALSE(vplkit::bvh_occluded(b.view(), o, d, 2.0f, 1.5f));
  CHECK(vplkit::bvh_occluded(b.view(), o, d, -5.0f, 2.0f));  // t_min < 0 reads as 0
  CHECK(vplkit::bvh_occluded(b.view(), o, d, qnan, 2.0f));    // so does NaN
  CHECK_FALSE(vplkit::bvh_occluded(b.view(), v3f(0, 0, 2), d, -5.0f, inf));  // never behind the origin
}

TEST_CASE("bvh hard case: T = double builds and traverses, it agrees with float up to edge and tie cases") {
  const tri_mesh m = vplkit_test::closed_room();
  std::vector<v3d> pd(m.positions.begin(), m.positions.end());
  const auto bd = vplkit::build_bvh(pd.data(), pd.size(), m.indices.data(), m.indices.size());
  const auto bf = build(m);
  random_source rnd(71);
  int same = 0, both_ok = 0, wrong = 0;
  for (int i = 0; i < 3000; ++i) {
    const v3f o = rnd.point_in(v3d(-0.95), v3d(0.95)), d(rnd.direction());
    const auto hd = vplkit::bvh_closest_hit(bd.view(), v3d(o), v3d(d));
    const auto hf = vplkit::bvh_closest_hit(bf.view(), o, d);
    REQUIRE(hd.hit);
    REQUIRE(hf.hit);
    if (hd.triangle == hf.triangle) {
      ++same;
      CHECK(std::abs(hd.t - double(hf.t)) <= 1e-5 * (1.0 + hd.t));
      continue;
    }
    const auto ref = vplkit_test::reference_closest(m, o, d, 0.0, INFINITY, 1e-5, 2.0);
    if (ref.acceptable(true, int(hd.triangle)) && ref.acceptable(true, int(hf.triangle))) ++both_ok;
    else ++wrong;
  }
  std::cout << "  double vs float: 3000 rays, " << same << " same triangle, " << both_ok << " edge/tie cases, " << wrong
            << " wrong\n";
  CHECK(wrong == 0);
}
