// SPDX-License-Identifier: MIT
// estimators/ris_mis_estimator.hpp, exactly (no statistics): the random-number layout that the GLSL
// mirror follows (step j: the M candidates of one reservoir, u [u0 u1] per candidate then the
// selection u, then u0 u1 of direction j), its two limits (n_ris = 0 is estimate_gathering with
// the same numbers; one candidate per sample is estimate_mis's VPL sample), the split into ranges,
// and the target h = n2 pmf f / (n1 p1 + n2 p2) of a candidate. The statistics are in
// tests/statistical/estimators_ris_mis_unbiased_test.cpp.
#include <synthetic_scene.hpp>

#include <vplkit/builders/flux_weights.hpp>
#include <vplkit/builders/vpl_distribution.hpp>
#include <vplkit/distribution/discrete_cdf.hpp>
#include <vplkit/estimators/gathering_estimator.hpp>
#include <vplkit/estimators/mis_estimator.hpp>
#include <vplkit/estimators/ris_mis_estimator.hpp>
#include <vplkit/vpl/luminance.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <tuple>
#include <vector>

using namespace vplkit;
using namespace vplkit_test;

namespace {

struct room {
  lit_room<double> r{16};
  defensive_mixture<double> flux = make_vpl_distribution(build_flux_weights(r.view), r.view, 0.0);
};

const room& fx() {
  static const room f;
  return f;
}

// The flux distribution, recording every u it is asked to draw with.
struct recording_draw {
  const defensive_mixture<double>* d;
  std::vector<double>* us;
  discrete_sample<double> sample(double u) const {
    us->push_back(u);
    return d->sample(u);
  }
  double pmf(std::size_t i) const { return d->pmf(i); }
};

bool close(vec3<double> a, vec3<double> b, double rel) {
  for (int c = 0; c < 3; ++c)
    if (!(std::abs(a[c] - b[c]) <= rel * std::max(std::abs(a[c]), std::abs(b[c])) + 1e-300)) return false;
  return true;
}

}  // namespace

TEST_CASE("ris-mis: the random-number layout, candidates then direction per step") {
  const room& f = fx();
  const auto& r = f.r;
  const gather_point<double>& gp = r.gps[0].gp;
  const double tol = 0.2;
  for (const vpl_mode mode : {vpl_mode::point, vpl_mode::patch}) {
    const std::uint32_t per = mode == vpl_mode::patch ? 4u : 2u;  // u [u0 u1] + the selection u
    for (const auto& [n1, n2, m] : std::vector<std::tuple<int, int, int>>{{3, 2, 5}, {2, 4, 3}, {0, 3, 4}, {4, 0, 7}}) {
      INFO("mode " << int(mode) << " n_dirs " << n1 << " n_ris " << n2 << " M " << m);
      std::vector<double> us;
      const recording_draw rec{&f.flux, &us};
      counter_rng rng = make_counter_rng(11u, 3u);
      (void)estimate_ris_mis(gp, r.view, rec, rng, n1, n2, m, r.tracer, r.vis, tol, mode);
      // Every number drawn: n_ris M (per) + 2 n_dirs.
      CHECK(rng.counter == std::uint32_t(n2 * m) * per + 2u * std::uint32_t(n1));
      // Candidate i of step j draws at offset(j) + i per, offset(j) = the numbers of the steps before.
      REQUIRE(us.size() == std::size_t(n2 * m));
      std::uint32_t offset = 0;
      std::size_t k = 0;
      for (int j = 0; j < std::max(n1, n2); ++j) {
        if (j < n2)
          for (int i = 0; i < m; ++i, ++k) {
            counter_rng at = make_counter_rng(11u, 3u);
            at.counter = offset + std::uint32_t(i) * per;
            CHECK(us[k] == rng_next_unit<double>(at));
          }
        offset += (j < n2 ? std::uint32_t(m) * per : 0u) + (j < n1 ? 2u : 0u);
      }
    }
  }
}

