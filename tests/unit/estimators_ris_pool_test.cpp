// SPDX-License-Identifier: MIT
// estimators/ris_candidate_pool.hpp, exactly (no statistics):
// - an entry (ris_pool_draw_entry / ris_pool_make_entry) is the draw of the non-pooled path: the
//   same texel, jitter, pmf, point, unit normal, area of p2 and radiance, and its h
//   (ris_pool_unshadowed) is ris_mis_unshadowed's for that draw bit for bit, at many gather points
//   (shading normals too), point and patch VPLs, n1 = 0 and n1 > 0, with and without plane records;
// - ris_pool_index: floor(u P) clamped into the pool, its ends, NaN and negative u, the u at which
//   it steps;
// - ris_mis_resample_pooled: 2 M numbers whatever the vpl_mode, and the reservoir that a weighted
//   reservoir written out here keeps over the same numbers (weights target / pmf, W's 1/M);
// - estimate_ris_mis_pooled: the layout (per step the M candidates then the direction) and the range
//   form split anywhere, bit for bit.
// The hard cases are in tests/hardcases/estimators_ris_pool_hardcases_test.cpp, the statistics in
// tests/statistical/estimators_ris_pool_unbiased_test.cpp.
#include <estimator_splits.hpp>
#include <estimators_reference.hpp>
#include <float_bits.hpp>
#include <synthetic_scene.hpp>

#include <vplkit/builders/flux_weights.hpp>
#include <vplkit/builders/vpl_distribution.hpp>
#include <vplkit/distribution/discrete_cdf.hpp>
#include <vplkit/distribution/weighted_reservoir.hpp>
#include <vplkit/estimators/mis_estimator.hpp>
#include <vplkit/estimators/ris_candidate_pool.hpp>
#include <vplkit/estimators/ris_mis_estimator.hpp>
#include <vplkit/vpl/dprsm_planes.hpp>
#include <vplkit/vpl/luminance.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <tuple>
#include <type_traits>
#include <vector>

using namespace vplkit;
using namespace vplkit_test;

namespace {

template <class T>
struct pool_room {
  lit_room<T> r{16};
  defensive_mixture<T> flux = make_vpl_distribution(build_flux_weights(r.view), r.view, T(0));
  discrete_cdf<T> uniform{uniform_valid_weights(r.view)};
  std::vector<dprsm_plane<T>> planes = build_dprsm_planes(r.view);
  dprsm_view<T> with_planes() const {
    dprsm_view<T> v = r.view;
    v.planes = planes.data();
    return v;
  }
  T tol = T(0.2);
};

// Many receivers: the room's named points, the valid pixels of a 12 x 12 G-buffer, and the named
// points again with a shading normal tilted off the geometric one.
template <class T>
std::vector<gather_point<T>> many_points(const lit_room<T>& r) {
  std::vector<gather_point<T>> out;
  for (const auto& g : r.gps) out.push_back(g.gp);
  const gbuffer_data<T> gb = r.scene.make_gbuffer(12, 12);
  const gbuffer_view<T> g = gb.view();
  for (int p = 0; p < g.pixel_count(); ++p)
    if (gather_point_valid(g.at(p))) out.push_back(g.at(p));
  for (const auto& n : r.gps) {
    gather_point<T> s = n.gp;
    s.shading_normal = s.normal + vec3<T>(T(0.2), T(0.1), T(-0.15));
    out.push_back(s);
  }
  return out;
}

// The draw of entry i of a pool filled with seed: the numbers counter_rng(seed, i) gives, u then
// (patch) xi0 and xi1, through the non-pooled path's ris_mis_draw_candidate.
template <class T, class D>
ris_mis_draw<T> draw_of(const dprsm_view<T>& view, const D& dist, std::uint32_t seed, std::uint32_t i, vpl_mode mode) {
  counter_rng rng = make_counter_rng(seed, i);
  const T u = rng_next_unit<T>(rng);
  vec2<T> xi(T(0));
  if (mode == vpl_mode::patch) {
    xi.x = rng_next_unit<T>(rng);
    xi.y = rng_next_unit<T>(rng);
  }
  return ris_mis_draw_candidate(view, dist, u, xi);
}

// Field by field (an entry of doubles has padding, which same_bits would compare).
template <class T>
bool same_entry(const ris_pool_entry<T>& a, const ris_pool_entry<T>& b) {
  return same_bits(a.position, b.position) && same_bits(a.pmf, b.pmf) && same_bits(a.normal, b.normal) &&
         same_bits(a.area, b.area) && same_bits(a.radiance, b.radiance) && a.texel == b.texel &&
         same_bits(a.xi, b.xi) && a.at_centre == b.at_centre;
}

// The entry index of a 24-bit number u = k 2^-24 in exact integer arithmetic: floor(k P / 2^24).
template <class T>
std::uint32_t exact_index(T u, std::uint32_t pool_size) {
  const std::uint64_t k = std::uint64_t(double(u) * 16777216.0);
  return std::uint32_t((k * pool_size) >> 24);
}

}  // namespace

