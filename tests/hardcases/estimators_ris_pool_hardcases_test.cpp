// SPDX-License-Identifier: MIT
// Presampled candidates for ris-mis (estimators/ris_candidate_pool.hpp), each hard case its own test:
// an empty pool (pool_size 0), a pool of one entry, a pool whose every entry is empty (pmf 0),
// entries with NaN, infinite, denormal or degenerate fields, entries whose patch point moved to its
// texel's centre, an invalid gather point, candidate and sample counts of zero or below. Nothing may
// be NaN or Inf, in float and double, and the numbers drawn follow the layout (2 M per reservoir
// whatever the vpl_mode, 2 per direction) whatever the pool holds; only an empty pool, an invalid
// gather point and the counts that make a reservoir empty draw nothing for it.
#include <estimator_checks.hpp>
#include <float_bits.hpp>
#include <special_values.hpp>
#include <synthetic_scene.hpp>

#include <vplkit/builders/flux_weights.hpp>
#include <vplkit/builders/vpl_distribution.hpp>
#include <vplkit/distribution/discrete_cdf.hpp>
#include <vplkit/estimators/gathering_estimator.hpp>
#include <vplkit/estimators/mis_estimator.hpp>
#include <vplkit/estimators/ris_candidate_pool.hpp>
#include <vplkit/estimators/ris_mis_estimator.hpp>
#include <vplkit/estimators/vpl_sum.hpp>
#include <vplkit/vpl/luminance.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdint>
#include <limits>
#include <tuple>
#include <type_traits>
#include <utility>
#include <vector>

using namespace vplkit;
using namespace vplkit_test;

namespace {

template <class T>
struct room {
  lit_room<T> r{16};
  defensive_mixture<T> flux = make_vpl_distribution(build_flux_weights(r.view), r.view, T(0));
  T tol = T(0.2);
  // A texel whose VPL lights floor_open, and so do its patch points at the jitters the cases use
  // (a texel on the disk's rim lights it as a point but rejects patch points there).
  int lit_texel() const {
    const gather_point<T>& gp = r.gps[0].gp;
    for (int t = 0; t < r.view.texel_count(); ++t) {
      bool lit = luminance(vpl_visible_contribution(gp, r.view, t, r.vis, T(0))) > T(0);
      for (const vec2<T> xi : {vec2<T>(T(0.1), T(0.9)), vec2<T>(T(0.5)), vec2<T>(T(0.99), T(0.02))})
        lit = lit && luminance(vpl_patch_visible_contribution(gp, r.view, t, xi, r.vis, T(0), tol)) > T(0);
      if (lit) return t;
    }
    return -1;
  }
  // A pool of n entries of the flux distribution.
  std::vector<ris_pool_entry<T>> pool(std::uint32_t n, std::uint32_t seed, vpl_mode mode) const {
    std::vector<ris_pool_entry<T>> p;
    for (std::uint32_t i = 0; i < n; ++i) p.push_back(ris_pool_draw_entry(r.view, flux, seed, i, mode, tol));
    return p;
  }
  // The entry of the draw (t, pmf) (xi: the jitter, patch VPLs).
  ris_pool_entry<T> entry(int t, T pmf, vpl_mode mode, vec2<T> xi = vec2<T>(T(0.5))) const {
    ris_mis_draw<T> c;
    c.s.texel = t;
    c.s.xi = mode == vpl_mode::patch ? xi : vec2<T>(T(0));
    c.pmf = pmf;
    return ris_pool_make_entry(r.view, c, mode, tol);
  }
};

// Numbers an estimate draws: 2 M per reservoir, 2 per direction.
inline std::uint32_t pooled_count(int n_dirs, int n_ris, int m) {
  return 2u * std::uint32_t(n_ris * m) + 2u * std::uint32_t(n_dirs);
}

// The directions of an estimate alone: step j's direction takes the numbers after the step's
// reservoir (2 M, or none when `reservoirs_draw` is false), weighed as ris-mis weighs them.
template <class T, class D>
vec3<T> directions_only(const room<T>& f, const gather_point<T>& gp, const D& dist, counter_rng rng, int n_dirs,
                        int n_ris, int m, bool reservoirs_draw, vpl_mode mode) {
  const orthonormal_basis<T> frame = make_orthonormal_basis(gather_point_shading_normal(gp));
  vec3<T> sum(T(0));
  for (int j = 0; j < std::max(n_dirs, n_ris); ++j) {
    if (j < n_ris && reservoirs_draw) rng.counter += 2u * std::uint32_t(m);
    if (j < n_dirs) {
      const T u0 = rng_next_unit<T>(rng), u1 = rng_next_unit<T>(rng);
      // The weights count the RIS samples as ris-mis does (n_ris max(1, M/2)); n_ris 0: none.
      sum += mis_gathering_sample(gp, f.r.view, dist, frame, sample_cosine_hemisphere(vec2<T>(u0, u1)), f.r.tracer,
                                  f.tol, T(n_dirs), ris_mis_vpl_samples<T>(n_ris, m), mis_mode::solid_angle, mode);
    }
  }
  return sum;
}

}  // namespace

