// SPDX-License-Identifier: MIT
// The clamp compensation (estimators/clamp_compensation.hpp, docs/math.md, "The clamp's compensation"): what each
// direction adds, that its weight and the clamp's sum to 1, that it is exactly 0 where the clamp is
// inactive, that short rays (trace_within) change nothing, its range forms and its stream. The
// statistical tests (tests/statistical/estimators_clamp_compensation_stat_test.cpp) show what it
// converges to; the hard cases are in tests/hardcases/estimators_clamp_compensation_hardcases_test.cpp.
#include <estimator_splits.hpp>
#include <float_bits.hpp>
#include <synthetic_scene.hpp>

#include <vplkit/estimators/clamp_compensation.hpp>
#include <vplkit/estimators/gathering_estimator.hpp>
#include <vplkit/estimators/vpl_sum.hpp>
#include <vplkit/visibility/light_visibility.hpp>
#include <vplkit/visibility/visibility_callables.hpp>
#include <vplkit/visibility/voxelize_triangles.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

using namespace vplkit;
using namespace vplkit_test;

namespace {

// Counts its calls and hides the wrapped tracer's trace_within (so the compensation traces whole rays).
template <class Tracer>
struct counting_tracer {
  Tracer tracer;
  int* calls;
  template <class T>
  ray_hit<T> operator()(vec3<T> x, vec3<T> n_x, vec3<T> dir) const {
    ++*calls;
    return tracer(x, n_x, dir);
  }
};

// A gather point of the room by name.
template <class T>
gather_point<T> room_point(const std::vector<named_gather_point<T>>& gps, const char* name) {
  for (const auto& g : gps)
    if (g.name == name) return g.gp;
  FAIL("no gather point " << name);
  return {};
}

// Cosine directions on an m x m grid of the primary sample square.
template <class T>
std::vector<vec3<T>> grid_directions(int m) {
  std::vector<vec3<T>> out;
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < m; ++i)
      out.push_back(sample_cosine_hemisphere(vec2<T>((T(i) + T(0.5)) / T(m), (T(j) + T(0.5)) / T(m))));
  return out;
}

}  // namespace

TEMPLATE_TEST_CASE("clamp compensation: its weight and the clamp's sum to 1 at every distance", "[estimators]", float,
                   double) {
  using T = TestType;
  for (const T dmin : {T(0.01), T(0.3), T(2.5)}) {
    for (int k = 0; k <= 40; ++k) {
      const T d = dmin * T(k) / T(20);  // 0 .. 2 dmin
      const T d_sq = d * d;
      const T clamp = d_sq / glm::max(d_sq, dmin * dmin);  // the VPL strategy's weight (vpl_geometry_term)
      const T comp = clamp_compensation_weight(d_sq, dmin);
      INFO("dmin " << dmin << " d " << d);
      CHECK(std::abs(clamp + comp - T(1)) <= T(2) * std::numeric_limits<T>::epsilon());
      if (d >= dmin) CHECK(comp == T(0));
    }
    CHECK(clamp_compensation_weight(T(0), dmin) == T(1));
    CHECK(clamp_compensation_weight(T(0.25) * dmin * dmin, -dmin) == clamp_compensation_weight(T(0.25) * dmin * dmin, dmin));
  }
  const T nan = std::numeric_limits<T>::quiet_NaN(), inf = std::numeric_limits<T>::infinity();
  CHECK(clamp_compensation_weight(T(0.1), T(0)) == T(0));  // no clamp, nothing to give back
  CHECK(clamp_compensation_weight(T(0), T(0)) == T(0));
  CHECK(clamp_compensation_weight(T(0.1), nan) == T(0));
  CHECK(clamp_compensation_weight(nan, T(1)) == T(0));
  CHECK(clamp_compensation_weight(T(1e30), inf) == T(1));  // an infinite clamp turns the VPLs off
  CHECK(clamp_compensation_weight(inf, inf) == T(0));
}

