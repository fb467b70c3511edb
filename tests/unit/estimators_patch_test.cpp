// SPDX-License-Identifier: MIT
// The patch-sampled estimators (vpl_mode::patch, docs/math.md section 11) on the synthetic room:
//  - the random-number layout: every VPL sample takes u, then u0, u1 (its jitter), always; MIS
//    then takes the direction's two; replaying the stream by hand gives the estimate bit for bit;
//  - ranges of samples give the one-shot estimate bit for bit with the stream at the same counter
//    (what lets vplrender's estimate kernels spread an estimate over passes), also at background pixels;
//  - the exhaustive patch sum reads its numbers at fixed counters: any cut of the texels into
//    ranges gives the same terms, and the stream's counter shifts them texel by texel;
//  - vpl_mode::point is the default and leaves every estimator as it was (n_dirs = 0 MIS is VPL
//    sampling with dmin = 0 in both modes).
#include <estimator_splits.hpp>
#include <synthetic_scene.hpp>

#include <vplkit/builders/vpl_distribution.hpp>
#include <vplkit/estimators/local_estimator.hpp>
#include <vplkit/estimators/mis_estimator.hpp>
#include <vplkit/estimators/vpl_sampling_estimator.hpp>
#include <vplkit/estimators/vpl_sum.hpp>
#include <vplkit/vpl/luminance.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

using namespace vplkit;
using namespace vplkit_test;

namespace {

// The first CDF wobbles around the flux, the second has holes at every fourth texel.
template <class T>
struct patch_fixture : room_with_local_dists<T> {
  static T first(std::size_t t, T lum) { return lum * (T(1) + T(0.5) * std::cos(T(0.3) * T(t))); }
  static T second(std::size_t t, T lum) { return t % 4 == 1 ? T(0) : lum; }
  patch_fixture() : room_with_local_dists<T>(16, first, second) {}
};

// Each estimate from the stream (23, 9), cut into one range, one per sample, and uneven pieces.
template <class T, class OneShot, class Range, class Finish>
void check_cuts(int n, OneShot&& one_shot, Range&& range, Finish&& finish) {
  check_splits<T>(make_counter_rng(23u, 9u), cuts_of(n, {0, 0, n / 2, n / 2, n}), one_shot, range, finish);
}

}  // namespace

TEMPLATE_TEST_CASE("patch estimators: three numbers per VPL sample, replayed by hand bit for bit", "[estimators]",
                   float, double) {
  using T = TestType;
  const patch_fixture<T> f;
  const T tol = T(0.3), dmin = T(0);
  const auto& dist = f.dists.front();
  for (const auto& g : f.gps) {
    INFO(g.name);
    const gather_point<T>& gp = g.gp;
    {  // VPL sampling: u, u0, u1 per sample
      counter_rng rng = make_counter_rng(4u, 1u), by_hand = rng;
      const vec3<T> e = estimate_vpl_sampling(gp, f.view, dist, rng, 5, f.vis, dmin, vpl_mode::patch, tol);
      vec3<T> sum(T(0));
      for (int k = 0; k < 5; ++k) {
        const T u = rng_next_unit<T>(by_hand), u0 = rng_next_unit<T>(by_hand), u1 = rng_next_unit<T>(by_hand);
        sum += vpl_sampling_patch_sample(gp, f.view, dist, u, vec2<T>(u0, u1), f.vis, dmin, tol);
      }
      CHECK(same_bits(e, sum / T(5)));
      CHECK(rng.counter == 15u);
      CHECK(by_hand.counter == 15u);
    }
    {  // local: per round, per CDF: u, u0, u1
      counter_rng rng = make_counter_rng(4u, 2u), by_hand = rng;
      const vec3<T> e = estimate_local(gp, f.view, f.dists.data(), 2, rng, 3, f.vis, dmin, local_combination::balance,
                                       vpl_mode::patch, tol);
      vec3<T> sum(T(0));
      for (int r = 0; r < 3; ++r)
        for (int i = 0; i < 2; ++i) {
          const T u = rng_next_unit<T>(by_hand), u0 = rng_next_unit<T>(by_hand), u1 = rng_next_unit<T>(by_hand);
          const auto s = f.dists[std::size_t(i)].sample(u);
          if (!(s.pmf > T(0))) continue;
          const vec3<T> c = vpl_patch_visible_contribution(gp, f.view, int(s.index), vec2<T>(u0, u1), f.vis, dmin, tol);
          if (c.x > T(0) || c.y > T(0) || c.z > T(0))
            sum += estimator_finite_or_zero(c / local_mixture_pmf_sum<T>(f.dists.data(), 2, s.index));
        }
      CHECK(same_bits(e, sum / T(3)));
      CHECK(rng.counter == 18u);
    }
    {  // MIS: per step, the VPL's u, u0, u1, then the direction's u0, u1
      counter_rng rng = make_counter_rng(4u, 3u), by_hand = rng;
      const int n_dirs = 3, n_vpls = 4;
      const vec3<T> e = estimate_mis(gp, f.view, dist, rng, n_dirs, n_vpls, f.tracer, f.vis, tol,
                                     mis_mode::solid_angle, vpl_mode::patch);
      const orthonormal_basis<T> frame = make_orthonormal_basis(gp.normal);
      vec3<T> sum(T(0));
      for (int j = 0; j < 4; ++j) {
        const T u = rng_next_unit<T>(by_hand), u0 = rng_next_unit<T>(by_hand), u1 = rng_next_unit<T>(by_hand);
        sum += mis_vpl_patch_sample(gp, f.view, dist, u, vec2<T>(u0, u1), f.vis, T(n_dirs), T(n_vpls),
                                    mis_mode::solid_angle, tol);
        if (j < n_dirs) {
          const T d0 = rng_next_unit<T>(by_hand), d1 = rng_next_unit<T>(by_hand);
          sum += mis_gathering_sample(gp, f.view, dist, frame, sample_cosine_hemisphere(vec2<T>(d0, d1)), f.tracer,
                                      tol, T(n_dirs), T(n_vpls), mis_mode::solid_angle, vpl_mode::patch);
        }
      }
      CHECK(same_bits(e, sum));
      CHECK(rng.counter == 4u * 3u + 3u * 2u);
    }
  }
}