TEMPLATE_TEST_CASE("ris pool hard case: an empty pool (pool_size 0) keeps nothing and draws nothing",
                   "[hardcases][ris-pool]", float, double) {
  // Reading entry 0 of an empty pool would crash (nullptr) or read past the buffer; drawing the
  // candidates' numbers anyway would move the directions' numbers.
  using T = TestType;
  const room<T> f;
  const std::vector<ris_pool_entry<T>> some = f.pool(4, 1u, vpl_mode::point);
  for (const ris_pool_entry<T>* p : {static_cast<const ris_pool_entry<T>*>(nullptr), some.data()})
    for (const auto& g : f.r.gps)
      for (const T n1 : {T(0), T(4)}) {
        INFO(g.name << " n1 " << n1 << " pointer " << (p != nullptr));
        counter_rng rng = make_counter_rng(1u, 0u);
        ris_mis_kept<T> kept;
        kept.h = vec3<T>(T(1));  // overwritten
        const ris_reservoir<T> r = ris_mis_resample_pooled(g.gp, p, 0u, rng, 16, n1, T(4), kept);
        CHECK_FALSE(ris_reservoir_has_sample(r));
        CHECK(r.kept.texel == -1);
        CHECK(r.weight_sum == T(0));
        CHECK(r.target == T(0));
        CHECK(r.confidence == T(0));
        CHECK(kept.h == vec3<T>(T(0)));
        CHECK(rng.counter == 0u);
        CHECK(ris_mis_shade_kept(g.gp, r, kept, f.r.vis) == vec3<T>(T(0)));
        // The whole estimate: without directions 0 and no numbers; with them, only the directions',
        // weighed as gathering alone (n2 = 0): weights that counted RIS lines adding nothing would
        // lose the integral of w2 f.
        for (const vpl_mode mode : {vpl_mode::point, vpl_mode::patch}) {
          counter_rng a = make_counter_rng(1u, 1u);
          CHECK(estimate_ris_mis_pooled(g.gp, f.r.view, f.flux, p, 0u, a, 0, 4, 16, f.r.tracer, f.r.vis, f.tol,
                                        mode) == vec3<T>(T(0)));
          CHECK(a.counter == 0u);
          counter_rng b = make_counter_rng(1u, 2u);
          const vec3<T> e =
              estimate_ris_mis_pooled(g.gp, f.r.view, f.flux, p, 0u, b, 3, 4, 16, f.r.tracer, f.r.vis, f.tol, mode);
          CHECK(finite_nonneg(e));
          CHECK(b.counter == pooled_count(3, 0, 0));
          CHECK(same_bits(e, directions_only(f, g.gp, f.flux, make_counter_rng(1u, 2u), 3, 0, 16, false, mode)));
          // ... which is estimate_ris_mis without candidates (M = 0), number for number.
          counter_rng c = make_counter_rng(1u, 2u);
          CHECK(same_bits(e, estimate_ris_mis(g.gp, f.r.view, f.flux, c, 3, 4, 0, f.r.tracer, f.r.vis, f.tol, mode)));
          CHECK(c.counter == b.counter);
          // The range form alike, split anywhere (it is what a renderer spreading the steps calls).
          for (int k = 0; k <= 4; ++k) {
            estimator_state<T> st = make_estimator_state<T>(make_counter_rng(1u, 2u));
            estimate_ris_mis_pooled_range(g.gp, f.r.view, f.flux, p, 0u, st, 0, k, 3, 4, 16, f.r.tracer, f.r.vis,
                                          f.tol, mode);
            estimate_ris_mis_pooled_range(g.gp, f.r.view, f.flux, p, 0u, st, k, 4, 3, 4, 16, f.r.tracer, f.r.vis,
                                          f.tol, mode);
            CHECK(same_bits(estimate_ris_mis_finish(st), e));
            CHECK(st.rng.counter == b.counter);
          }
        }
      }
}