TEST_CASE("ris-mis: the directions take the numbers after their step's candidates (estimate_gathering's)") {
  const room& f = fx();
  const auto& r = f.r;
  const double tol = 0.2;
  // No VPL strategy reaches anything (an empty distribution: p2 = 0): the directions alone, each
  // f / (n1 p1), that is estimate_gathering's sample of the same two numbers over n1.
  const discrete_cdf<double> empty(std::vector<double>(std::size_t(r.view.texel_count()), 0.0));
  const int n1 = 3, n2 = 2, m = 4;
  for (const auto& g : r.gps) {
    counter_rng rng = make_counter_rng(12u, 0u);
    const vec3<double> e = estimate_ris_mis(g.gp, r.view, empty, rng, n1, n2, m, r.tracer, r.vis, tol);
    vec3<double> expected(0.0);
    std::uint32_t offset = 0;
    for (int j = 0; j < n1; ++j) {
      if (j < n2) offset += std::uint32_t(m) * 2u;
      counter_rng at = make_counter_rng(12u, 0u);
      at.counter = offset;
      expected += estimate_gathering(g.gp, r.view, at, 1, r.tracer, tol) / double(n1);
      offset += 2u;
    }
    INFO(g.name);
    CHECK(close(e, expected, 1e-12));
    // n_ris = 0: estimate_gathering itself, number for number.
    counter_rng a = make_counter_rng(13u, 0u), b = a;
    CHECK(close(estimate_ris_mis(g.gp, r.view, f.flux, a, 8, 0, 16, r.tracer, r.vis, tol),
                estimate_gathering(g.gp, r.view, b, 8, r.tracer, tol), 1e-12));
    CHECK(a.counter == b.counter);
    // No candidates (M <= 0): n_ris counts as 0, so the directions weigh as gathering alone.
    for (const int m0 : {0, -2}) {
      counter_rng c = make_counter_rng(13u, 1u), d = c;
      CHECK(close(estimate_ris_mis(g.gp, r.view, f.flux, c, 8, 5, m0, r.tracer, r.vis, tol),
                  estimate_gathering(g.gp, r.view, d, 8, r.tracer, tol), 1e-12));
      CHECK(c.counter == d.counter);
    }
  }
}

TEST_CASE("ris-mis: the weights count each RIS sample as max(1, M/2) VPL samples") {
  // n2 = N max(1, M/2) in float and double alike (integers and halves: exact), 0 for no samples.
  for (const auto& [n, m, expected] : std::vector<std::tuple<int, int, double>>{
           {4, 1, 4.0}, {4, 2, 4.0}, {3, 5, 7.5}, {2, 16, 16.0}, {16, 32, 256.0}, {0, 8, 0.0}, {3, 0, 0.0},
           {-1, 4, 0.0}, {2, -3, 0.0}}) {
    INFO("N " << n << " M " << m);
    CHECK(ris_mis_vpl_samples<double>(n, m) == expected);
    CHECK(ris_mis_vpl_samples<float>(n, m) == float(expected));
  }
  // The estimate written out with them: the reservoirs and the directions weigh with n2 = 5 (N = 2
  // RIS samples of M = 5), the RIS values are divided by N = 2. Weights of n2 = N (the count of
  // estimate_mis) or a division by n2 would give other values.
  const room& f = fx();
  const auto& r = f.r;
  const double tol = 0.2;
  const int nd = 3, nr = 2, m = 5;
  const double n1 = nd, n2 = 5.0;
  int differs = 0;
  for (const auto& g : r.gps)
    for (const vpl_mode mode : {vpl_mode::point, vpl_mode::patch}) {
      const counter_rng start = make_counter_rng(17u, 3u);
      counter_rng a = start, q = start;
      const vec3<double> e = estimate_ris_mis(g.gp, r.view, f.flux, a, nd, nr, m, r.tracer, r.vis, tol, mode);
      const orthonormal_basis<double> frame = make_orthonormal_basis(gather_point_shading_normal(g.gp));
      vec3<double> sum(0.0), as_mis(0.0);
      for (int j = 0; j < std::max(nd, nr); ++j) {
        if (j < nr) {
          counter_rng q1 = q;
          ris_mis_kept<double> kept;
          const ris_reservoir<double> res = ris_mis_resample(g.gp, r.view, f.flux, q, m, n1, n2, mode, tol, kept);
          sum += ris_mis_shade_kept(g.gp, res, kept, r.vis) / double(nr);
          ris_mis_kept<double> kept1;
          const ris_reservoir<double> res1 = ris_mis_resample(g.gp, r.view, f.flux, q1, m, n1, double(nr), mode, tol,
                                                              kept1);
          as_mis += ris_mis_shade_kept(g.gp, res1, kept1, r.vis) / double(nr);
        }
        if (j < nd) {
          const double u0 = rng_next_unit<double>(q), u1 = rng_next_unit<double>(q);
          const vec3<double> local = sample_cosine_hemisphere(vec2<double>(u0, u1));
          sum += mis_gathering_sample(g.gp, r.view, f.flux, frame, local, r.tracer, tol, n1, n2, mis_mode::solid_angle,
                                      mode);
          as_mis += mis_gathering_sample(g.gp, r.view, f.flux, frame, local, r.tracer, tol, n1, double(nr),
                                         mis_mode::solid_angle, mode);
        }
      }
      INFO(g.name << " mode " << int(mode));
      CHECK(e == sum);
      CHECK(q.counter == a.counter);
      if (!close(e, as_mis, 1e-6)) ++differs;
    }
  CHECK(differs > 4);  // the count matters at most of the room's points
}

