// SPDX-License-Identifier: MIT
// speed_vs_error's analysis helpers (examples/speed_vs_error/{metrics,pareto}.hpp) on hand-made
// numbers whose answers are known in closed form.
#include "metrics.hpp"
#include "pareto.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <limits>
#include <random>

using speed_vs_error::cost_error_point;

TEST_CASE("pareto front keeps only points no other point beats in time and error") {
  const std::vector<cost_error_point> pts = {
      {"a", 1, 10.0, 1.0},   // fastest: on the front
      {"b", 1, 12.0, 1.5},   // slower and worse than a: dominated
      {"a", 4, 40.0, 0.5},   // on the front
      {"b", 4, 30.0, 0.6},   // slower than a@1 but more accurate: on the front
      {"c", 1, 30.0, 0.7},   // same time as b@4, worse: dominated
      {"c", 4, 100.0, 0.5},  // same error as a@4, slower: dominated (strictly better error needed)
      {"d", 1, 5.0, std::numeric_limits<double>::quiet_NaN()},  // unusable: ignored
      {"d", 2, 0.0, 0.1},                                        // zero time: ignored
  };
  const auto f = speed_vs_error::pareto_front(pts);
  REQUIRE(f.size() == 3);
  CHECK(f[0].method == "a");
  CHECK(f[0].samples == 1);
  CHECK(f[1].method == "b");
  CHECK(f[1].samples == 4);
  CHECK(f[2].method == "a");
  CHECK(f[2].samples == 4);
  for (std::size_t i = 1; i < f.size(); ++i) {
    CHECK(f[i].ms > f[i - 1].ms);
    CHECK(f[i].error < f[i - 1].error);
  }
}

TEST_CASE("time to error interpolates on the power law between bracketing points") {
  // error = 2 / sqrt(ms): halving the error costs 4x the time; log-log interpolation is exact.
  std::vector<cost_error_point> m;
  for (double ms : {1.0, 4.0, 16.0, 64.0}) m.push_back({"m", 0, ms, 2.0 / std::sqrt(ms)});
  const auto t = speed_vs_error::time_to_error(m, 2.0 / std::sqrt(8.0));
  REQUIRE(t.has_value());
  CHECK(*t == Approx(8.0).epsilon(1e-12));
  // Already reached by the fastest point.
  CHECK(*speed_vs_error::time_to_error(m, 5.0) == Approx(1.0));
  // Never reached: no extrapolation.
  CHECK_FALSE(speed_vs_error::time_to_error(m, 0.1).has_value());
  // Order of the input does not matter.
  std::swap(m[0], m[3]);
  CHECK(*speed_vs_error::time_to_error(m, 2.0 / std::sqrt(8.0)) == Approx(8.0).epsilon(1e-12));
  // A non-monotone curve: the first crossing (fastest) counts.
  const std::vector<cost_error_point> bumpy = {{"m", 0, 1, 1.0}, {"m", 0, 2, 0.4}, {"m", 0, 3, 0.6}, {"m", 0, 4, 0.3}};
  CHECK(*speed_vs_error::time_to_error(bumpy, 0.5) < 2.0);
}

TEST_CASE("error targets span from the level every method reaches to the best error") {
  const std::vector<cost_error_point> pts = {
      {"a", 1, 1, 1.0}, {"a", 4, 4, 0.1}, {"b", 1, 1, 2.0}, {"b", 4, 4, 0.4}};
  const auto t = speed_vs_error::error_targets(pts, 3);
  REQUIRE(t.size() == 3);
  CHECK(t[0] == Approx(0.4));  // b's best: both methods reach it
  CHECK(t[1] == Approx(0.2));  // geometric middle
  CHECK(t[2] == Approx(0.1));  // a's best
  CHECK(speed_vs_error::error_targets({}, 3).empty());
  // The last target is exactly the best error, so the best method reaches it at its own point.
  const std::vector<cost_error_point> odd = {{"a", 1, 3.0, 0.0297804}, {"a", 2, 9.0, 0.0297803}, {"b", 1, 1.0, 0.1}};
  const auto t2 = speed_vs_error::error_targets(odd, 4);
  REQUIRE(t2.size() == 4);
  CHECK(t2.back() == 0.0297803);
  std::vector<cost_error_point> a_only(odd.begin(), odd.begin() + 2);
  CHECK(speed_vs_error::time_to_error(a_only, t2.back()).has_value());
}