TEMPLATE_TEST_CASE("ris pool hard case: a pool of one entry is estimate_ris_mis with that one draw",
                   "[hardcases][ris-pool]", float, double) {
  // Every candidate reads the one entry. Point VPLs: the candidates of estimate_ris_mis with a
  // distribution that always draws that texel with that pmf take the same two numbers each (u, then
  // the selection u), so the whole estimate must agree bit for bit. Without directions it is the
  // contribution over the pmf whatever M (W = (1/M) M w / target = 1 / pmf): a weight_sum not divided
  // by M would give M times that.
  using T = TestType;
  const room<T> f;
  const int t = f.lit_texel();
  REQUIRE(t >= 0);
  const gather_point<T>& gp = f.r.gps[0].gp;
  const T rel = std::is_same<T, float>::value ? T(1e-5) : T(1e-12);
  for (const T p : {T(1), T(0.25), T(1e-6)}) {
    const fixed_draw<T> one{std::size_t(t), p};
    const ris_pool_entry<T> e = f.entry(t, p, vpl_mode::point);
    REQUIRE(e.pmf == p);
    const vec3<T> term = vpl_visible_contribution(gp, f.r.view, t, f.r.vis, T(0)) / p;
    REQUIRE(luminance(term) > T(0));
    for (const auto& c : std::vector<std::tuple<int, int, int>>{{0, 3, 1}, {0, 3, 7}, {0, 2, 64}, {4, 3, 9}, {2, 5, 2}}) {
      const int nd = std::get<0>(c), nr = std::get<1>(c), m = std::get<2>(c);
      INFO("pmf " << p << " n_dirs " << nd << " n_ris " << nr << " M " << m);
      for (const auto& g : f.r.gps) {
        counter_rng a = make_counter_rng(2u, 0u), b = a;
        const vec3<T> pooled =
            estimate_ris_mis_pooled(g.gp, f.r.view, one, &e, 1u, a, nd, nr, m, f.r.tracer, f.r.vis, f.tol);
        const vec3<T> direct = estimate_ris_mis(g.gp, f.r.view, one, b, nd, nr, m, f.r.tracer, f.r.vis, f.tol);
        INFO(g.name);
        CHECK(same_bits(pooled, direct));
        CHECK(a.counter == b.counter);
        CHECK(a.counter == pooled_count(nd, nr, m));
      }
      if (nd == 0) {
        counter_rng a = make_counter_rng(2u, 1u);
        const vec3<T> v = estimate_ris_mis_pooled(gp, f.r.view, one, &e, 1u, a, 0, nr, m, f.r.tracer, f.r.vis, f.tol);
        for (int ch = 0; ch < 3; ++ch) CHECK(std::abs(v[ch] - term[ch]) <= T(4) * rel * term[ch]);
      }
    }
    // The reservoir: the entry, W = 1 / pmf.
    for (const int m : {1, 3, 64}) {
      counter_rng q = make_counter_rng(2u, 2u);
      ris_mis_kept<T> kept;
      const ris_reservoir<T> r = ris_mis_resample_pooled(gp, &e, 1u, q, m, T(4), T(3), kept);
      REQUIRE(ris_reservoir_has_sample(r));
      CHECK(r.kept.texel == t);
      CHECK(r.confidence == T(m));
      const T w = ris_contribution_weight(r);
      CHECK(std::abs(w * p - T(1)) <= T(4) * rel);
    }
  }
  // Patch VPLs: every candidate is the one jittered point, the estimate without directions its
  // contribution over the pmf (the at-centre part included: n1 = 0).
  for (const vec2<T> xi : {vec2<T>(T(0.1), T(0.9)), vec2<T>(T(0.5)), vec2<T>(T(0.99), T(0.02))}) {
    const T p = T(0.5);
    const ris_pool_entry<T> e = f.entry(t, p, vpl_mode::patch, xi);
    const vec3<T> term = vpl_patch_visible_contribution(gp, f.r.view, t, xi, f.r.vis, T(0), f.tol) / p;
    REQUIRE(luminance(term) > T(0));
    const fixed_draw<T> one{std::size_t(t), p};
    counter_rng a = make_counter_rng(2u, 3u);
    const vec3<T> v =
        estimate_ris_mis_pooled(gp, f.r.view, one, &e, 1u, a, 0, 3, 5, f.r.tracer, f.r.vis, f.tol, vpl_mode::patch);
    INFO("xi " << xi.x << " " << xi.y);
    for (int ch = 0; ch < 3; ++ch) CHECK(std::abs(v[ch] - term[ch]) <= T(16) * rel * term[ch]);
    CHECK(a.counter == pooled_count(0, 3, 5));
  }
}