TEMPLATE_TEST_CASE("clamp compensation: a direction adds the gathering sample times 1 - d^2 / dmin^2 within dmin",
                   "[estimators]", float, double) {
  using T = TestType;
  const lit_room<T> room(32);
  const auto tracer = with_light_visibility(room.tracer, room.vis);
  const T dmin = T(0.4);
  int near = 0, far = 0;
  for (const auto& g : room.gps) {
    const orthonormal_basis<T> frame = make_orthonormal_basis(gather_point_shading_normal(g.gp));
    for (const vec3<T>& local : grid_directions<T>(24)) {
      const vec3<T> k = clamp_compensation_sample(g.gp, room.view, frame, local, tracer, dmin, T(0));
      const ray_hit<T> h = tracer(g.gp.position, g.gp.normal, to_world(frame, local));
      const vec3<T> w = h.position - g.gp.position;
      const T d_sq = glm::dot(w, w);
      INFO(g.name << " direction " << local.x << " " << local.y << " " << local.z);
      if (h.hit && d_sq < dmin * dmin) {
        const vec3<T> expected = gathering_sample(g.gp, room.view, frame, local, tracer, T(0)) * (T(1) - d_sq / (dmin * dmin));
        CHECK(same_bits(k, expected));
        near += luminance(expected) > T(0) ? 1 : 0;
      } else {
        CHECK(same_bits(k, vec3<T>(T(0))));
        far += 1;
      }
    }
  }
  // floor_corner (0.1 from two walls) and the block's faces see surfaces within dmin
  CHECK(near > 50);
  CHECK(far > 1000);
}

TEMPLATE_TEST_CASE("clamp compensation, patch VPLs: a hit in a moved part is weighed by its texel centre's distance",
                   "[estimators]", float, double) {
  using T = TestType;
  const lit_room<T> room(32);
  const auto tracer = with_light_visibility(room.tracer, room.vis);
  const T dmin = T(0.4);
  int moved = 0, plain = 0;
  for (const auto& g : room.gps) {
    const orthonormal_basis<T> frame = make_orthonormal_basis(gather_point_shading_normal(g.gp));
    for (const vec3<T>& local : grid_directions<T>(24)) {
      const vec3<T> point = clamp_compensation_sample(g.gp, room.view, frame, local, tracer, dmin, T(0));
      const vec3<T> patch = clamp_compensation_sample(g.gp, room.view, frame, local, tracer, dmin, T(0), vpl_mode::patch);
      const gathering_ray_result<T> r =
          trace_gathering_ray(room.view, g.gp.position, g.gp.normal, to_world(frame, local), tracer, T(0));
      INFO(g.name);
      if (point != vec3<T>(T(0)) && dprsm_patch_direction_at_centre(room.view, r.texel, r.hit)) {
        const vec3<T> wc = room.view.position[r.texel] - g.gp.position;
        const vec3<T> expected = gathering_sample(g.gp, room.view, frame, local, tracer, T(0)) *
                                 clamp_compensation_weight(glm::dot(wc, wc), dmin);
        CHECK(same_bits(patch, expected));
        ++moved;
      } else {
        CHECK(same_bits(patch, point));
        plain += point != vec3<T>(T(0)) ? 1 : 0;
      }
    }
  }
  CHECK(moved > 10);
  CHECK(plain > 10);
}

// Counts the shadow rays (light visibility queries) it answers.
template <class Visibility>
struct counting_visibility {
  Visibility visibility;
  int* calls;
  template <class T>
  bool operator()(vec3<T> x, vec3<T> n_x, vec3<T> y, vec3<T> n_y) const {
    ++*calls;
    return visibility(x, n_x, y, n_y);
  }
};

