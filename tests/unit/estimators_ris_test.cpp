// SPDX-License-Identifier: MIT
// The resampled estimator (estimators/ris_estimator.hpp) and its spatial reuse
// (estimators/ris_spatial_reuse.hpp), exactly: the random numbers each part draws, a candidate
// pass replayed by hand (the kept sample, its target, W), RIS with one candidate against VPL
// sampling, the range forms against the one-shot, the keep-k shading's single query per distinct
// sample, the neighbour picker's square, the similarity test, the buffer record's round trip, and a
// reuse without neighbours, which must return the canonical reservoir.
#include <estimator_splits.hpp>
#include <float_bits.hpp>
#include <synthetic_scene.hpp>

#include <vplkit/builders/flux_weights.hpp>
#include <vplkit/builders/vpl_distribution.hpp>
#include <vplkit/estimators/ris_estimator.hpp>
#include <vplkit/estimators/ris_params.h>
#include <vplkit/estimators/ris_spatial_reuse.hpp>
#include <vplkit/estimators/vpl_sampling_estimator.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <map>
#include <vector>

using namespace vplkit;
using namespace vplkit_test;

namespace {

template <class T>
struct fixture : room_with_local_dists<T> {
  fixture()
      : room_with_local_dists<T>(
            16, [](std::size_t t, T lum) { return lum * (T(1) + T(0.5) * std::sin(T(0.1) * T(t))); },
            [](std::size_t t, T lum) { return t % 3 == 0 ? T(0) : lum; }) {}
};

// Counts the visibility queries it answers (exactly, through the scene).
template <class T>
struct counting_visibility {
  exact_visibility<T> vis;
  int* queries;
  bool operator()(vec3<T> x, vec3<T> nx, vec3<T> y, vec3<T> ny) const {
    ++*queries;
    return vis(x, nx, y, ny);
  }
};

}  // namespace

TEMPLATE_TEST_CASE("ris: the random numbers each part draws", "[estimators][ris]", float, double) {
  using T = TestType;
  const fixture<T> f;
  const auto& dist = f.dists.front();
  const gather_point<T>& gp = f.gps[0].gp;
  for (const vpl_mode mode : {vpl_mode::point, vpl_mode::patch}) {
    const std::uint32_t per_draw = mode == vpl_mode::patch ? 3u : 1u;
    INFO("mode " << int(mode));
    for (const int m : {1, 5, 32}) {
      counter_rng rng = make_counter_rng(5u, 1u);
      (void)ris_resample(gp, f.view, dist, rng, m, T(0.05), mode);
      CHECK(rng.counter == std::uint32_t(m) * (per_draw + 1u));
      for (const int k : {1, 3, ris_max_kept}) {
        counter_rng r2 = make_counter_rng(5u, 1u);
        ris_reservoir<T> res[ris_max_kept];
        ris_resample_candidates(gp, f.view, dist, r2, m, res, k, T(0.05), mode);
        CHECK(r2.counter == std::uint32_t(m) * (per_draw + std::uint32_t(k)));
      }
      counter_rng r3 = make_counter_rng(5u, 1u);
      (void)estimate_ris(gp, f.view, dist, r3, 3, m, f.vis, T(0.05), mode);
      CHECK(r3.counter == 3u * std::uint32_t(m) * (per_draw + 1u));
    }
    // Nothing for M <= 0, N <= 0 or an invalid gather point.
    counter_rng rng = make_counter_rng(5u, 1u);
    const gather_point<T> background{gp.position, vec3<T>(T(0)), gp.albedo};
    CHECK(ris_resample(gp, f.view, dist, rng, 0, T(0.05), mode).confidence == T(0));
    CHECK(estimate_ris(gp, f.view, dist, rng, 0, 8, f.vis, T(0.05), mode) == vec3<T>(T(0)));
    CHECK(estimate_ris(gp, f.view, dist, rng, 4, -1, f.vis, T(0.05), mode) == vec3<T>(T(0)));
    CHECK(estimate_ris(background, f.view, dist, rng, 4, 8, f.vis, T(0.05), mode) == vec3<T>(T(0)));
    CHECK(rng.counter == 0u);
  }
  // The spatial reuse: 1 + 3K numbers, whatever it rejects.
  const gbuffer_data<T> gb = f.scene.make_gbuffer(12, 12);
  const auto g = gb.view();
  std::vector<ris_reservoir<T>> res(std::size_t(g.pixel_count()));
  for (int p = 0; p < g.pixel_count(); ++p) {
    counter_rng r = make_counter_rng(9u, std::uint32_t(p));
    res[std::size_t(p)] = ris_resample(g.at(p), f.view, dist, r, 4, T(0.05));
  }
  const auto load = [&](int p) { return ris_neighbour<T>{g.at(p), res[std::size_t(p)]}; };
  for (const int k : {0, 1, 5, ris_max_neighbours, ris_max_neighbours + 3}) {
    ris_spatial_settings<T> s;
    s.neighbours = k;
    s.radius = 3;
    counter_rng rng = make_counter_rng(2u, 3u);
    (void)ris_spatial_reuse(g.at(30), 30, 12, 12, f.view, res[30], load, s, rng, T(0.05));
    const int attempts = k < ris_max_neighbours ? k : ris_max_neighbours;
    CHECK(rng.counter == std::uint32_t(1 + 3 * attempts));
  }
}