TEMPLATE_TEST_CASE("ris pool hard case: a pool whose every entry is empty (pmf 0)", "[hardcases][ris-pool]", float,
                   double) {
  // pmf 0 marks an empty entry, whatever its other fields hold: weighed 0 at every gather point, so
  // every reservoir is empty (its numbers still drawn: the layout does not depend on the pool).
  // An implementation that tested the texel or the radiance instead of the pmf would keep the copy
  // of a lit entry with pmf 0 below, and divide by its pmf 0.
  using T = TestType;
  const room<T> f;
  const int t = f.lit_texel();
  REQUIRE(t >= 0);
  const int invalid = 0;  // the corner texel of face 0 lies outside the unit disk: no VPL
  REQUIRE_FALSE(f.r.view.texel_valid(invalid));
  const discrete_cdf<T> zero(std::vector<T>(std::size_t(f.r.view.texel_count()), T(0)));
  const fixed_draw<T> outside{std::size_t(f.r.view.texel_count()), T(1)};
  const fixed_draw<T> unlit{std::size_t(invalid), T(0.5)};
  for (const vpl_mode mode : {vpl_mode::point, vpl_mode::patch}) {
    INFO("mode " << int(mode));
    ris_pool_entry<T> lit_copy = f.entry(t, T(0.5), mode);
    REQUIRE(lit_copy.pmf > T(0));
    lit_copy.pmf = T(0);
    const std::vector<ris_pool_entry<T>> pool = {
        ris_pool_entry<T>{},  // default
        ris_pool_draw_entry(f.r.view, zero, 3u, 0u, mode, f.tol),
        ris_pool_draw_entry(f.r.view, outside, 3u, 1u, mode, f.tol),
        ris_pool_draw_entry(f.r.view, unlit, 3u, 2u, mode, f.tol),
        f.entry(t, T(0), mode),
        f.entry(t, -T(1), mode),
        lit_copy};
    for (const ris_pool_entry<T>& e : pool) CHECK_FALSE(e.pmf > T(0));
    CHECK(pool[2].texel == -1);  // a draw outside the view keeps no texel
    CHECK(pool[3].texel == invalid);
    CHECK(pool[3].pmf == T(0));  // ... one without flux keeps its texel, pmf 0
    const std::uint32_t n = std::uint32_t(pool.size());
    for (const auto& g : f.r.gps)
      for (const T n1 : {T(0), T(4)}) {
        INFO(g.name << " n1 " << n1);
        const mis_receiver<T> rx = make_mis_receiver(g.gp);
        for (const ris_pool_entry<T>& e : pool) CHECK(ris_pool_unshadowed(g.gp, rx, e, n1, T(4)) == vec3<T>(T(0)));
        counter_rng rng = make_counter_rng(3u, 0u);
        ris_mis_kept<T> kept;
        const ris_reservoir<T> r = ris_mis_resample_pooled(g.gp, pool.data(), n, rng, 32, n1, T(4), kept);
        CHECK_FALSE(ris_reservoir_has_sample(r));
        CHECK(r.weight_sum == T(0));
        CHECK(r.confidence == T(32));
        CHECK(rng.counter == 64u);
        counter_rng a = make_counter_rng(3u, 1u);
        CHECK(estimate_ris_mis_pooled(g.gp, f.r.view, f.flux, pool.data(), n, a, 0, 4, 8, f.r.tracer, f.r.vis, f.tol,
                                      mode) == vec3<T>(T(0)));
        CHECK(a.counter == pooled_count(0, 4, 8));
        // With directions: theirs alone, after each step's 2 M numbers.
        counter_rng b = make_counter_rng(3u, 2u);
        const vec3<T> e = estimate_ris_mis_pooled(g.gp, f.r.view, f.flux, pool.data(), n, b, 3, 4, 8, f.r.tracer,
                                                  f.r.vis, f.tol, mode);
        CHECK(finite_nonneg(e));
        CHECK(b.counter == pooled_count(3, 4, 8));
        CHECK(same_bits(e, directions_only(f, g.gp, f.flux, make_counter_rng(3u, 2u), 3, 4, 8, true, mode)));
      }
  }
}