TEST_CASE("image error metrics follow their stated formulas") {
  vplrender::image_rgb x, r;
  x.width = r.width = 2;
  x.height = r.height = 1;
  r.rgb = {1, 1, 1, 0, 0, 0};
  x.rgb = {2, 1, 1, 0, 0, 0.5f};
  const auto e = speed_vs_error::compare(x, r);
  CHECK(e.rmse == Approx(std::sqrt((1.0 + 0.25) / 6.0)));
  CHECK(e.relmse == Approx((1.0 / (1.0 + 1e-2) + 0.25 / 1e-2) / 6.0));
}

TEST_CASE("reference noise and the net error follow their stated formulas") {
  vplrender::image_rgb r, r2, x;
  x.width = r.width = r2.width = 2;
  x.height = r.height = r2.height = 1;
  r.rgb = {1, 1, 1, 0, 0, 0};
  r2.rgb = {2, 1, 1, 0, 0, 0.5f};
  x.rgb = {1.5f, 1, 3, 0, 0, 0};
  // v = (r - r2)^2 / 2 = {0.5, 0, 0, 0, 0, 0.125}; m = (r + r2) / 2 = {1.5, 1, 1, 0, 0, 0.25}.
  const auto n = speed_vs_error::estimate_noise(r, r2);
  CHECK(n.mse == Approx((0.5 + 0.125) / 6.0));
  CHECK(n.relmse == Approx((0.5 / (2.25 + 1e-2) + 0.125 / (0.0625 + 1e-2)) / 6.0));
  CHECK(n.mse_se > 0.0);
  CHECK(n.relmse_se > 0.0);
  // (x - r)^2 - v = {0.25 - 0.5, 0, 4, 0, 0, -0.125}.
  const auto net = speed_vs_error::compare_net(x, r, r2);
  CHECK(net.rmse == Approx(std::sqrt((-0.25 + 4.0 - 0.125) / 6.0)));
  CHECK(net.relmse == Approx((-0.25 / (2.25 + 1e-2) + 4.0 / (1.0 + 1e-2) - 0.125 / (0.0625 + 1e-2)) / 6.0));
  // Closer to the truth than the noise tells: RMSE 0, the relMSE signed.
  const auto below = speed_vs_error::compare_net(r, r, r2);
  CHECK(below.rmse == 0.0);
  CHECK(below.relmse < 0.0);
  vplrender::image_rgb small = r;
  small.width = 1;
  small.rgb.resize(3);
  CHECK_THROWS(speed_vs_error::estimate_noise(r, small));
  CHECK_THROWS(speed_vs_error::compare_net(x, r, small));
  CHECK_THROWS(speed_vs_error::compare_net(small, r, r2));
}

TEST_CASE("removing the reference's noise recovers the error against the truth") {
  // Truth t in [0.5, 2]; two references and a run, each t plus independent Gaussian noise (sd
  // 0.05 each: 2.5-10 % of t, as a converged reference's noise is a few %). Against r the run's
  // MSE is about 0.0025 + 0.0025: half of it is the reference's. Net of the noise measured from r and r2
  // it is the run's own.
  const int w = 200, h = 200;
  vplrender::image_rgb t, r, r2, x;
  for (vplrender::image_rgb* im : {&t, &r, &r2, &x}) {
    im->width = w;
    im->height = h;
    im->rgb.resize(std::size_t(3) * w * h);
  }
  std::mt19937 gen(12345u);
  std::uniform_real_distribution<float> level(0.5f, 2.0f);
  std::normal_distribution<float> noise_sd(0.0f, 0.05f);
  for (std::size_t i = 0; i < t.rgb.size(); ++i) {
    t.rgb[i] = level(gen);
    r.rgb[i] = t.rgb[i] + noise_sd(gen);
    r2.rgb[i] = t.rgb[i] + noise_sd(gen);
    x.rgb[i] = t.rgb[i] + noise_sd(gen);
  }
  const auto truth = speed_vs_error::compare(x, t);
  const auto raw = speed_vs_error::compare(x, r);
  const auto noise = speed_vs_error::estimate_noise(r, r2);
  const auto net = speed_vs_error::compare_net(x, r, r2);
  CHECK(raw.rmse * raw.rmse == Approx(0.005).epsilon(0.03));  // twice the run's own: the floor
  CHECK(raw.relmse == Approx(truth.relmse + noise.relmse).epsilon(0.05));
  CHECK(noise.mse == Approx(0.0025).epsilon(0.03));
  CHECK(net.rmse * net.rmse == Approx(truth.rmse * truth.rmse).epsilon(0.05));
  CHECK(net.relmse == Approx(truth.relmse).epsilon(0.03));
  CHECK(noise.relmse_se < 0.02 * noise.relmse);
}