TEMPLATE_TEST_CASE("ris pool: an entry holds its draw's texel, pmf, point, normal, area and radiance",
                   "[ris-pool]", float, double) {
  // A pool whose entries took other numbers (a different order, xi before u), the texel centre's
  // area for a patch point, the raw texel normal or a radiance of another normal would differ here.
  using T = TestType;
  const pool_room<T> f;
  const dprsm_view<T> planes = f.with_planes();
  int lit = 0, moved = 0;
  const auto check_dist = [&](const dprsm_view<T>& view, const auto& dist, const char* name) {
    for (const vpl_mode mode : {vpl_mode::point, vpl_mode::patch})
      for (std::uint32_t i = 0; i < 256; ++i) {
        INFO(name << " planes " << (view.planes != nullptr) << " mode " << int(mode) << " entry " << i);
        const ris_pool_entry<T> e = ris_pool_draw_entry(view, dist, 31u, i, mode, f.tol);
        const ris_mis_draw<T> c = draw_of(view, dist, 31u, i, mode);
        REQUIRE(same_entry(ris_pool_make_entry(view, c, mode, f.tol), e));  // the two constructors agree
        CHECK(e.texel == c.s.texel);
        CHECK(same_bits(e.xi, c.s.xi));
        if (mode == vpl_mode::point) CHECK(e.xi == vec2<T>(T(0)));
        REQUIRE(c.s.texel >= 0);
        const int t = c.s.texel;
        // The pmf is the one the gathering directions and ris_mis_shade read: distribution.pmf(t).
        CHECK(same_bits(c.pmf, estimator_pmf(T(dist.pmf(std::size_t(t))))));
        if (mode == vpl_mode::point) {
          const vpl<T> v = view.vpl_at(t);
          if (!vpl_has_flux(v)) {
            CHECK(e.pmf == T(0));
            continue;
          }
          CHECK(same_bits(e.pmf, c.pmf));
          CHECK(same_bits(e.position, view.position[t]));
          CHECK(same_bits(e.normal, unit_or_zero(view.normal[t])));
          CHECK(same_bits(e.area, mis_texel_patch_area(view, t)));
          CHECK(same_bits(e.radiance, reflected_radiance(view.light.position, view.light.intensity,
                                                         view.position[t], view.normal[t], view.albedo[t])));
          CHECK(e.at_centre == 0);
        } else {
          const dprsm_patch_sample<T> p = dprsm_patch_vpl(view, t, c.s.xi, f.tol);
          if (!vpl_has_flux(p.point)) {
            CHECK(e.pmf == T(0));
            continue;
          }
          CHECK(same_bits(e.pmf, c.pmf));
          CHECK(same_bits(e.position, p.point.position));
          CHECK(same_bits(e.normal, unit_or_zero(view.normal[t])));
          CHECK(same_bits(e.area, vpl_patch_area(p.solid_angle, p.distance, p.cos_alpha)));
          CHECK(same_bits(e.radiance, reflected_radiance(view.light.position, view.light.intensity,
                                                         p.point.position, p.point.normal, view.albedo[t])));
          CHECK(e.at_centre == (p.at_centre ? 1 : 0));
          if (p.at_centre) ++moved;
        }
        CHECK(e.pmf > T(0));
        CHECK(e.area > T(0));
        CHECK(luminance(e.radiance) > T(0));
        ++lit;
      }
  };
  for (const dprsm_view<T>* view : {&f.r.view, &planes}) {
    check_dist(*view, f.flux, "flux");
    check_dist(*view, f.uniform, "uniform");
  }
  CHECK(lit > 1500);  // of 2 views x 2 distributions x 2 modes x 256 entries
  CHECK(moved > 0);   // some patch points moved to their texel's centre
  // Entries are independent: entry i is the same whatever else is drawn, in any order.
  for (std::uint32_t i : {0u, 7u, 255u, 100000u})
    CHECK(same_entry(ris_pool_draw_entry(f.r.view, f.flux, 5u, i, vpl_mode::patch, f.tol),
                    ris_pool_make_entry(f.r.view, draw_of(f.r.view, f.flux, 5u, i, vpl_mode::patch),
                                        vpl_mode::patch, f.tol)));
}