TEMPLATE_TEST_CASE("ris pool hard case: entries with NaN, infinite, denormal or degenerate fields",
                   "[hardcases][ris-pool]", float, double) {
  // An entry read back from a buffer may hold anything. Whatever it holds: h, the reservoir's
  // weights and the estimate stay finite and not negative, and the numbers follow the layout.
  using T = TestType;
  using lim = std::numeric_limits<T>;
  const T nan = lim::quiet_NaN(), inf = lim::infinity();
  const room<T> f;
  const int t = f.lit_texel();
  REQUIRE(t >= 0);
  const gather_point<T>& gp = f.r.gps[0].gp;
  for (const vpl_mode mode : {vpl_mode::point, vpl_mode::patch}) {
    const ris_pool_entry<T> good = f.entry(t, T(0.01), mode);
    REQUIRE(luminance(ris_pool_unshadowed(gp, make_mis_receiver(gp), good, T(0), T(2))) > T(0));
    std::vector<std::pair<const char*, ris_pool_entry<T>>> bad;
    const auto add = [&](const char* what, auto&& change) {
      ris_pool_entry<T> e = good;
      change(e);
      bad.emplace_back(what, e);
    };
    add("radiance inf", [&](ris_pool_entry<T>& e) { e.radiance = vec3<T>(inf); });
    add("radiance inf in one channel", [&](ris_pool_entry<T>& e) { e.radiance.y = inf; });
    add("radiance NaN", [&](ris_pool_entry<T>& e) { e.radiance = vec3<T>(nan); });
    add("radiance NaN in one channel", [&](ris_pool_entry<T>& e) { e.radiance.z = nan; });
    add("radiance max", [&](ris_pool_entry<T>& e) { e.radiance = vec3<T>(lim::max()); });
    add("radiance negative", [&](ris_pool_entry<T>& e) { e.radiance = vec3<T>(-T(1)); });
    add("pmf denormal", [&](ris_pool_entry<T>& e) { e.pmf = lim::denorm_min(); });
    add("pmf below the smallest normal", [&](ris_pool_entry<T>& e) { e.pmf = lim::min() / T(4); });
    add("pmf denormal, radiance max", [&](ris_pool_entry<T>& e) {
      e.pmf = lim::denorm_min();
      e.radiance = vec3<T>(lim::max());
    });
    add("pmf smallest normal, radiance max", [&](ris_pool_entry<T>& e) {
      e.pmf = lim::min();
      e.radiance = vec3<T>(lim::max());
    });
    add("pmf inf", [&](ris_pool_entry<T>& e) { e.pmf = inf; });
    add("pmf NaN", [&](ris_pool_entry<T>& e) { e.pmf = nan; });
    add("pmf max", [&](ris_pool_entry<T>& e) { e.pmf = lim::max(); });
    add("area 0", [&](ris_pool_entry<T>& e) { e.area = T(0); });
    add("area denormal", [&](ris_pool_entry<T>& e) { e.area = lim::denorm_min(); });
    add("area inf", [&](ris_pool_entry<T>& e) { e.area = inf; });
    add("area NaN", [&](ris_pool_entry<T>& e) { e.area = nan; });
    add("area max", [&](ris_pool_entry<T>& e) { e.area = lim::max(); });
    add("position NaN", [&](ris_pool_entry<T>& e) { e.position = vec3<T>(nan); });
    add("position inf", [&](ris_pool_entry<T>& e) { e.position.x = inf; });
    add("position at the gather point", [&](ris_pool_entry<T>& e) { e.position = gp.position; });
    add("normal NaN", [&](ris_pool_entry<T>& e) { e.normal = vec3<T>(nan); });
    add("normal 0", [&](ris_pool_entry<T>& e) { e.normal = vec3<T>(T(0)); });
    add("normal not unit (huge)", [&](ris_pool_entry<T>& e) { e.normal *= lim::max() / T(4); });
    add("normal inf", [&](ris_pool_entry<T>& e) { e.normal = vec3<T>(T(0), inf, T(0)); });
    add("texel and xi NaN", [&](ris_pool_entry<T>& e) {
      e.texel = -7;
      e.xi = vec2<T>(nan);
    });
    for (const auto& [what, e] : bad) {
      INFO("mode " << int(mode) << ": " << what);
      for (const T n1 : {T(0), T(4)}) {
        // h is finite (negative only where the entry's radiance is: no draw makes one, and a
        // negative target is never kept).
        const vec3<T> h = ris_pool_unshadowed(gp, make_mis_receiver(gp), e, n1, T(2));
        CHECK(finite3(h));
        if (!(e.radiance.x < T(0))) CHECK(finite_nonneg(h));
        // The bad entry alone, and among good ones.
        const std::vector<ris_pool_entry<T>> pools[2] = {{e}, {good, e, good, e}};
        for (const std::vector<ris_pool_entry<T>>& pool : pools) {
          const std::uint32_t n = std::uint32_t(pool.size());
          counter_rng rng = make_counter_rng(4u, 0u);
          ris_mis_kept<T> kept;
          const ris_reservoir<T> r = ris_mis_resample_pooled(gp, pool.data(), n, rng, 16, n1, T(2), kept);
          CHECK(std::isfinite(r.weight_sum));
          CHECK(std::isfinite(r.target));
          CHECK(r.weight_sum >= T(0));
          CHECK(std::isfinite(ris_contribution_weight(r)));
          CHECK(finite_nonneg(kept.h));
          CHECK(finite_nonneg(ris_mis_shade_kept(gp, r, kept, f.r.vis)));
          CHECK(rng.counter == 32u);
          for (const auto& g : f.r.gps) {
            counter_rng a = make_counter_rng(4u, 1u);
            CHECK(finite_nonneg(estimate_ris_mis_pooled(g.gp, f.r.view, f.flux, pool.data(), n, a, int(n1), 2, 16,
                                                        f.r.tracer, f.r.vis, f.tol, mode)));
            CHECK(a.counter == pooled_count(int(n1), 2, 16));
          }
        }
      }
    }
  }
}

