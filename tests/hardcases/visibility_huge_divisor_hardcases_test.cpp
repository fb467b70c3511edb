// SPDX-License-Identifier: MIT
// Hard cases of huge divisors in the BVH and DDA queries (include/vplkit/visibility/bvh_ray.hpp,
// bvh_traverse.hpp, dda.hpp): directions and normals with components near FLT_MAX, between 2^126
// and 2^128, mixed with denormal and zero ones, and a triangle whose edge-function sum (det)
// exceeds 2^126.
// GLSL bounds x / y only for |y| in [2^-126, 2^126], and NVIDIA divides as x * (1 / y) with the
// reciprocal flushed to 0 above 2^126, so a division by a huge value gives 0, and a later division
// by that 0 gives 0 * inf = NaN. The library scales such divisors by 1/4 first. Each case runs the
// templates twice: IEEE float, and T = gpu_float under reciprocal_division_scope
// (tests/support/gpu_model_float.hpp), the CPU model of NVIDIA's division, which reproduces the
// hazard without a GPU: without the scaling, the model's unit vectors are NaN and its rays miss.
#include <bvh_gpu_model.hpp>
#include <bvh_test_scenes.hpp>
#include <gpu_model_float.hpp>

#include <vplkit/visibility/bvh_build.hpp>
#include <vplkit/visibility/bvh_traverse.hpp>
#include <vplkit/visibility/bvh_visibility.hpp>
#include <vplkit/visibility/dda.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