TEMPLATE_TEST_CASE("ris pool: h of an entry is ris_mis_unshadowed's of its draw, bit for bit", "[ris-pool]", float,
                   double) {
  // The pooled candidate must weigh exactly as the non-pooled one (ris-mis's estimate and MIS weights
  // are kept, only the candidates' origin changes). A pool that dropped n2 pmf from h, took the
  // texel's area for a patch point, or counted the moved (at_centre) points with n1 > 0 would differ.
  using T = TestType;
  const pool_room<T> f;
  const dprsm_view<T> planes = f.with_planes();
  const std::vector<gather_point<T>> points = many_points(f.r);
  REQUIRE(points.size() > 100);
  long compared = 0, nonzero = 0, mismatches = 0, at_centre_counted = 0, at_centre_dropped = 0;
  for (const dprsm_view<T>* view : {&f.r.view, &planes})
    for (const vpl_mode mode : {vpl_mode::point, vpl_mode::patch}) {
      std::vector<ris_pool_entry<T>> pool;
      std::vector<ris_mis_draw<T>> draws;
      for (std::uint32_t i = 0; i < 96; ++i) {
        pool.push_back(ris_pool_draw_entry(*view, f.flux, 77u, i, mode, f.tol));
        draws.push_back(draw_of(*view, f.flux, 77u, i, mode));
      }
      for (const gather_point<T>& gp : points) {
        const mis_receiver<T> rx = make_mis_receiver(gp);
        for (const T n1 : {T(0), T(4)})
          for (const T n2 : {T(1), T(3)})
            for (std::size_t i = 0; i < pool.size(); ++i) {
              vpl<T> v;
              const vec3<T> a = ris_pool_unshadowed(gp, rx, pool[i], n1, n2);
              const vec3<T> b =
                  ris_mis_unshadowed(gp, rx, *view, draws[i].s, draws[i].pmf, n1, n2, mode, f.tol, v);
              ++compared;
              if (!same_bits(a, b)) {
                if (mismatches < 5) {
                  INFO("planes " << (view->planes != nullptr) << " mode " << int(mode) << " n1 " << n1 << " n2 "
                                 << n2 << " entry " << i << " gp " << gp.position.x << " " << gp.position.y << " "
                                 << gp.position.z);
                  CHECK(same_bits(a, b));
                }
                ++mismatches;
              }
              if (luminance(a) > T(0)) ++nonzero;
              if (pool[i].at_centre != 0) {
                // A moved point belongs to gathering alone when there is gathering, to the VPL
                // strategy when there is none.
                if (n1 > T(0)) {
                  CHECK(a == vec3<T>(T(0)));
                  ++at_centre_dropped;
                } else if (luminance(a) > T(0)) {
                  ++at_centre_counted;
                }
              }
            }
      }
    }
  CHECK(mismatches == 0);
  CHECK(nonzero > compared / 5);  // the comparison sees real values, not only zeros
  CHECK(at_centre_dropped > 0);
  CHECK(at_centre_counted > 0);
}