namespace {

// Whether an entry of texel t (the room's radiance times `bright`) with a pmf below the smallest
// normal T is kept by a reservoir at any of the room's points, n1 = 0 or 4, point or patch VPLs.
template <class T>
void check_tiny_pmf_not_kept(const room<T>& f, T bright) {
  using lim = std::numeric_limits<T>;
  const int t = f.lit_texel();
  REQUIRE(t >= 0);
  for (const vpl_mode mode : {vpl_mode::point, vpl_mode::patch}) {
    ris_pool_entry<T> e = f.entry(t, T(0.01), mode);
    e.radiance *= bright;
    for (const T tiny : {lim::denorm_min(), lim::min() / T(4), lim::min() / T(2), lim::min() * T(0.999)}) {
      e.pmf = tiny;
      for (const auto& g : f.r.gps)
        for (const T n1 : {T(0), T(4)}) {
          INFO("mode " << int(mode) << " pmf " << tiny << " radiance x " << bright << " " << g.name << " n1 " << n1);
          counter_rng rng = make_counter_rng(5u, 0u);
          ris_mis_kept<T> kept;
          const ris_reservoir<T> r = ris_mis_resample_pooled(g.gp, &e, 1u, rng, 4, n1, T(2), kept);
          CHECK_FALSE(ris_reservoir_has_sample(r));
          CHECK(rng.counter == 8u);
        }
    }
  }
}

}  // namespace

TEMPLATE_TEST_CASE("ris pool hard case: a pmf outside the normal range counts as 0, as estimator_pmf's",
                   "[hardcases][ris-pool]", float, double) {
  // docs/math.md's normal-range contract: a denormal pmf is 0 on a GPU that flushes, so it counts as
  // 0 everywhere (estimator_pmf, which the non-pooled draw applies). An entry that holds one (a
  // buffer written elsewhere, or a pool filled by code that skipped estimator_pmf) must not be kept:
  // with it a flushing GPU and the C++ path would keep different samples. With the room's radiance
  // h = ... n2 pmf is itself below the smallest normal, so its target is not usable; the brighter
  // case is the next test.
  using T = TestType;
  const room<T> f;
  check_tiny_pmf_not_kept(f, T(1));
}

// With a light 100 to 1000 times the room's (800 to 8000 W/sr: ordinary HDR units), h = w2 f /
// (p2 / pmf) of an entry whose pmf is below the smallest normal would be a normal number, its target
// usable and its weight target / pmf finite, W ~ 1 / pmf (about 1e38 in float), while a GPU that
// flushes reads that pmf as 0 and keeps nothing. ris_pool_unshadowed weighs with estimator_pmf(e.pmf)
// so that both keep nothing. (This failed while the header tested the pmf with `> 0` only.)
TEMPLATE_TEST_CASE("ris pool hard case: a pmf below the normal range is not kept under a bright light",
                   "[hardcases][ris-pool]", float, double) {
  using T = TestType;
  const room<T> f;
  check_tiny_pmf_not_kept(f, T(1000));
}