TEMPLATE_TEST_CASE("clamp compensation: the lit test's shadow ray only for hits that would add something, same values",
                   "[estimators]", float, double) {
  using T = TestType;
  const lit_room<T> room(32);
  int shadow_rays = 0, lit_test_first = 0;
  const auto tracer = with_light_visibility(room.tracer, counting_visibility<exact_visibility<T>>{room.vis, &shadow_rays});
  const auto reference_tracer =
      with_light_visibility(room.tracer, counting_visibility<exact_visibility<T>>{room.vis, &lit_test_first});
  // dmin 1: floor_shadow, 0.8 under the block, sees its underside within dmin; the light is above
  // the block, so that face's lit side faces away from x: L_o towards x is 0, no shadow ray needed.
  const T dmin = T(1);
  int nonzero = 0;
  for (const vpl_mode vmode : {vpl_mode::point, vpl_mode::patch})
    for (const auto& g : room.gps) {
      const orthonormal_basis<T> frame = make_orthonormal_basis(gather_point_shading_normal(g.gp));
      for (const vec3<T>& local : grid_directions<T>(24)) {
        const int before = shadow_rays;
        const vec3<T> k = clamp_compensation_sample(g.gp, room.view, frame, local, tracer, dmin, T(0), vmode);
        // The lit test first, as gathering evaluates a hit (evaluate_gathering_hit), then the weight.
        const vec3<T> dir = to_world(frame, local);
        const ray_hit<T> h = room.tracer(g.gp.position, g.gp.normal, dir);
        const vec3<T> w = h.position - g.gp.position;
        T weight = clamp_compensation_weight(glm::dot(w, w), dmin);
        vec3<T> expected(T(0));
        if (h.hit && weight > T(0) && gather_point_accepts_direction(g.gp, dir) &&
            !vpl_hit_on_own_plane(g.gp.position, h)) {
          const gathering_ray_result<T> r = evaluate_gathering_hit(room.view, g.gp.position, h, reference_tracer, T(0));
          if (r.lit) {
            if (vmode == vpl_mode::patch && dprsm_patch_direction_at_centre(room.view, r.texel, r.hit)) {
              const vec3<T> wc = room.view.position[r.texel] - g.gp.position;
              weight = clamp_compensation_weight(glm::dot(wc, wc), dmin);
            }
            expected = estimator_finite_or_zero(g.gp.albedo * r.radiance * weight);
          }
        }
        INFO(g.name << " direction " << local.x << " " << local.y << " " << local.z);
        CHECK(same_bits(k, expected));
        CHECK(shadow_rays - before <= 1);
        if (luminance(k) > T(0)) {
          ++nonzero;
          CHECK(shadow_rays - before == 1);  // a lit hit was asked
        }
      }
    }
  std::printf("clamp compensation, dmin %.2f: %d shadow rays (lit test first: %d), %d directions add light\n",
              double(dmin), shadow_rays, lit_test_first, nonzero);
  CHECK(nonzero > 100);
  // Hits within dmin whose lit side faces away from x (or whose texel saw nothing there) trace none.
  CHECK(shadow_rays < lit_test_first);
}

TEMPLATE_TEST_CASE("clamp compensation: exactly 0 where the clamp is inactive, and then clamped + it = unclamped",
                   "[estimators]", float, double) {
  using T = TestType;
  const lit_room<T> room(32);
  const auto tracer = with_light_visibility(room.tracer, room.vis);
  // floor_open lies 0.8 and more from every other surface: with dmin 0.3 no VPL point it can see
  // and no hit is within dmin (its own floor's VPLs lie in its tangent plane: cos(theta2) = 0).
  const gather_point<T> gp = room_point(room.gps, "floor_open");
  const T dmin = T(0.3);
  counter_rng rng = make_counter_rng(5u, 9u);
  const vec3<T> k = estimate_clamp_compensation(gp, room.view, rng, 256, tracer, dmin, T(0));
  CHECK(same_bits(k, vec3<T>(T(0))));
  CHECK(rng.counter == 512u);  // two numbers per direction, whatever it hit
  const counter_rng stream = make_counter_rng(6u, 1u);
  const vec3<T> clamped = exhaustive_vpl_patch_sum(gp, room.view, stream, 2, room.vis, dmin, T(0));
  const vec3<T> unclamped = exhaustive_vpl_patch_sum(gp, room.view, stream, 2, room.vis, T(0), T(0));
  CHECK(luminance(unclamped) > T(0));
  CHECK(same_bits(clamped + k, unclamped));
  // ... while next to the walls it is not
  counter_rng rng2 = make_counter_rng(5u, 9u);
  CHECK(luminance(estimate_clamp_compensation(room_point(room.gps, "floor_corner"), room.view, rng2, 256, tracer,
                                              dmin, T(0))) > T(0));
}