TEMPLATE_TEST_CASE("ris: a candidate pass replayed by hand", "[estimators][ris]", float, double) {
  using T = TestType;
  const fixture<T> f;
  const auto& dist = f.dists[1];  // with holes: some draws land on the fallback
  const T dmin = T(0.05);
  for (const auto& g : f.gps) {
    INFO(g.name);
    for (const vpl_mode mode : {vpl_mode::point, vpl_mode::patch}) {
      const int m = 12;
      counter_rng rng = make_counter_rng(41u, 7u), replay = rng;
      const ris_reservoir<T> r = ris_resample(g.gp, f.view, dist, rng, m, dmin, mode);
      // By hand: every candidate's weight, the running sum, the selection rule u S < w.
      T sum = T(0);
      int kept = -1;
      ris_sample<T> kept_sample;
      for (int i = 0; i < m; ++i) {
        const T u = rng_next_unit<T>(replay);
        ris_sample<T> s;
        if (mode == vpl_mode::patch) {
          s.xi.x = rng_next_unit<T>(replay);
          s.xi.y = rng_next_unit<T>(replay);
        }
        const auto d = dist.sample(u);
        s.texel = int(d.index);
        const vpl<T> v = ris_sample_vpl(f.view, s, mode, std::numeric_limits<T>::infinity());
        const T target = luminance(vpl_contribution(g.gp, v, dmin));
        const T w = d.pmf > T(0) ? target / d.pmf : T(0);
        const T us = rng_next_unit<T>(replay);
        if (w > T(0)) {
          sum += w;
          if (us * sum < w || kept < 0) kept = i, kept_sample = s;
        }
      }
      CHECK(rng.counter == replay.counter);
      CHECK(r.confidence == T(m));
      if (kept < 0) {
        CHECK(r.kept.texel == -1);
        continue;
      }
      CHECK(ris_same_sample(r.kept, kept_sample));
      CHECK(same_bits(r.weight_sum, sum / T(m)));
      CHECK(same_bits(r.target, luminance(vpl_contribution(
                                    g.gp, ris_sample_vpl(f.view, kept_sample, mode, std::numeric_limits<T>::infinity()),
                                    dmin))));
      CHECK(same_bits(ris_contribution_weight(r), r.weight_sum / r.target));
    }
  }
}

TEMPLATE_TEST_CASE("ris: one candidate is one VPL sample", "[estimators][ris]", float, double) {
  using T = TestType;
  const fixture<T> f;
  const auto& dist = f.dists.front();
  const T dmin = T(0.05);
  const T tol = std::is_same<T, float>::value ? T(1e-5) : T(1e-12);
  int nonzero = 0;
  for (const auto& g : f.gps)
    for (std::uint32_t s = 0; s < 40; ++s) {
      counter_rng rng = make_counter_rng(77u, s), copy = rng;
      const ris_reservoir<T> r = ris_resample(g.gp, f.view, dist, rng, 1, dmin);
      const vec3<T> ris = ris_shade(g.gp, f.view, r, f.vis, dmin);
      const vec3<T> vs = vpl_sampling_sample(g.gp, f.view, dist, rng_next_unit<T>(copy), f.vis, dmin);
      INFO(g.name << " stream " << s);
      for (int c = 0; c < 3; ++c) CHECK(std::abs(ris[c] - vs[c]) <= tol * std::abs(vs[c]));
      nonzero += vs.x > T(0) ? 1 : 0;
    }
  CHECK(nonzero > 50);  // the comparison saw lit samples, not only zeros
}