TEMPLATE_TEST_CASE("ris pool hard case: entries moved to their texel's centre are gathering's when n1 > 0",
                   "[hardcases][ris-pool]", float, double) {
  // A patch point hidden by a neighbour's plane moves to its texel's centre (at_centre): with
  // gathering (n1 > 0) that part belongs to gathering alone and the entry weighs 0; without it the
  // VPL strategy takes it. Ignoring the flag would count those parts twice (MIS's bias at creases);
  // dropping them always would lose them when n1 = 0.
  using T = TestType;
  const room<T> f;
  // Moved entries that light one of the room's points when n1 = 0.
  std::vector<std::pair<ris_pool_entry<T>, std::size_t>> moved;
  for (std::uint32_t i = 0; i < 4096 && moved.size() < 8; ++i) {
    const ris_pool_entry<T> e = ris_pool_draw_entry(f.r.view, f.flux, 6u, i, vpl_mode::patch, f.tol);
    if (e.at_centre == 0) continue;
    for (std::size_t g = 0; g < f.r.gps.size(); ++g)
      if (luminance(ris_pool_unshadowed(f.r.gps[g].gp, make_mis_receiver(f.r.gps[g].gp), e, T(0), T(2))) > T(0)) {
        moved.emplace_back(e, g);
        break;
      }
  }
  REQUIRE(moved.size() >= 2);
  const ris_pool_entry<T> empty{};
  for (const auto& [e, g] : moved) {
    const gather_point<T>& gp = f.r.gps[g].gp;
    INFO("texel " << e.texel << " at " << f.r.gps[g].name);
    const mis_receiver<T> rx = make_mis_receiver(gp);
    CHECK(ris_pool_unshadowed(gp, rx, e, T(4), T(2)) == vec3<T>(T(0)));
    CHECK(ris_pool_unshadowed(gp, rx, e, T(1), T(2)) == vec3<T>(T(0)));
    CHECK(luminance(ris_pool_unshadowed(gp, rx, e, T(0), T(2))) > T(0));
    // The reservoir of a pool of that entry: empty with n1 > 0, the entry with n1 = 0.
    counter_rng a = make_counter_rng(6u, 0u), b = a;
    ris_mis_kept<T> kept;
    CHECK_FALSE(ris_reservoir_has_sample(ris_mis_resample_pooled(gp, &e, 1u, a, 8, T(4), T(2), kept)));
    const ris_reservoir<T> r = ris_mis_resample_pooled(gp, &e, 1u, b, 8, T(0), T(2), kept);
    REQUIRE(ris_reservoir_has_sample(r));
    CHECK(r.kept.texel == e.texel);
    CHECK(same_bits(r.kept.xi, e.xi));
    // With directions the estimate is theirs alone, as with an empty entry (same numbers).
    counter_rng c = make_counter_rng(6u, 1u), d = c;
    const fixed_draw<T> one{std::size_t(e.texel), e.pmf};
    const vec3<T> with_moved =
        estimate_ris_mis_pooled(gp, f.r.view, one, &e, 1u, c, 4, 2, 8, f.r.tracer, f.r.vis, f.tol, vpl_mode::patch);
    const vec3<T> with_empty =
        estimate_ris_mis_pooled(gp, f.r.view, one, &empty, 1u, d, 4, 2, 8, f.r.tracer, f.r.vis, f.tol, vpl_mode::patch);
    CHECK(same_bits(with_moved, with_empty));
    CHECK(c.counter == d.counter);
  }
  // The flag is honoured whatever the mode: a point entry marked moved weighs 0 with n1 > 0.
  const int t = f.lit_texel();
  REQUIRE(t >= 0);
  ris_pool_entry<T> p = f.entry(t, T(0.5), vpl_mode::point);
  const gather_point<T>& gp0 = f.r.gps[0].gp;
  const vec3<T> before = ris_pool_unshadowed(gp0, make_mis_receiver(gp0), p, T(0), T(2));
  p.at_centre = 1;
  CHECK(ris_pool_unshadowed(gp0, make_mis_receiver(gp0), p, T(4), T(2)) == vec3<T>(T(0)));
  CHECK(same_bits(ris_pool_unshadowed(gp0, make_mis_receiver(gp0), p, T(0), T(2)), before));
}

TEMPLATE_TEST_CASE("ris pool hard case: an invalid gather point draws nothing", "[hardcases][ris-pool]", float,
                   double) {
  using T = TestType;
  const T nan = std::numeric_limits<T>::quiet_NaN(), inf = std::numeric_limits<T>::infinity();
  const room<T> f;
  const gather_point<T>& gp = f.r.gps[0].gp;
  const std::vector<ris_pool_entry<T>> pool = f.pool(64, 7u, vpl_mode::patch);
  const std::vector<gather_point<T>> bad = {
      {gp.position, vec3<T>(T(0)), gp.albedo},                  // background: no surface
      {vec3<T>(nan, T(0), T(0)), gp.normal, gp.albedo},         // NaN position
      {vec3<T>(T(0), inf, T(0)), gp.normal, gp.albedo},         // infinite position
      {gp.position, vec3<T>(nan, T(1), T(0)), gp.albedo},       // NaN normal
      {gp.position, vec3<T>(inf, T(1), T(0)), gp.albedo}};      // infinite normal
  for (std::size_t k = 0; k < bad.size(); ++k) {
    INFO("gather point " << k);
    REQUIRE_FALSE(gather_point_valid(bad[k]));
    counter_rng rng = make_counter_rng(7u, 0u);
    ris_mis_kept<T> kept;
    const ris_reservoir<T> r = ris_mis_resample_pooled(bad[k], pool.data(), 64u, rng, 16, T(4), T(4), kept);
    CHECK_FALSE(ris_reservoir_has_sample(r));
    CHECK(r.confidence == T(0));
    CHECK(rng.counter == 0u);
    CHECK(ris_mis_shade_kept(bad[k], r, kept, f.r.vis) == vec3<T>(T(0)));
    for (const vpl_mode mode : {vpl_mode::point, vpl_mode::patch}) {
      CHECK(estimate_ris_mis_pooled(bad[k], f.r.view, f.flux, pool.data(), 64u, rng, 4, 4, 16, f.r.tracer, f.r.vis,
                                    f.tol, mode) == vec3<T>(T(0)));
      estimator_state<T> st = make_estimator_state<T>(rng);
      estimate_ris_mis_pooled_range(bad[k], f.r.view, f.flux, pool.data(), 64u, st, 0, 4, 4, 4, 16, f.r.tracer,
                                    f.r.vis, f.tol, mode);
      CHECK(st.sum == vec3<T>(T(0)));
      CHECK(st.rng.counter == 0u);
    }
    CHECK(rng.counter == 0u);
    // An entry weighed at such a point: 0 or finite, never NaN.
    for (const ris_pool_entry<T>& e : pool)
      CHECK(finite_nonneg(ris_pool_unshadowed(bad[k], make_mis_receiver(bad[k]), e, T(4), T(4))));
  }
}