TEMPLATE_TEST_CASE("ris pool: ris_pool_index is floor(u P) clamped into the pool", "[ris-pool]", float, double) {
  // An index from u (P - 1) or round(u P) would miss the ends or step in the wrong places; one
  // without the clamp would read entry P for u = 1; NaN must not become an index at all.
  using T = TestType;
  using lim = std::numeric_limits<T>;
  const T below_one = std::nextafter(T(1), T(0));
  const std::uint32_t big = 1u << 20;
  const T last_number = T(1) - T(1.0 / 16777216.0);  // the largest number the stream gives
  const std::vector<std::uint32_t> sizes = {1u, 2u, 3u, 31u, 1000u, big, 1u << 24, (1u << 24) + 1u, 0xffffffffu};
  for (const std::uint32_t p : sizes) {
    INFO("P " << p);
    CHECK(ris_pool_index(T(0), p) == 0u);
    CHECK(ris_pool_index(-T(0), p) == 0u);
    CHECK(ris_pool_index(lim::denorm_min(), p) == 0u);
    if (p <= (1u << 24)) {
      // The last entry from the stream's largest number on.
      CHECK(ris_pool_index(below_one, p) == p - 1u);
      CHECK(ris_pool_index(last_number, p) == p - 1u);
    } else {
      // Beyond 2^24 entries the stream's 2^24 numbers cannot reach every entry: the largest one reads
      // floor((1 - 2^-24) P) (in float of P rounded to 2^24, 2^32), and the entries above it are never
      // read (harmless for the estimate: which entries are read does not depend on what they hold).
      const std::uint32_t top = ris_pool_index(last_number, p);
      CHECK(top < p - 1u);
      if (std::is_same<T, double>::value)
        CHECK(top == exact_index(last_number, p));
      else
        CHECK(top == (p == (1u << 24) + 1u ? (1u << 24) - 1u : 0xffffff00u));
    }
    // Outside [0, 1): clamped. 1 and above read the last entry, NaN and negative numbers the first.
    CHECK(ris_pool_index(T(1), p) == p - 1u);
    CHECK(ris_pool_index(T(2), p) == p - 1u);
    CHECK(ris_pool_index(lim::infinity(), p) == p - 1u);
    CHECK(ris_pool_index(lim::max(), p) == p - 1u);
    CHECK(ris_pool_index(lim::quiet_NaN(), p) == 0u);
    CHECK(ris_pool_index(-lim::quiet_NaN(), p) == 0u);
    CHECK(ris_pool_index(T(-0.5), p) == 0u);
    CHECK(ris_pool_index(-lim::infinity(), p) == 0u);
  }
  // One entry: every u reads it.
  for (const T u : {T(0), T(0.25), T(0.5), below_one, T(1), lim::quiet_NaN(), T(-3)}) CHECK(ris_pool_index(u, 1u) == 0u);
  // Two entries: the step at 1/2.
  CHECK(ris_pool_index(std::nextafter(T(0.5), T(0)), 2u) == 0u);
  CHECK(ris_pool_index(T(0.5), 2u) == 1u);
  // P = 2^20 (u P exact): entry i from u = i 2^-20 on, entry i - 1 just below it.
  for (const std::uint32_t i : {1u, 2u, 3u, 1000u, big / 2u, big / 2u + 1u, big - 1u}) {
    const T u = T(double(i) / double(big));
    INFO("i " << i);
    CHECK(ris_pool_index(u, big) == i);
    CHECK(ris_pool_index(std::nextafter(u, T(0)), big) == i - 1u);
    CHECK(ris_pool_index(std::nextafter(u, T(1)), big) == i);
  }
  // Every number the stream can give (k 2^-24): the index never decreases with u, never leaves the
  // pool and reads every entry; in double u P is exact (24 + 32 bits < 64, and P < 2^29 fits 53),
  // so the index is floor(k P / 2^24) exactly, every entry read by floor or ceil of 2^24 / P numbers.
  for (const std::uint32_t p : {3u, 31u, 1000u, big}) {
    INFO("P " << p);
    std::vector<std::uint32_t> count(p, 0u);
    std::uint32_t prev = 0, wrong_exact = 0, decreasing = 0, off_by_more = 0;
    for (std::uint32_t k = 0; k < (1u << 24); ++k) {
      const T u = T(float(k) * (1.0f / 16777216.0f));
      const std::uint32_t i = ris_pool_index(u, p);
      const std::uint32_t exact = std::uint32_t((std::uint64_t(k) * p) >> 24);
      if (i >= p) {
        FAIL("index " << i << " outside the pool at k " << k);
      }
      ++count[i];
      if (i < prev) ++decreasing;
      prev = i;
      if (i != exact) ++wrong_exact;
      if (i > exact + 1u || i < exact) ++off_by_more;
    }
    CHECK(decreasing == 0u);
    CHECK(off_by_more == 0u);  // float rounds the product up by at most one entry, never down
    if (std::is_same<T, double>::value) CHECK(wrong_exact == 0u);
    const std::uint32_t lo = (1u << 24) / p;
    std::uint32_t fewest = 0xffffffffu, most = 0;
    for (const std::uint32_t c : count) {
      fewest = std::min(fewest, c);
      most = std::max(most, c);
    }
    // Exactly uniform where P divides 2^24; within one number otherwise (double), a few (float).
    if (std::is_same<T, double>::value || p == big) {
      CHECK(fewest >= lo);
      CHECK(most <= lo + 1u);
    } else {
      CHECK(fewest + 2u >= lo);
      CHECK(most <= lo + 3u);
    }
  }
  // Float rounds u P: with P = 31 and u = 1082401 2^-24 the product 2 - 2^-24 is a tie that rounds
  // to 2, so the entry is 2 where the exact floor is 1 (the GLSL mirror's float product alike); in
  // double the product is exact.
  const T u31 = T(1082401.0 / 16777216.0);
  CHECK(exact_index(u31, 31u) == 1u);
  CHECK(ris_pool_index(u31, 31u) == (std::is_same<T, float>::value ? 2u : 1u));
}