TEST_CASE("ris-mis: one candidate per sample is estimate_mis's VPL sample") {
  const room& f = fx();
  const auto& r = f.r;
  const double tol = 0.2, n1 = 4.0, n2 = 3.0;
  int nonzero = 0;
  for (const auto& g : r.gps)
    for (const vpl_mode mode : {vpl_mode::point, vpl_mode::patch})
      for (std::uint32_t s = 0; s < 16; ++s) {
        counter_rng rng = make_counter_rng(14u, s), numbers = rng;
        const double u = rng_next_unit<double>(numbers);
        const double u0 = rng_next_unit<double>(numbers), u1 = rng_next_unit<double>(numbers);
        const ris_reservoir<double> res = ris_mis_resample(g.gp, r.view, f.flux, rng, 1, n1, n2, mode, tol);
        const vec3<double> ris = ris_mis_shade(g.gp, r.view, f.flux, res, r.vis, n1, n2, mode, tol) / n2;
        const vec3<double> mis =
            mode == vpl_mode::patch
                ? mis_vpl_patch_sample(g.gp, r.view, f.flux, u, vec2<double>(u0, u1), r.vis, n1, n2,
                                       mis_mode::solid_angle, tol)
                : mis_vpl_sample(g.gp, r.view, f.flux, u, r.vis, n1, n2, mis_mode::solid_angle);
        INFO(g.name << " mode " << int(mode) << " stream " << s);
        CHECK(close(ris, mis, 1e-12));
        if (luminance(mis) > 0.0) ++nonzero;
      }
  CHECK(nonzero > 50);
}

TEST_CASE("ris-mis: the target is n2 pmf times the MIS value, and ranges compose") {
  const room& f = fx();
  const auto& r = f.r;
  const gather_point<double>& gp = r.gps[0].gp;
  const double tol = 0.2, n1 = 2.0, n2 = 5.0;
  int checked = 0;
  for (int t = 0; t < r.view.texel_count(); t += 7) {
    const double pmf = f.flux.pmf(std::size_t(t));
    if (!(pmf > 0.0)) continue;
    ris_sample<double> s;
    s.texel = t;
    vpl<double> v;
    const vec3<double> h = ris_mis_unshadowed(gp, r.view, s, pmf, n1, n2, vpl_mode::point, tol, v);
    const vec3<double> value =
        mis_vpl_unshadowed(gp, r.view, t, r.view.vpl_at(t), pmf, mis_texel_patch_area(r.view, t), n1, n2);
    CHECK(close(h, value * (n2 * pmf), 1e-12));
    if (luminance(h) > 0.0) ++checked;
  }
  CHECK(checked > 20);
  // [0, 2) then [2, 5) is the whole estimate, number for number.
  counter_rng a = make_counter_rng(15u, 0u), b = a;
  const vec3<double> whole = estimate_ris_mis(gp, r.view, f.flux, a, 5, 3, 8, r.tracer, r.vis, tol);
  estimator_state<double> st = make_estimator_state<double>(b);
  estimate_ris_mis_range(gp, r.view, f.flux, st, 0, 2, 5, 3, 8, r.tracer, r.vis, tol);
  estimate_ris_mis_range(gp, r.view, f.flux, st, 2, 5, 5, 3, 8, r.tracer, r.vis, tol);
  CHECK(estimate_ris_mis_finish(st) == whole);
  CHECK(st.rng.counter == a.counter);
}