TEMPLATE_TEST_CASE("clamp compensation: dmin = 0 gives 0 without tracing a ray", "[estimators]", float, double) {
  using T = TestType;
  const lit_room<T> room(32);
  int calls = 0;
  const counting_tracer<exact_tracer<T>> tracer{room.tracer, &calls};
  for (const auto& g : room.gps) {
    counter_rng rng = make_counter_rng(3u, 4u);
    CHECK(same_bits(estimate_clamp_compensation(g.gp, room.view, rng, 16, tracer, T(0), T(0)), vec3<T>(T(0))));
    CHECK(rng.counter == 32u);
  }
  CHECK(calls == 0);
  counter_rng rng = make_counter_rng(3u, 4u);
  estimate_clamp_compensation(room.gps.front().gp, room.view, rng, 16, tracer, T(0.1), T(0));
  CHECK(calls > 0);  // the counter counts
}

TEMPLATE_TEST_CASE("trace_within: the voxel tracers give their whole ray's hit within reach", "[estimators]", float,
                   double) {
  using T = TestType;
  const lit_room<T> room(32);
  const synthetic_scene<T>& s = room.scene;
  const voxel_bounds<T> b = fit_voxel_bounds(s.positions.data(), s.positions.size());
  const triangle_voxel_grid<T> grid =
      voxelize_triangles(b.min, b.max, ivec3(32), s.positions.data(), s.positions.size(), s.indices.data(), s.indices.size());
  const triangle_voxel_tracer<T> triangles{grid.view()};
  const voxel_tracer<T> voxels{grid.occupancy().view()};
  STATIC_REQUIRE(tracer_has_trace_within<triangle_voxel_tracer<T>, T>::value);
  STATIC_REQUIRE(tracer_has_trace_within<voxel_tracer<T>, T>::value);
  STATIC_REQUIRE(!tracer_has_trace_within<exact_tracer<T>, T>::value);
  int within = 0, cut = 0;
  auto check = [&](const auto& tracer, const gather_point<T>& gp, vec3<T> dir, T reach) {
    const ray_hit<T> whole = tracer(gp.position, gp.normal, dir);
    const ray_hit<T> part = tracer.trace_within(gp.position, gp.normal, dir, reach);
    if (whole.hit && glm::length(whole.position - gp.position) <= reach) {
      ++within;
      CHECK(part.hit);
      CHECK(same_bits(part.position, whole.position));
      CHECK(same_bits(part.normal, whole.normal));
    } else if (part.hit) {
      CHECK(glm::length(part.position - gp.position) > reach);  // beyond reach: it may say what it met
    } else {
      ++cut;
    }
  };
  for (const auto& g : room.gps) {
    const orthonormal_basis<T> frame = make_orthonormal_basis(g.gp.normal);
    for (const vec3<T>& local : grid_directions<T>(12))
      for (const T reach : {T(0.05), T(0.3), T(1.5)}) {
        INFO(g.name << " reach " << reach);
        check(triangles, g.gp, to_world(frame, local), reach);
        check(voxels, g.gp, to_world(frame, local), reach);
      }
  }
  CHECK(within > 100);
  CHECK(cut > 100);
  // and the compensation is the same with short rays as with whole ones
  const T dmin = T(0.4);
  for (const auto& g : room.gps) {
    int calls = 0;
    const counting_tracer<triangle_voxel_tracer<T>> whole{triangles, &calls};
    counter_rng r1 = make_counter_rng(8u, 2u), r2 = r1;
    INFO(g.name);
    CHECK(same_bits(estimate_clamp_compensation(g.gp, room.view, r1, 64, triangles, dmin, T(0)),
                    estimate_clamp_compensation(g.gp, room.view, r2, 64, whole, dmin, T(0))));
  }
}

// Hides the wrapped tracer's surface_within (keeps trace_within): every gather point is traced.
template <class Tracer>
struct always_tracing {
  Tracer tracer;
  template <class T>
  ray_hit<T> operator()(vec3<T> x, vec3<T> n_x, vec3<T> dir) const {
    return tracer(x, n_x, dir);
  }
  template <class T>
  ray_hit<T> trace_within(vec3<T> x, vec3<T> n_x, vec3<T> dir, T reach) const {
    return tracer.trace_within(x, n_x, dir, reach);
  }
};