TEMPLATE_TEST_CASE("ris pool hard case: candidate and sample counts of zero or below", "[hardcases][ris-pool]", float,
                   double) {
  // n_candidates <= 0 makes n_ris 0 (as estimate_ris_mis): the directions then weigh as gathering
  // alone. n_ris <= 0: no reservoir. n2 <= 0 or NaN in the resample: empty, no numbers.
  using T = TestType;
  const room<T> f;
  const gather_point<T>& gp = f.r.gps[0].gp;
  const std::vector<ris_pool_entry<T>> pool = f.pool(64, 8u, vpl_mode::point);
  for (const int m : {0, -1, INT_MIN}) {
    counter_rng rng = make_counter_rng(8u, 0u);
    ris_mis_kept<T> kept;
    const ris_reservoir<T> r = ris_mis_resample_pooled(gp, pool.data(), 64u, rng, m, T(4), T(4), kept);
    CHECK_FALSE(ris_reservoir_has_sample(r));
    CHECK(r.confidence == T(0));
    CHECK(rng.counter == 0u);
  }
  for (const T n2 : {T(0), -T(1), std::numeric_limits<T>::quiet_NaN()}) {
    counter_rng rng = make_counter_rng(8u, 1u);
    ris_mis_kept<T> kept;
    const ris_reservoir<T> r = ris_mis_resample_pooled(gp, pool.data(), 64u, rng, 16, T(4), n2, kept);
    CHECK_FALSE(ris_reservoir_has_sample(r));
    CHECK(rng.counter == 0u);
    for (const ris_pool_entry<T>& e : pool) CHECK(ris_pool_unshadowed(gp, make_mis_receiver(gp), e, T(4), n2) == vec3<T>(T(0)));
  }
  for (const vpl_mode mode : {vpl_mode::point, vpl_mode::patch}) {
    INFO("mode " << int(mode));
    counter_rng rng = make_counter_rng(8u, 2u);
    // Nothing to do: 0, no numbers.
    for (const auto& c : std::vector<std::tuple<int, int, int>>{{0, 0, 16}, {-3, -2, 16}, {0, 4, 0}, {0, 4, -5},
                                                                 {-1, 4, INT_MIN}, {0, -4, 8}}) {
      INFO("n_dirs " << std::get<0>(c) << " n_ris " << std::get<1>(c) << " M " << std::get<2>(c));
      CHECK(estimate_ris_mis_pooled(gp, f.r.view, f.flux, pool.data(), 64u, rng, std::get<0>(c), std::get<1>(c),
                                    std::get<2>(c), f.r.tracer, f.r.vis, f.tol, mode) == vec3<T>(T(0)));
      CHECK(rng.counter == 0u);
    }
    // Directions with no reservoirs: the non-pooled estimate's value and numbers (gathering alone,
    // n2 = 0), whatever the pool holds.
    for (const auto& c : std::vector<std::pair<int, int>>{{0, 16}, {-2, 16}, {6, 0}, {6, -3}}) {
      const int nr = c.first, m = c.second;
      INFO("n_ris " << nr << " M " << m);
      counter_rng a = make_counter_rng(8u, 3u), b = a, g = a;
      const vec3<T> pooled =
          estimate_ris_mis_pooled(gp, f.r.view, f.flux, pool.data(), 64u, a, 3, nr, m, f.r.tracer, f.r.vis, f.tol, mode);
      const vec3<T> direct = estimate_ris_mis(gp, f.r.view, f.flux, b, 3, nr, m, f.r.tracer, f.r.vis, f.tol, mode);
      CHECK(same_bits(pooled, direct));
      CHECK(a.counter == pooled_count(3, 0, 0));
      CHECK(b.counter == a.counter);
      const vec3<T> gathering = estimate_gathering(gp, f.r.view, g, 3, f.r.tracer, f.tol);
      const T rel = std::is_same<T, float>::value ? T(1e-5) : T(1e-12);
      for (int ch = 0; ch < 3; ++ch) CHECK(std::abs(pooled[ch] - gathering[ch]) <= rel * gathering[ch]);
      CHECK(luminance(pooled) > T(0));
    }
  }
}