TEMPLATE_TEST_CASE("ris: ranges of samples give the one-shot estimate bit for bit", "[estimators][ris]", float,
                   double) {
  using T = TestType;
  const fixture<T> f;
  const auto& dist = f.dists.front();
  for (const auto& g : f.gps)
    for (const vpl_mode mode : {vpl_mode::point, vpl_mode::patch}) {
      INFO(g.name << " mode " << int(mode));
      const int n = 6, m = 5;
      check_splits<T>(make_counter_rng(17u, 3u), cuts_of(n, {0, 0, 2, 2, 5, n}),
                      [&](counter_rng& rng) { return estimate_ris(g.gp, f.view, dist, rng, n, m, f.vis, T(0.05), mode); },
                      [&](estimator_state<T>& s, int b, int e) {
                        estimate_ris_range(g.gp, f.view, dist, s, b, e, m, f.vis, T(0.05), mode);
                      },
                      [&](const estimator_state<T>& s) { return estimate_ris_finish(s, n); });
    }
}

TEMPLATE_TEST_CASE("ris: keep k shades each distinct sample once", "[estimators][ris]", float, double) {
  using T = TestType;
  const fixture<T> f;
  const auto& dist = f.dists.front();
  const gather_point<T>& gp = f.gps[0].gp;  // floor_open: lit by most VPLs
  int queries = 0;
  const counting_visibility<T> vis{f.vis, &queries};
  // One candidate: all k reservoirs keep it, one query.
  ris_reservoir<T> res[ris_max_kept];
  counter_rng rng = make_counter_rng(3u, 0u);
  ris_resample_candidates(gp, f.view, dist, rng, 1, res, ris_max_kept, T(0.05));
  REQUIRE(ris_reservoir_has_sample(res[0]));
  const vec3<T> v = ris_shade_kept(gp, f.view, res, ris_max_kept, vis, T(0.05));
  CHECK(queries == 1);
  const vec3<T> one = ris_shade(gp, f.view, res[0], f.vis, T(0.05));
  CHECK(one.x > T(0));
  for (int c = 0; c < 3; ++c) CHECK(std::abs(v[c] - one[c]) <= T(1e-6) * one[c]);  // the mean of 8 equal values
  // Many candidates: one query per distinct kept sample, and the mean of the k values.
  queries = 0;
  ris_resample_candidates(gp, f.view, dist, rng, 64, res, ris_max_kept, T(0.05));
  int distinct = 0;
  vec3<T> sum(T(0));
  for (int j = 0; j < ris_max_kept; ++j) {
    bool seen = false;
    for (int i = 0; i < j; ++i) seen = seen || ris_same_sample(res[i].kept, res[j].kept);
    distinct += seen ? 0 : 1;
    sum += ris_shade(gp, f.view, res[j], f.vis, T(0.05));
    CHECK(res[j].weight_sum == res[0].weight_sum);
  }
  const vec3<T> mean = ris_shade_kept(gp, f.view, res, ris_max_kept, vis, T(0.05));
  CHECK(queries == distinct);
  CHECK(distinct > 1);
  for (int c = 0; c < 3; ++c) CHECK(std::abs(mean[c] - sum[c] / T(ris_max_kept)) <= T(1e-6) * std::abs(mean[c]));
  // More than ris_max_kept asked: ris_max_kept filled and averaged.
  CHECK(same_bits(ris_shade_kept(gp, f.view, res, ris_max_kept + 5, f.vis, T(0.05)), mean));
}

TEST_CASE("ris: the neighbour picker covers its square uniformly and stays in the image", "[estimators][ris]") {
  const int w = 20, h = 15, radius = 3, side = 2 * radius + 1;
  const int pixel = 7 * w + 10;
  std::map<std::pair<int, int>, int> counts;
  const int steps = side * 8;
  for (int a = 0; a < steps; ++a)
    for (int b = 0; b < steps; ++b) {
      const float u0 = (float(a) + 0.5f) / float(steps), u1 = (float(b) + 0.5f) / float(steps);
      const int p = ris_neighbour_pixel(pixel, w, h, radius, u0, u1);
      if (p < 0) continue;
      ++counts[{p % w - 10, p / w - 7}];
    }
  CHECK(counts.size() == std::size_t(side * side - 1));  // every offset but (0, 0)
  for (const auto& c : counts) {
    INFO(c.first.first << "," << c.first.second);
    CHECK(std::abs(c.first.first) <= radius);
    CHECK(std::abs(c.first.second) <= radius);
    CHECK(c.second == 64);  // 8 x 8 grid points per cell
  }
  // At the corner, half the square is outside: -1, never a wrapped pixel.
  for (int a = 0; a < steps; ++a) {
    const int p = ris_neighbour_pixel(0, w, h, radius, (float(a) + 0.5f) / float(steps), 0.99f);
    if (p >= 0) CHECK(p / w == 3);
    CHECK(ris_neighbour_pixel(0, w, h, radius, (float(a) + 0.5f) / float(steps), 0.0f) == -1);  // dy = -3
  }
  // u outside [0, 1): clamped (NaN and negative to the first cell, >= 1 to the last).
  CHECK(ris_neighbour_pixel(pixel, w, h, radius, std::nanf(""), 0.5f) == 7 * w + 7);
  CHECK(ris_neighbour_pixel(pixel, w, h, radius, -1.0f, 0.5f) == 7 * w + 7);
  CHECK(ris_neighbour_pixel(pixel, w, h, radius, 1.0f, 0.5f) == 7 * w + 13);
  CHECK(ris_neighbour_pixel(pixel, w, h, 0, 0.1f, 0.1f) == -1);
  CHECK(ris_neighbour_pixel(w * h, w, h, radius, 0.1f, 0.1f) == -1);
}