TEMPLATE_TEST_CASE("ris pool: ris_mis_resample_pooled keeps what a weighted reservoir over its numbers keeps",
                   "[ris-pool]", float, double) {
  // Written out: candidate k takes u (the entry floor(u P)) and u_keep, in that order; its weight is
  // lum(h) / pmf with h the non-pooled path's ris_mis_unshadowed of the entry's draw; the reservoir
  // keeps it when u_keep S_k < w_k; weight_sum = S / M. Drawing 3 or 4 numbers per candidate in patch
  // mode, swapping u and u_keep, weighing by lum(h) alone or dividing by the kept count instead of M
  // would change the kept entry or the weights.
  using T = TestType;
  const pool_room<T> f;
  const std::vector<gather_point<T>> points = many_points(f.r);
  const std::vector<std::uint32_t> sizes =
      std::is_same<T, double>::value ? std::vector<std::uint32_t>{1u, 37u, 64u, 1000u}
                                     : std::vector<std::uint32_t>{1u, 64u, 256u};  // float: P a power of 2 (u P exact)
  long compared = 0, kept_any = 0, replaced = 0;
  for (const vpl_mode mode : {vpl_mode::point, vpl_mode::patch})
    for (const std::uint32_t p : sizes) {
      std::vector<ris_pool_entry<T>> pool;
      std::vector<ris_mis_draw<T>> draws;
      for (std::uint32_t i = 0; i < p; ++i) {
        pool.push_back(ris_pool_draw_entry(f.r.view, f.flux, 90u + p, i, mode, f.tol));
        draws.push_back(draw_of(f.r.view, f.flux, 90u + p, i, mode));
      }
      for (std::size_t g = 0; g < points.size(); g += 5)
        for (const int m : {1, 2, 7, 8, 9, 33})
          for (const T n1 : {T(0), T(4)})
            for (std::uint32_t s = 0; s < 3; ++s) {
              const gather_point<T>& gp = points[g];
              const T n2 = T(3);
              INFO("mode " << int(mode) << " P " << p << " point " << g << " M " << m << " n1 " << n1 << " stream "
                           << s);
              const counter_rng start = make_counter_rng(41u, std::uint32_t(g * 16u + s));
              counter_rng rng = start;
              ris_mis_kept<T> kept;
              const ris_reservoir<T> r = ris_mis_resample_pooled(gp, pool.data(), p, rng, m, n1, n2, kept);
              CHECK(rng.counter == 2u * std::uint32_t(m));  // whatever the vpl_mode
              // The reservoir written out.
              counter_rng numbers = start;
              T sum = T(0);
              int keep = -1, first = -1;
              std::uint32_t keep_entry = 0;
              T keep_target = T(0);
              vec3<T> keep_h(T(0));
              for (int k = 0; k < m; ++k) {
                const T u = rng_next_unit<T>(numbers);
                const T u_keep = rng_next_unit<T>(numbers);
                const std::uint32_t i = exact_index(u, p);
                vpl<T> v;
                const vec3<T> h =
                    ris_mis_unshadowed(gp, f.r.view, draws[i].s, draws[i].pmf, n1, n2, mode, f.tol, v);
                const T target = luminance(h);
                if (!(target >= std::numeric_limits<T>::min() && target <= std::numeric_limits<T>::max())) continue;
                const T w = target / draws[i].pmf;
                if (!(w >= std::numeric_limits<T>::min() && w <= std::numeric_limits<T>::max())) continue;
                sum += w;
                if (first < 0) first = k;
                if (u_keep * sum < w || keep < 0) {
                  keep = k;
                  keep_entry = i;
                  keep_target = target;
                  keep_h = h;
                }
              }
              ++compared;
              CHECK(same_bits(r.confidence, T(m)));
              if (keep < 0) {
                CHECK_FALSE(ris_reservoir_has_sample(r));
                CHECK(r.weight_sum == T(0));
                CHECK(kept.h == vec3<T>(T(0)));
                continue;
              }
              ++kept_any;
              if (keep != first) ++replaced;
              REQUIRE(ris_reservoir_has_sample(r));
              CHECK(r.kept.texel == pool[keep_entry].texel);
              CHECK(same_bits(r.kept.xi, pool[keep_entry].xi));
              CHECK(same_bits(r.target, keep_target));
              CHECK(same_bits(r.weight_sum, sum / T(m)));
              CHECK(same_bits(kept.h, keep_h));
              CHECK(same_bits(kept.position, pool[keep_entry].position));
              CHECK(same_bits(kept.normal, pool[keep_entry].normal));
            }
    }
  CHECK(kept_any > compared / 3);
  CHECK(replaced > kept_any / 4);  // the selection is exercised, not only "keep the first"
}