TEST_CASE("ris-mis: the shade from the kept h and point is ris_mis_shade's, bit for bit") {
  // estimate_ris_mis shades from what ris_mis_resample kept instead of evaluating h again; the
  // draw's pmf is the distribution's pmf(texel), so the value must not change in any bit.
  const room& f = fx();
  const auto& r = f.r;
  const double tol = 0.2;
  int shaded = 0;
  for (const auto& g : r.gps)
    for (const vpl_mode mode : {vpl_mode::point, vpl_mode::patch})
      for (const int m : {1, 2, 8})
        for (const double n1 : {0.0, 4.0})
          for (std::uint32_t s = 0; s < 12; ++s) {
            counter_rng a = make_counter_rng(21u, s), b = a;
            ris_mis_kept<double> kept;
            const ris_reservoir<double> ra = ris_mis_resample(g.gp, r.view, f.flux, a, m, n1, 3.0, mode, tol, kept);
            const ris_reservoir<double> rb = ris_mis_resample(g.gp, r.view, f.flux, b, m, n1, 3.0, mode, tol);
            REQUIRE(ris_same_sample(ra.kept, rb.kept));
            REQUIRE(ra.weight_sum == rb.weight_sum);
            const vec3<double> from_kept = ris_mis_shade_kept(g.gp, ra, kept, r.vis);
            const vec3<double> again = ris_mis_shade(g.gp, r.view, f.flux, rb, r.vis, n1, 3.0, mode, tol);
            INFO(g.name << " mode " << int(mode) << " M " << m << " n1 " << n1 << " stream " << s);
            CHECK(from_kept == again);
            if (ris_reservoir_has_sample(ra)) {
              CHECK(luminance(kept.h) == ra.target);
              ++shaded;
            } else {
              CHECK(kept.h == vec3<double>(0.0));
            }
          }
  CHECK(shaded > 500);
  // The float instance, as the renderer runs it: the whole estimate against resample + shade.
  const lit_room<float> rf{16};
  const defensive_mixture<float> flux_f = make_vpl_distribution(build_flux_weights(rf.view), rf.view, 0.0f);
  int nonzero = 0;
  for (const auto& g : rf.gps)
    for (const vpl_mode mode : {vpl_mode::point, vpl_mode::patch})
      for (std::uint32_t s = 0; s < 12; ++s) {
        counter_rng a = make_counter_rng(22u, s), b = a;
        const vec3<float> whole = estimate_ris_mis(g.gp, rf.view, flux_f, a, 0, 3, 2, rf.tracer, rf.vis, 0.2f, mode);
        vec3<float> sum(0.0f);
        for (int k = 0; k < 3; ++k) {
          const ris_reservoir<float> res = ris_mis_resample(g.gp, rf.view, flux_f, b, 2, 0.0f, 3.0f, mode, 0.2f);
          sum += ris_mis_shade(g.gp, rf.view, flux_f, res, rf.vis, 0.0f, 3.0f, mode, 0.2f) / 3.0f;
        }
        INFO(g.name << " mode " << int(mode) << " stream " << s);
        CHECK(whole == sum);
        if (luminance(whole) > 0.0f) ++nonzero;
      }
  CHECK(nonzero > 20);
}
