// SPDX-License-Identifier: MIT
// The range forms of the estimators: an estimate spread over consecutive ranges of its samples
// (estimate_X_range on one estimator_state, then estimate_X_finish) equals the one-shot estimate_X
// bit for bit and leaves the random-number stream where the one-shot leaves it, however [0, n) is
// cut. This is what lets a GPU kernel split an estimate over passes (examples/vplrender's estimate
// kernels) and still match the CPU backend.
#include <estimator_splits.hpp>
#include <synthetic_scene.hpp>

#include <vplkit/builders/vpl_distribution.hpp>
#include <vplkit/estimators/estimator_state.hpp>
#include <vplkit/estimators/gathering_estimator.hpp>
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

// Each estimate from the stream (17, 3), cut into one range, one per sample, and uneven pieces.
template <class T, class OneShot, class Range, class Finish>
void check_splits(int n, OneShot&& one_shot, Range&& range, Finish&& finish) {
  vplkit_test::check_splits<T>(make_counter_rng(17u, 3u), cuts_of(n, {0, 0, n / 3, n / 3, n - 1, n}), one_shot, range,
                               finish);
}

template <class T>
struct fixture : room_with_local_dists<T> {
  fixture()
      : room_with_local_dists<T>(
            16, [](std::size_t t, T lum) { return lum * (T(1) + T(0.5) * std::sin(T(0.1) * T(t))); },
            [](std::size_t t, T lum) { return t % 3 == 0 ? T(0) : lum; }) {}
};

}  // namespace

TEMPLATE_TEST_CASE("estimators: ranges of samples give the one-shot estimate bit for bit", "[estimators]",
                   float, double) {
  using T = TestType;
  const fixture<T> f;
  const auto& dist = f.dists.front();
  const T dmin = T(0.05), tol = T(0.02);
  for (const auto& g : f.gps) {
    INFO(g.name);
    const gather_point<T>& gp = g.gp;
    {
      INFO("VPL sampling");
      const int n = 7;
      check_splits<T>(
          n, [&](counter_rng& rng) { return estimate_vpl_sampling(gp, f.view, dist, rng, n, f.vis, dmin); },
          [&](estimator_state<T>& s, int b, int e) {
            estimate_vpl_sampling_range(gp, f.view, dist, s, b, e, f.vis, dmin);
          },
          [&](const estimator_state<T>& s) { return estimate_vpl_sampling_finish(s, n); });
    }
    for (const local_combination comb : {local_combination::balance, local_combination::average}) {
      INFO("local, combination " << int(comb));
      const int n = 5;
      check_splits<T>(
          n,
          [&](counter_rng& rng) {
            return estimate_local(gp, f.view, f.dists.data(), 2, rng, n, f.vis, dmin, comb);
          },
          [&](estimator_state<T>& s, int b, int e) {
            estimate_local_range(gp, f.view, f.dists.data(), 2, s, b, e, f.vis, dmin, comb);
          },
          [&](const estimator_state<T>& s) { return estimate_local_finish(s, n); });
    }
    {
      INFO("gathering");
      const int n = 9;
      check_splits<T>(
          n, [&](counter_rng& rng) { return estimate_gathering(gp, f.view, rng, n, f.tracer, tol); },
          [&](estimator_state<T>& s, int b, int e) { estimate_gathering_range(gp, f.view, s, b, e, f.tracer, tol); },
          [&](const estimator_state<T>& s) { return estimate_gathering_finish(s, n); });
    }
    for_each_mis_case({{6, 4}, {3, 8}, {0, 5}}, [&](mis_mode mode, int n_dirs, int n_vpls) {
      check_splits<T>(
          std::max(n_dirs, n_vpls),
          [&](counter_rng& rng) {
            return estimate_mis(gp, f.view, dist, rng, n_dirs, n_vpls, f.tracer, f.vis, tol, mode);
          },
          [&](estimator_state<T>& s, int b, int e) {
            estimate_mis_range(gp, f.view, dist, s, b, e, n_dirs, n_vpls, f.tracer, f.vis, tol, mode);
          },
          [&](const estimator_state<T>& s) { return estimate_mis_finish(s, n_dirs, n_vpls, mode); });
    });
    {
      INFO("exhaustive sum");
      const vec3<T> expected = exhaustive_vpl_sum(gp, f.view, f.vis, dmin);
      const int n = f.view.texel_count();
      for (const std::vector<int>& cut : {std::vector<int>{0, n}, std::vector<int>{-5, 100, 101, 700, n + 9}}) {
        vpl_sum_state state;
        for (std::size_t k = 0; k + 1 < cut.size(); ++k)
          exhaustive_vpl_sum_range(gp, f.view, state, cut[k], cut[k + 1], f.vis, dmin);
        CHECK(same_bits(exhaustive_vpl_sum_finish<T>(state), expected));
      }
    }
  }
}

TEMPLATE_TEST_CASE("estimators: range forms add nothing at background pixels and finish counts <= 0 as 0",
                   "[estimators]", float, double) {
  using T = TestType;
  const fixture<T> f;
  gather_point<T> background = f.gps.front().gp;
  background.normal = vec3<T>(T(0));
  estimator_state<T> s = make_estimator_state<T>(make_counter_rng(1u, 2u));
  estimate_vpl_sampling_range(background, f.view, f.dists.front(), s, 0, 4, f.vis, T(0));
  estimate_local_range(background, f.view, f.dists.data(), 2, s, 0, 4, f.vis, T(0));
  estimate_gathering_range(background, f.view, s, 0, 4, f.tracer, T(0.02));
  estimate_mis_range(background, f.view, f.dists.front(), s, 0, 4, 4, 4, f.tracer, f.vis, T(0.02));
  CHECK(s.rng.counter == 0u);
  CHECK(s.sum == vec3<T>(T(0)));
  vpl_sum_state sum;
  exhaustive_vpl_sum_range(background, f.view, sum, 0, f.view.texel_count(), f.vis, T(0));
  CHECK(sum.sum == vec3<double>(0.0));

  s.sum = vec3<T>(T(1));
  CHECK(estimate_vpl_sampling_finish(s, 0) == vec3<T>(T(0)));
  CHECK(estimate_local_finish(s, -1) == vec3<T>(T(0)));
  CHECK(estimate_gathering_finish(s, 0) == vec3<T>(T(0)));
  CHECK(estimate_mis_finish(s, 0, 0, mis_mode::as_published) == vec3<T>(T(0)));
  CHECK(estimate_mis_finish(s, 0, 2, mis_mode::as_published) == vec3<T>(T(0.5)));
  CHECK(estimate_mis_finish(s, 0, 2, mis_mode::solid_angle) == vec3<T>(T(1)));
}