TEMPLATE_TEST_CASE("ris pool: the pooled estimate's layout, candidates then direction per step", "[ris-pool]", float,
                   double) {
  // Step j < max(n_dirs, n_ris): if j < n_ris one reservoir (2 M numbers) shaded from what it kept
  // over n_ris, then if j < n_dirs the direction (2 numbers); both strategies' weights count
  // n2 = n_ris max(1, M/2) VPL samples (M = 5: 2.5 per RIS sample). Written out here from the
  // pieces; a loop that drew all reservoirs first, divided the RIS values by n2, or weighed with
  // n2 = n_ris or n2 = M, would differ.
  using T = TestType;
  const pool_room<T> f;
  const auto& r = f.r;
  for (const vpl_mode mode : {vpl_mode::point, vpl_mode::patch}) {
    std::vector<ris_pool_entry<T>> pool;
    for (std::uint32_t i = 0; i < 128; ++i) pool.push_back(ris_pool_draw_entry(r.view, f.flux, 3u, i, mode, f.tol));
    int nonzero = 0;
    for (const auto& [nd, nr, m] : std::vector<std::tuple<int, int, int>>{{3, 2, 5}, {2, 4, 3}, {0, 3, 4}, {4, 0, 7}}) {
      for (const auto& g : r.gps) {
        INFO("mode " << int(mode) << " n_dirs " << nd << " n_ris " << nr << " M " << m << " " << g.name);
        const counter_rng start = make_counter_rng(12u, 5u);
        counter_rng rng = start;
        const vec3<T> e = estimate_ris_mis_pooled(g.gp, r.view, f.flux, pool.data(), 128u, rng, nd, nr, m, r.tracer,
                                                  r.vis, f.tol, mode);
        CHECK(rng.counter == 2u * std::uint32_t(nr * m) + 2u * std::uint32_t(nd));
        counter_rng q = start;
        const T n1 = T(nd), n2 = T(nr) * T(std::max(m, 2)) / T(2);
        const orthonormal_basis<T> frame = make_orthonormal_basis(gather_point_shading_normal(g.gp));
        vec3<T> sum(T(0));
        for (int j = 0; j < std::max(nd, nr); ++j) {
          if (j < nr) {
            ris_mis_kept<T> kept;
            const ris_reservoir<T> res = ris_mis_resample_pooled(g.gp, pool.data(), 128u, q, m, n1, n2, kept);
            sum += ris_mis_shade_kept(g.gp, res, kept, r.vis) / T(nr);
          }
          if (j < nd) {
            const T u0 = rng_next_unit<T>(q), u1 = rng_next_unit<T>(q);
            sum += mis_gathering_sample(g.gp, r.view, f.flux, frame, sample_cosine_hemisphere(vec2<T>(u0, u1)),
                                        r.tracer, f.tol, n1, n2, mis_mode::solid_angle, mode);
          }
        }
        CHECK(same_bits(e, sum));
        CHECK(q.counter == rng.counter);
        if (luminance(e) > T(0)) ++nonzero;
      }
    }
    CHECK(nonzero > 14);
  }
}