TEST_CASE("ris: the similarity test rejects other normals and points off the tangent plane", "[estimators][ris]") {
  using v3 = vec3<double>;
  const gather_point<double> q{v3(0, 0, 0), v3(0, 2, 0), v3(0.5)};
  const auto at = [](v3 p, v3 n) { return gather_point<double>{p, n, v3(0.5)}; };
  CHECK(ris_neighbour_similar(q, at(v3(1, 0, 0), v3(0, 1, 0)), 0.9, 0.1));
  CHECK(ris_neighbour_similar(q, at(v3(1, 0.09, 0), v3(0, 1, 0)), 0.9, 0.1));
  CHECK_FALSE(ris_neighbour_similar(q, at(v3(1, 0.11, 0), v3(0, 1, 0)), 0.9, 0.1));   // a step (depth edge)
  CHECK_FALSE(ris_neighbour_similar(q, at(v3(1, 0, 0), v3(0.5, 0.5, 0)), 0.9, 0.1));  // 45 degrees
  CHECK_FALSE(ris_neighbour_similar(q, at(v3(1, 0, 0), v3(0, -1, 0)), 0.9, 0.1));     // the other side
  CHECK_FALSE(ris_neighbour_similar(q, at(v3(1, 0, 0), v3(0, 0, 0)), 0.9, 0.1));      // background
  CHECK(ris_neighbour_similar(q, at(v3(1, 5, 0), v3(-1, 0, 0)), -2.0, std::numeric_limits<double>::infinity()));
}

TEST_CASE("ris: the buffer record holds a reservoir bit for bit", "[estimators][ris]") {
  static_assert(sizeof(gpu::ris_reservoir_record) == 32, "32-byte record");
  ris_reservoir<float> r;
  r.kept.texel = 1234;
  r.kept.xi = vec2<float>(0.25f, std::nextafter(1.0f, 0.0f));
  r.weight_sum = 3.5e-7f;
  r.target = 1.25e3f;
  r.confidence = 96.0f;
  const ris_reservoir<float> back = gpu::ris_reservoir_from_record(gpu::make_ris_reservoir_record(r));
  CHECK(ris_same_sample(back.kept, r.kept));
  CHECK(same_bits(back.weight_sum, r.weight_sum));
  CHECK(same_bits(back.target, r.target));
  CHECK(same_bits(back.confidence, r.confidence));
  const gpu::ris_reservoir_record empty = gpu::make_ris_reservoir_record(ris_reservoir<float>{});
  CHECK(empty.texel == -1);
  CHECK_FALSE(ris_reservoir_has_sample(gpu::ris_reservoir_from_record(empty)));
}

TEMPLATE_TEST_CASE("ris: a reuse without neighbours returns the canonical reservoir", "[estimators][ris]", float,
                   double) {
  using T = TestType;
  const fixture<T> f;
  const auto& dist = f.dists.front();
  const auto load = [](int) -> ris_neighbour<T> { FAIL("no neighbour may be loaded"); return {}; };
  for (const auto& g : f.gps)
    for (const ris_reuse_mis mis : {ris_reuse_mis::pairwise, ris_reuse_mis::balance}) {
      counter_rng rng = make_counter_rng(8u, 1u);
      const ris_reservoir<T> c = ris_resample(g.gp, f.view, dist, rng, 16, T(0.05));
      const T u[1] = {T(0.999)};
      const ris_reservoir<T> r = ris_combine(g.gp, f.view, c, static_cast<const int*>(nullptr), 0, load, u, mis, T(0.05));
      INFO(g.name << " mis " << int(mis));
      CHECK(ris_same_sample(r.kept, c.kept));
      CHECK(same_bits(r.target, c.target));
      CHECK(same_bits(r.weight_sum, c.weight_sum));
      CHECK(r.confidence == c.confidence);
    }
}