TEMPLATE_TEST_CASE("triangle_voxel_surface_within: never false where another surface is within reach, often false elsewhere",
                   "[estimators]", float, double) {
  using T = TestType;
  const synthetic_scene<T> s;
  const voxel_bounds<T> b = fit_voxel_bounds(s.positions.data(), s.positions.size());
  const triangle_voxel_grid<T> grid =
      voxelize_triangles(b.min, b.max, ivec3(32), s.positions.data(), s.positions.size(), s.indices.data(), s.indices.size());
  // Brute force: is a triangle whose plane does not pass within tol of x nearer than reach?
  auto near = [&](vec3<T> x, T reach, T tol) {
    for (int t = 0; t < s.triangle_count(); ++t) {
      const vec3<T> a = s.positions[s.indices[3 * t]], bb = s.positions[s.indices[3 * t + 1]],
                    c = s.positions[s.indices[3 * t + 2]];
      const vec3<T> n = glm::normalize(glm::cross(bb - a, c - a));
      if (std::abs(glm::dot(n, x - a)) <= tol) continue;
      // distance to the triangle by sampling it densely (a lower bound is not needed: the test
      // only asks that a triangle surely within reach be found)
      for (int i = 0; i <= 40; ++i)
        for (int j = 0; i + j <= 40; ++j) {
          const vec3<T> p = a + (bb - a) * (T(i) / T(40)) + (c - a) * (T(j) / T(40));
          if (glm::length(p - x) < reach) return true;
        }
    }
    return false;
  };
  int falses = 0, trues = 0;
  const T tol = T(1e-5);
  for (int k = 0; k < 400; ++k) {
    // points on the floor, the red wall and the block's top, some close to a crease
    const T u = T((k * 37) % 400) / T(400), v = T((k * 91) % 400) / T(400);
    const vec3<T> pts[3] = {vec3<T>(T(-2) + T(4) * u, T(0), T(-2) + T(4) * v),
                            vec3<T>(T(-2), T(3) * u * u, T(-2) + T(4) * v),
                            vec3<T>(T(-1) + T(1.4) * u, T(1.2), T(-0.8) + T(1.4) * v)};
    for (const vec3<T>& x : pts)
      for (const T reach : {T(0.02), T(0.1), T(0.3)}) {
        const bool said = triangle_voxel_surface_within(grid.view(), x, reach, tol);
        INFO("x " << x.x << " " << x.y << " " << x.z << " reach " << reach);
        CHECK(said == triangle_voxel_surface_within_scan(grid.view(), x, reach, tol));  // the voxels' planes change nothing
        if (near(x, reach, tol)) CHECK(said);
        (said ? trues : falses) += 1;
      }
  }
  CHECK(falses > 1000);
  CHECK(trues > 200);
  // what it cannot look at: true
  const T inf = std::numeric_limits<T>::infinity(), nan = std::numeric_limits<T>::quiet_NaN();
  CHECK(triangle_voxel_surface_within(grid.view(), vec3<T>(T(0.5), T(0), T(0.5)), T(100), tol));
  CHECK(triangle_voxel_surface_within(grid.view(), vec3<T>(T(0.5), T(0), T(0.5)), inf, tol));
  CHECK(triangle_voxel_surface_within(grid.view(), vec3<T>(T(0.5), T(0), T(0.5)), nan, tol));
  CHECK(triangle_voxel_surface_within(grid.view(), vec3<T>(nan, T(0), T(0.5)), T(0.1), tol));
  CHECK(triangle_voxel_surface_within(grid.view(), vec3<T>(T(0.5), T(0), T(0.5)), T(-1), tol));
  CHECK(!triangle_voxel_surface_within(grid.view(), vec3<T>(T(0.5), T(0), T(0.5)), T(0), tol));  // reach 0: nothing
}