TEMPLATE_TEST_CASE("ris pool: the pooled estimate is its range form split anywhere, bit for bit", "[ris-pool]", float,
                   double) {
  // [0, k) then [k, end) for every k, every step its own range, and uneven cuts: the one-shot's sum
  // and stream. A range form that restarted its steps at 0, or kept n2 from the range's length,
  // would differ.
  using T = TestType;
  const pool_room<T> f;
  const auto& r = f.r;
  for (const vpl_mode mode : {vpl_mode::point, vpl_mode::patch}) {
    std::vector<ris_pool_entry<T>> pool;
    for (std::uint32_t i = 0; i < 64; ++i) pool.push_back(ris_pool_draw_entry(r.view, f.flux, 9u, i, mode, f.tol));
    for (const auto& counts :
         std::vector<std::tuple<int, int, int>>{{5, 3, 8}, {2, 6, 2}, {0, 4, 16}, {4, 0, 3}, {3, 3, 1}})
      for (std::size_t gi = 0; gi < r.gps.size(); ++gi) {
        const int nd = std::get<0>(counts), nr = std::get<1>(counts), m = std::get<2>(counts);
        const gather_point<T>& gp = r.gps[gi].gp;
        const int end = std::max(nd, nr);
        INFO("mode " << int(mode) << " n_dirs " << nd << " n_ris " << nr << " M " << m << " " << r.gps[gi].name);
        const counter_rng start = make_counter_rng(15u, std::uint32_t(gi));
        counter_rng a = start;
        const vec3<T> whole =
            estimate_ris_mis_pooled(gp, r.view, f.flux, pool.data(), 64u, a, nd, nr, m, r.tracer, r.vis, f.tol, mode);
        const auto range = [&](estimator_state<T>& st, int b, int e) {
          estimate_ris_mis_pooled_range(gp, r.view, f.flux, pool.data(), 64u, st, b, e, nd, nr, m, r.tracer, r.vis,
                                        f.tol, mode);
        };
        for (int k = 0; k <= end; ++k) {
          estimator_state<T> st = make_estimator_state<T>(start);
          range(st, 0, k);
          range(st, k, end);
          INFO("split at " << k);
          CHECK(same_bits(estimate_ris_mis_finish(st), whole));
          CHECK(st.rng.counter == a.counter);
        }
        check_splits<T>(
            start, cuts_of(end, {0, 0, 1, end / 2, end / 2, end}),
            [&](counter_rng& rng) {
              return estimate_ris_mis_pooled(gp, r.view, f.flux, pool.data(), 64u, rng, nd, nr, m, r.tracer, r.vis,
                                             f.tol, mode);
            },
            range, [](const estimator_state<T>& st) { return estimate_ris_mis_finish(st); });
      }
  }
}