TEMPLATE_TEST_CASE("patch estimators: ranges of samples give the one-shot estimate bit for bit", "[estimators]",
                   float, double) {
  using T = TestType;
  const patch_fixture<T> f;
  const vpl_mode P = vpl_mode::patch;
  const auto& dist = f.dists.front();
  const T tol = T(0.3), dmin = T(0.02);
  for (const auto& g : f.gps) {
    INFO(g.name);
    const gather_point<T>& gp = g.gp;
    check_cuts<T>(
        7, [&](counter_rng& rng) { return estimate_vpl_sampling(gp, f.view, dist, rng, 7, f.vis, dmin, P, tol); },
        [&](estimator_state<T>& s, int b, int e) {
          estimate_vpl_sampling_range(gp, f.view, dist, s, b, e, f.vis, dmin, P, tol);
        },
        [&](const estimator_state<T>& s) { return estimate_vpl_sampling_finish(s, 7); });
    for (const local_combination comb : {local_combination::balance, local_combination::average})
      check_cuts<T>(
          5,
          [&](counter_rng& rng) {
            return estimate_local(gp, f.view, f.dists.data(), 2, rng, 5, f.vis, dmin, comb, P, tol);
          },
          [&](estimator_state<T>& s, int b, int e) {
            estimate_local_range(gp, f.view, f.dists.data(), 2, s, b, e, f.vis, dmin, comb, P, tol);
          },
          [&](const estimator_state<T>& s) { return estimate_local_finish(s, 5); });
    for_each_mis_case({{6, 4}, {2, 7}, {0, 5}}, [&](mis_mode mode, int n_dirs, int n_vpls) {
      check_cuts<T>(
          std::max(n_dirs, n_vpls),
          [&](counter_rng& rng) {
            return estimate_mis(gp, f.view, dist, rng, n_dirs, n_vpls, f.tracer, f.vis, tol, mode, P);
          },
          [&](estimator_state<T>& s, int b, int e) {
            estimate_mis_range(gp, f.view, dist, s, b, e, n_dirs, n_vpls, f.tracer, f.vis, tol, mode, P);
          },
          [&](const estimator_state<T>& s) { return estimate_mis_finish(s, n_dirs, n_vpls, mode); });
    });
  }
  // Background: nothing added, nothing drawn.
  gather_point<T> background = f.gps.front().gp;
  background.normal = vec3<T>(T(0));
  estimator_state<T> s = make_estimator_state<T>(make_counter_rng(1u, 2u));
  estimate_vpl_sampling_range(background, f.view, dist, s, 0, 4, f.vis, T(0), P, tol);
  estimate_local_range(background, f.view, f.dists.data(), 2, s, 0, 4, f.vis, T(0), local_combination::balance, P, tol);
  estimate_mis_range(background, f.view, dist, s, 0, 4, 4, 4, f.tracer, f.vis, tol, mis_mode::solid_angle, P);
  CHECK(s.rng.counter == 0u);
  CHECK(s.sum == vec3<T>(T(0)));
}