namespace {

using vplkit_test::gpu_float;
using vplkit_test::random_source;
using vplkit_test::tri_mesh;
using vplkit_test::v3d;
using vplkit_test::v3f;
using v3g = vplkit::vec3<gpu_float>;

constexpr float flt_max = std::numeric_limits<float>::max();
constexpr float flt_min = std::numeric_limits<float>::min();
const float two_126 = std::ldexp(1.0f, 126);
const float two_127 = std::ldexp(1.0f, 127);

using model_bvh = vplkit_test::gpu_model_bvh;
v3g to_model(v3f v) { return vplkit_test::to_gpu_model(v); }
v3f of_model(v3g v) { return vplkit_test::of_gpu_model(v); }

std::string show(v3f v) {
  char b[128];
  std::snprintf(b, sizeof b, "(%.9g, %.9g, %.9g)", double(v.x), double(v.y), double(v.z));
  return b;
}

bool finite(v3f v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

// The double reference of v / |v| (v finite): scaled by its largest component first.
v3d unit_reference(v3f v) {
  const v3d d(v);
  const double m = std::fmax(std::fabs(d.x), std::fmax(std::fabs(d.y), std::fabs(d.z)));
  const v3d s = d / m;
  return s / std::sqrt(glm::dot(s, s));
}

// Directions and normals whose largest component lies above 2^126 (the scaling fires), at 2^126
// (it does not), with denormal, zero and normal components beside it.
std::vector<v3f> huge_vectors() {
  const float denormal = 1e-40f;
  const float above = std::nextafter(two_126, flt_max);
  return {v3f(flt_max, flt_max, flt_max),  v3f(-flt_max, 0.0f, 0.0f),       v3f(0.0f, 0.0f, flt_max),
          v3f(two_127, -two_126, 3.0f),     v3f(above, 1.0f, 0.0f),          v3f(two_126, two_126, -two_126),
          v3f(flt_max, denormal, -flt_min), v3f(1.5f * two_127, 1e-45f, 1e20f), v3f(3e38f, -3e38f, 1e38f),
          v3f(denormal, -two_127, 0.0f),    v3f(-1e38f, 2e38f, -0.5f * flt_max)};
}

vplkit::bvh<float> build(const tri_mesh& m) {
  return vplkit::build_bvh(m.positions.data(), m.positions.size(), m.indices.data(), m.indices.size());
}

}  // namespace

TEST_CASE("huge divisor hard case: unit vectors of directions and normals up to FLT_MAX, also under NVIDIA's division") {
  for (const v3f v : huge_vectors()) {
    INFO("v = " << show(v));
    const v3d ref = unit_reference(v);
    const v3f ieee = vplkit::detail::bvh_unit_vector(v);
    v3f model;
    v3f dda_ieee, dda_model;
    bool dda_ok_ieee, dda_ok_model;
    {
      const vplkit_test::reciprocal_division_scope nvidia;
      model = of_model(vplkit::detail::bvh_unit_vector(to_model(v)));
      v3g d(gpu_float(0.0f));
      dda_ok_model = vplkit::dda_unit_direction(to_model(v), d);
      dda_model = of_model(d);
    }
    dda_ok_ieee = vplkit::dda_unit_direction(v, dda_ieee);
    INFO("bvh_unit_vector: IEEE " << show(ieee) << ", NVIDIA model " << show(model));
    INFO("dda_unit_direction: IEEE " << show(dda_ieee) << ", NVIDIA model " << show(dda_model));
    REQUIRE(finite(ieee));
    REQUIRE(finite(model));
    CHECK(dda_ok_ieee);
    CHECK(dda_ok_model);
    REQUIRE(finite(dda_model));
    for (int k = 0; k < 3; ++k) {
      // Two divisions and a square root of at most a few ulps each, on unit-sized values; the
      // DDA flushes components below FLT_MIN to 0.
      CHECK(std::fabs(double(ieee[k]) - ref[k]) <= 4e-7);
      CHECK(std::fabs(double(model[k]) - ref[k]) <= 8e-7);
      CHECK(std::fabs(double(dda_ieee[k]) - ref[k]) <= 4e-7);
      CHECK(std::fabs(double(dda_model[k]) - ref[k]) <= 8e-7);
    }
  }
}

TEST_CASE("huge divisor hard case: make_bvh_ray scales a direction by 1/4 exactly when a component exceeds 2^126") {
  // At or below 2^126 the ray keeps the direction as given (t_scale 1: the arithmetic of every
  // query is the unguarded one); above it, the direction / 4 and t_scale 4.
  const float above = std::nextafter(two_126, flt_max);
  for (const v3f v : {v3f(two_126, -two_126, 1.0f), v3f(0.5f, -two_126, 3.0f), v3f(1e-30f, 2.0f, -two_126),
                      v3f(1.0f, 0.0f, 0.0f)}) {
    INFO("v = " << show(v));
    const auto r = vplkit::make_bvh_ray(v3f(0.0f), v);
    CHECK(r.valid);
    CHECK(r.t_scale == 1.0f);
    CHECK(r.dir == v);
  }
  for (const v3f v : {v3f(above, 1.0f, 0.0f), v3f(-1.0f, -flt_max, 2.0f), v3f(3.0f, 2.0f, -two_127)}) {
    INFO("v = " << show(v));
    const auto r = vplkit::make_bvh_ray(v3f(0.0f), v);
    CHECK(r.valid);
    CHECK(r.t_scale == 4.0f);
    CHECK(r.dir == v * 0.25f);
  }
}

TEST_CASE("huge divisor hard case: rays with directions above 2^126 hit what the direction / 4 hits, at t / 4, also under NVIDIA's division") {
  // A closed room of half extent 2^20 (inside the triangle test's range; t = distance / |dir| is
  // then about 2^-107, still normal): every valid ray from inside hits. Rays aimed at triangle
  // centroids (no edge or tie ambiguity), their direction scaled so that the largest component
  // lies in (2^126, FLT_MAX], some with components zeroed or made denormal.
  tri_mesh m;
  const double half = std::ldexp(1.0, 20);
  m.box(v3d(0.0), v3d(half), glm::dmat3(1.0), 3, true);
  const auto b = build(m);
  const model_bvh mb(b);
  random_source rnd(2127);
  int hits = 0;
  for (int i = 0; i < 400; ++i) {
    const v3f o(rnd.point_in(v3d(-0.5 * half), v3d(0.5 * half)));
    const std::size_t tri = std::size_t(rnd.integer(0, int(m.triangle_count()) - 1));
    const v3f target = (m.vertex(tri, 0) + m.vertex(tri, 1) + m.vertex(tri, 2)) / 3.0f;
    v3d dir = v3d(target) - v3d(o);
    const double dm = std::fmax(std::fabs(dir.x), std::fmax(std::fabs(dir.y), std::fabs(dir.z)));
    dir *= rnd.uniform(std::ldexp(1.0, 126) * 1.0000002, double(flt_max)) / dm;
    v3f d(dir);
    if (i % 7 == 0) {  // a denormal or zero beside the huge component (the ray misses the target then)
      const int k = rnd.integer(0, 2);
      if (std::fabs(d[k]) < two_126) d[k] = i % 2 ? 1e-40f : 0.0f;
    }
    INFO("o = " << show(o) << " d = " << show(d));
    const auto h = vplkit::bvh_closest_hit(b.view(), o, d);
    const auto h4 = vplkit::bvh_closest_hit(b.view(), o, d * 0.25f);
    REQUIRE(h.hit);
    REQUIRE(h4.hit);
    ++hits;
    CHECK(h.triangle == h4.triangle);
    // Exact: the scaled ray is the same ray, its t four times as large.
    CHECK(h.t == 0.25f * h4.t);
    CHECK(h.u == h4.u);
    CHECK(h.v == h4.v);
    CHECK(h.position == h4.position);
    CHECK(vplkit::bvh_occluded(b.view(), o, d));
    CHECK(vplkit::bvh_occluded(b.view(), o, d, 0.0f, 1.0f));  // the target lies within t <= 1
    {
      const vplkit_test::reciprocal_division_scope nvidia;
      const auto g = vplkit::bvh_closest_hit(mb.view(), to_model(o), to_model(d));
      REQUIRE(g.hit);
      CHECK(g.triangle == h.triangle);
      CHECK(std::fabs(double(float(g.t)) - double(h.t)) <= 1e-5 * double(h.t));
      CHECK(vplkit::bvh_occluded(mb.view(), to_model(o), to_model(d), gpu_float(0.0f), gpu_float(1.0f)));
      CHECK(finite(of_model(g.normal)));
    }
  }
  CHECK(hits == 400);
}

TEST_CASE("huge divisor hard case: a triangle whose det exceeds 2^126 (t = 1, exact barycentrics), also under NVIDIA's division") {
  // Vertices (-S, -S, 1), (S, -S, 1), (0, S, 1), S = 1.5 * 2^62, ray from 0 along +z: the edge
  // functions are -S^2, -S^2, -2 S^2, det = -9 * 2^124 (above 2^126, finite), tn = det, so t = 1,
  // u = 1/4, v = 1/2 exactly. The normal, cross(e1, e2) = (0, 0, 9 * 2^124), is huge too.
  const float s = 1.5f * std::ldexp(1.0f, 62);
  tri_mesh m;
  m.positions = {v3f(-s, -s, 1.0f), v3f(s, -s, 1.0f), v3f(0.0f, s, 1.0f)};
  m.indices = {0, 1, 2};
  const auto b = build(m);
  const model_bvh mb(b);
  const v3f o(0.0f), d(0.0f, 0.0f, 1.0f);
  const auto h = vplkit::bvh_closest_hit(b.view(), o, d);
  REQUIRE(h.hit);
  CHECK(h.t == 1.0f);
  CHECK(h.u == 0.25f);
  CHECK(h.v == 0.5f);
  CHECK(h.normal == v3f(0.0f, 0.0f, 1.0f));
  const vplkit_test::reciprocal_division_scope nvidia;
  const auto g = vplkit::bvh_closest_hit(mb.view(), to_model(o), to_model(d));
  INFO("NVIDIA model: t " << float(g.t) << " u " << float(g.u) << " v " << float(g.v) << " normal "
                          << show(of_model(g.normal)));
  REQUIRE(g.hit);
  CHECK(std::fabs(float(g.t) - 1.0f) <= 2.5e-7f);
  CHECK(std::fabs(float(g.u) - 0.25f) <= 1e-7f);
  CHECK(std::fabs(float(g.v) - 0.5f) <= 1e-7f);
  CHECK(std::fabs(float(g.normal.z) - 1.0f) <= 2.5e-7f);
  CHECK(vplkit::bvh_occluded(mb.view(), to_model(o), to_model(d)));
}