TEMPLATE_TEST_CASE("clamp compensation: gather points with no other surface within dmin are skipped, the estimate unchanged",
                   "[estimators]", float, double) {
  using T = TestType;
  const lit_room<T> room(32);
  const synthetic_scene<T>& s = room.scene;
  const voxel_bounds<T> b = fit_voxel_bounds(s.positions.data(), s.positions.size());
  const triangle_voxel_grid<T> grid =
      voxelize_triangles(b.min, b.max, ivec3(32), s.positions.data(), s.positions.size(), s.indices.data(), s.indices.size());
  const triangle_voxel_tracer<T> tracer{grid.view()};
  const auto shadow = with_light_visibility(tracer, triangle_voxel_visibility<T>{grid.view()});
  STATIC_REQUIRE(tracer_has_surface_within<triangle_voxel_tracer<T>, T>::value);
  STATIC_REQUIRE(tracer_has_surface_within<decltype(shadow), T>::value);  // forwarded
  STATIC_REQUIRE(tracer_has_trace_within<decltype(shadow), T>::value);
  STATIC_REQUIRE(!tracer_has_surface_within<always_tracing<triangle_voxel_tracer<T>>, T>::value);
  const gbuffer_data<T> gb = s.make_gbuffer(24, 24);
  const T dmin = T(0.2);
  int skipped = 0, traced = 0, nonzero = 0;
  for (int p = 0; p < gb.view().pixel_count(); ++p) {
    const gather_point<T> gp = gb.view().at(p);
    if (!gather_point_valid(gp)) continue;
    (clamp_compensation_may_add(tracer, gp, dmin) ? traced : skipped) += 1;
    counter_rng r1 = make_counter_rng(4u, std::uint32_t(p)), r2 = r1, r3 = r1, r4 = r1;
    const vec3<T> a = estimate_clamp_compensation(gp, room.view, r1, 8, tracer, dmin, T(0));
    const vec3<T> c = estimate_clamp_compensation(gp, room.view, r2, 8, always_tracing<triangle_voxel_tracer<T>>{tracer},
                                                  dmin, T(0));
    INFO("pixel " << p);
    CHECK(same_bits(a, c));
    CHECK(r1.counter == r2.counter);
    const vec3<T> d = estimate_clamp_compensation(gp, room.view, r3, 8, shadow, dmin, T(0));
    const vec3<T> e = estimate_clamp_compensation(gp, room.view, r4, 8, with_light_visibility(always_tracing<triangle_voxel_tracer<T>>{tracer}, triangle_voxel_visibility<T>{grid.view()}), dmin, T(0));
    CHECK(same_bits(d, e));
    nonzero += luminance(a) > T(0) ? 1 : 0;
  }
  std::printf("24x24 G-buffer of the room, dmin %.3f: %d gather points skipped, %d traced, %d with a compensation\n",
              double(dmin), skipped, traced, nonzero);
  CHECK(skipped > 300);  // 417 of 576
  CHECK(nonzero > 20);   // 50
}

TEMPLATE_TEST_CASE("clamp compensation: ranges of directions give the one-shot estimate bit for bit", "[estimators]",
                   float, double) {
  using T = TestType;
  const lit_room<T> room(16);
  const auto tracer = with_light_visibility(room.tracer, room.vis);
  const T dmin = T(0.5);
  const int n = 9;
  for (const auto& g : room.gps) {
    INFO(g.name);
    check_splits<T>(
        make_counter_rng(17u, 3u), cuts_of(n, {0, 0, n / 3, n / 3, n - 1, n}),
        [&](counter_rng& rng) { return estimate_clamp_compensation(g.gp, room.view, rng, n, tracer, dmin, T(0)); },
        [&](estimator_state<T>& s, int b, int e) {
          estimate_clamp_compensation_range(g.gp, room.view, s, b, e, tracer, dmin, T(0));
        },
        [&](const estimator_state<T>& s) { return estimate_clamp_compensation_finish(s, n); });
  }
}

TEST_CASE("clamp compensation: a stream of its own, from the estimator stream's key", "[estimators]") {
  const counter_rng a = make_counter_rng(1u, 42u);
  counter_rng advanced = a;
  rng_next_u32(advanced);
  const counter_rng c = clamp_compensation_stream(a);
  CHECK(c.key != a.key);
  CHECK(c.counter == 0u);
  CHECK(clamp_compensation_stream(advanced).key == c.key);  // the estimator's draws do not move it
  CHECK(clamp_compensation_stream(make_counter_rng(1u, 43u)).key != c.key);
}