TEMPLATE_TEST_CASE("exhaustive patch sum: fixed counters per texel and stratum, any cut of the texels", "[estimators]",
                   float, double) {
  using T = TestType;
  const patch_fixture<T> f;
  const T tol = T(0.3);
  const counter_rng stream = make_counter_rng(77u, 5u);
  const int n = f.view.texel_count();
  for (const auto& g : f.gps) {
    INFO(g.name);
    for (int m : {1, 3}) {
      // By hand: texel by texel, strata row by row, from the stated counters.
      vec3<double> sum(0.0);
      for (int t = 0; t < n; ++t)
        for (int j = 0; j < m; ++j)
          for (int i = 0; i < m; ++i) {
            counter_rng r{stream.key, stream.counter + 2u * std::uint32_t(t * m * m + j * m + i)};
            const T u0 = rng_next_unit<T>(r), u1 = rng_next_unit<T>(r);
            const vec2<T> xi((T(i) + u0) / T(m), (T(j) + u1) / T(m));
            REQUIRE(xi == exhaustive_vpl_patch_jitter<T>(stream, t, m, i, j));
            sum += vec3<double>(vpl_patch_visible_contribution(g.gp, f.view, t, xi, f.vis, T(0), tol));
          }
      const vec3<T> one_shot = exhaustive_vpl_patch_sum(g.gp, f.view, stream, m, f.vis, T(0), tol);
      CHECK(same_bits(one_shot, vec3<T>(sum / double(m * m))));
      for (const auto& cut : {std::vector<int>{0, n}, std::vector<int>{-3, 0, 1, 200, 201, 333, n + 4}}) {
        vpl_sum_state state;
        for (std::size_t k = 0; k + 1 < cut.size(); ++k)
          exhaustive_vpl_patch_sum_range(g.gp, f.view, state, cut[k], cut[k + 1], stream, m, f.vis, T(0), tol);
        CHECK(same_bits(exhaustive_vpl_patch_sum_finish<T>(state, m), one_shot));
      }
    }
    // The stream's counter shifts the numbers texel by texel (m = 1: two numbers per texel).
    const counter_rng shifted{stream.key, stream.counter + 2u};
    for (int t = 0; t + 1 < n; t += 37)
      CHECK(exhaustive_vpl_patch_jitter<T>(shifted, t, 1, 0, 0) == exhaustive_vpl_patch_jitter<T>(stream, t + 1, 1, 0, 0));
    // Background pixels and strata <= 0 give 0.
    gather_point<T> background = g.gp;
    background.normal = vec3<T>(T(0));
    CHECK(exhaustive_vpl_patch_sum(background, f.view, stream, 2, f.vis, T(0), tol) == vec3<T>(T(0)));
    CHECK(exhaustive_vpl_patch_sum(g.gp, f.view, stream, 0, f.vis, T(0), tol) == vec3<T>(T(0)));
    CHECK(exhaustive_vpl_patch_sum(g.gp, f.view, stream, -2, f.vis, T(0), tol) == vec3<T>(T(0)));
  }
}

TEMPLATE_TEST_CASE("patch estimators: point is the default, MIS without directions is VPL sampling", "[estimators]",
                   float, double) {
  using T = TestType;
  const patch_fixture<T> f;
  const auto& dist = f.dists.front();
  for (const auto& g : f.gps) {
    INFO(g.name);
    counter_rng a = make_counter_rng(8u, 1u), b = a;
    CHECK(same_bits(estimate_vpl_sampling(g.gp, f.view, dist, a, 6, f.vis, T(0.05)),
                    estimate_vpl_sampling(g.gp, f.view, dist, b, 6, f.vis, T(0.05), vpl_mode::point, T(0.3))));
    CHECK(a.counter == 6u);
    for (const vpl_mode mode : {vpl_mode::point, vpl_mode::patch}) {
      // n_dirs = 0: every VPL sample adds f / (n2 p2) = L V / (n2 pmf), i.e. VPL sampling with dmin 0
      // (to rounding: f / p2 and L / pmf are computed differently).
      counter_rng m = make_counter_rng(8u, 2u), v = m;
      const vec3<T> e_mis = estimate_mis(g.gp, f.view, dist, m, 0, 16, f.tracer, f.vis, T(0.3), mis_mode::solid_angle, mode);
      const vec3<T> e_vpl = estimate_vpl_sampling(g.gp, f.view, dist, v, 16, f.vis, T(0), mode, T(0.3));
      CHECK(m.counter == v.counter);
      const T rel = std::is_same<T, float>::value ? T(1e-4) : T(1e-10);
      for (int k = 0; k < 3; ++k) CHECK(std::abs(e_mis[k] - e_vpl[k]) <= rel * std::abs(e_vpl[k]) + T(1e-30));
    }
  }
}
