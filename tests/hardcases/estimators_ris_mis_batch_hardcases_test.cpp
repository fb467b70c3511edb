// SPDX-License-Identifier: MIT
// The fast paths of ris-mis's candidate loop (estimators/ris_mis_estimator.hpp) against the
// expressions they stand for, bit for bit:
// - ris_mis_resample draws its candidates in batches (numbers and draws first, with the texels
//   prefetched, then the weights): the same reservoir and the same numbers drawn as one candidate at
//   a time with the per-candidate normalisations (the GLSL mirror's loop), for candidate counts
//   below, at and above the batch, point and patch VPLs, with the view's plane records and without;
// - the *_unit forms that take a normal already normalised (mis_vpl_unshadowed_unit,
//   reflected_radiance_unit_normal, dprsm_plane_side_of_unit) give their normalising forms' values
//   on degenerate input too: zero, NaN, infinite, tiny and huge normals, coincident points.
#include <float_bits.hpp>
#include <synthetic_scene.hpp>

#include <vplkit/builders/flux_weights.hpp>
#include <vplkit/builders/vpl_distribution.hpp>
#include <vplkit/core/unit_or_zero.hpp>
#include <vplkit/estimators/mis_estimator.hpp>
#include <vplkit/estimators/ris_mis_estimator.hpp>
#include <vplkit/vpl/dprsm_lookup.hpp>
#include <vplkit/vpl/dprsm_planes.hpp>
#include <vplkit/vpl/vpl.hpp>

#include <catch2/catch.hpp>
#include <special_values.hpp>

#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

using namespace vplkit;
using namespace vplkit_test;

namespace {

// L_o of a lit point y with its normal normalised here (reflected_radiance's expressions).
template <class T>
vec3<T> radiance_reference(vec3<T> c, vec3<T> intensity, vec3<T> y, vec3<T> n, vec3<T> rho) {
  if (vpl_points_coincide(c, y)) return vec3<T>(T(0));
  const vec3<T> w = c - y;
  const T cos_a = glm::max(T(0), flush_denormal(glm::dot(unit_or_zero(n), unit_or_zero(w))));
  if (!(cos_a > T(0))) return vec3<T>(T(0));
  const T d1sq = glm::max(glm::dot(w, w), vpl_distance_sq_floor<T>());
  return flush_denormal(rho * intensity * flush_denormal(cos_a / (vpl_pi<T> * d1sq)));
}

// mis_vpl_unshadowed as it was written before its fast path: both of gp's normals and the VPL's
// normalised per call.
template <class T>
vec3<T> mis_value_reference(const gather_point<T>& gp, const dprsm_view<T>& view, int t, const vpl<T>& v, T pmf,
                            T area, T n1, T n2) {
  const vec3<T> x = gp.position, y = v.position;
  if (!vpl_has_flux(v) || vpl_points_coincide(x, y)) return vec3<T>(T(0));
  const vec3<T> wd = unit_or_zero(y - x);
  const T cos2 = glm::dot(unit_or_zero(gather_point_shading_normal(gp)), wd);
  const T cos1 = -glm::dot(unit_or_zero(v.normal), wd);
  if (!(cos2 > T(0)) || !(cos1 > T(0)) || !(glm::dot(unit_or_zero(gp.normal), wd) > T(0))) return vec3<T>(T(0));
  const vec3<T> f = gp.albedo * radiance_reference(view.light.position, view.light.intensity, y, v.normal,
                                                   view.albedo[t]) * (cos2 / vpl_pi<T>);
  const vec3<T> w = x - y;
  const T p2 = vpl_pdf_solid_angle(pmf, glm::dot(w, w), area, cos1);
  return mis_balance_value(f, n1, cosine_pdf_solid_angle(cos2), n2, p2);
}

// ris_mis_unshadowed as it was written before its fast path.
template <class T>
vec3<T> unshadowed_reference(const gather_point<T>& gp, const dprsm_view<T>& view, const ris_sample<T>& s, T pmf,
                             T n1, T n2, vpl_mode mode, T tol) {
  if (!(pmf > T(0)) || !(n2 > T(0)) || s.texel < 0 || s.texel >= view.texel_count()) return vec3<T>(T(0));
  vpl<T> v;
  T area;
  if (mode == vpl_mode::patch) {
    const dprsm_patch_sample<T> p = dprsm_patch_vpl(view, s.texel, s.xi, tol);
    if (p.at_centre && n1 > T(0)) return vec3<T>(T(0));
    v = p.point;
    area = vpl_patch_area(p.solid_angle, p.distance, p.cos_alpha);
  } else {
    v = view.vpl_at(s.texel);
    area = mis_texel_patch_area(view, s.texel);
  }
  return estimator_finite_or_zero(mis_value_reference(gp, view, s.texel, v, pmf, area, n1, n2) * (n2 * pmf));
}

// ris_mis_resample one candidate at a time with unshadowed_reference.
template <class T, class D>
ris_reservoir<T> resample_reference(const gather_point<T>& gp, const dprsm_view<T>& view, const D& dist,
                                    counter_rng& rng, int m, T n1, T n2, vpl_mode mode, T tol) {
  ris_reservoir<T> r;
  if (!gather_point_valid(gp) || m <= 0 || !(n2 > T(0))) return r;
  weighted_reservoir<T> res;
  for (int i = 0; i < m; ++i) {
    ris_sample<T> s;
    const T u = rng_next_unit<T>(rng);
    if (mode == vpl_mode::patch) {
      s.xi.x = rng_next_unit<T>(rng);
      s.xi.y = rng_next_unit<T>(rng);
    }
    const auto d = dist.sample(u);
    const T pmf = estimator_pmf(T(d.pmf));
    T w = T(0), target = T(0);
    if (pmf > T(0) && d.index < std::size_t(view.texel_count())) {
      s.texel = int(d.index);
      const T p = luminance(unshadowed_reference(gp, view, s, pmf, n1, n2, mode, tol));
      if (reservoir_weight_usable(p)) {
        target = p;
        w = p / pmf;
      }
    }
    if (reservoir_update(res, std::uint32_t(i), w, rng_next_unit<T>(rng))) {
      r.kept = s;
      r.target = target;
    }
  }
  r.confidence = T(m);
  if (!reservoir_empty_of(res)) r.weight_sum = res.weight_sum / T(m);
  return r;
}

// A T with a random sign, exponent in [lo, hi] and mantissa (splitmix64 bits).
template <class T>
T random_float(std::uint64_t& state, int lo, int hi) {
  state += 0x9e3779b97f4a7c15ull;
  std::uint64_t z = state;
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  z ^= z >> 31;
  const int e = lo + int(z % std::uint64_t(hi - lo + 1));
  const T mant = T(1) + T((z >> 11) & ((1ull << 40) - 1)) / T(1ull << 40);
  const T x = std::ldexp(mant, e);
  return (z >> 63) != 0 ? -x : x;
}

}  // namespace

TEMPLATE_TEST_CASE("unit_or_zero hard case: the host shortcut gives the scaled form's bits", "[hardcases][ris-mis]",
                   float, double) {
  using T = TestType;
  using lim = std::numeric_limits<T>;
  std::uint64_t state = 12345u;
  int mismatches = 0;
  long shortcut = 0;
  const int lo = lim::min_exponent - lim::digits - 2, hi = lim::max_exponent;
  for (int i = 0; i < 400000; ++i) {
    // Components of exponents near each other (the common case), of independent exponents over the
    // whole range (denormals, overflow), and with exact zeros, NaN and infinities mixed in.
    const int centre = -70 + i % 141;
    vec3<T> v;
    if (i % 3 == 0) {
      v = vec3<T>(random_float<T>(state, centre - 3, centre + 3), random_float<T>(state, centre - 30, centre),
                  random_float<T>(state, centre - 12, centre + 1));
    } else if (i % 3 == 1) {
      v = vec3<T>(random_float<T>(state, lo, hi), random_float<T>(state, lo, hi), random_float<T>(state, lo, hi));
    } else {
      v = vec3<T>(random_float<T>(state, -64, 64), T(0), random_float<T>(state, -64, 64));
      if (i % 11 == 2) v.y = lim::quiet_NaN();
      if (i % 13 == 2) v.z = lim::infinity();
      if (i % 17 == 2) v.x = lim::denorm_min();
    }
    const T m = max_abs_component(flush_denormal(v));
    if (m >= T(0x1p-50) && m <= T(0x1p60)) ++shortcut;
    const vec3<T> a = unit_or_zero(v), b = vplkit::detail::unit_or_zero_scaled(v);  // the general path
    if (!same_bits(a, b)) {
      if (mismatches < 5) {
        INFO("v " << v.x << " " << v.y << " " << v.z);
        CHECK(same_bits(a, b));
      }
      ++mismatches;
    }
  }
  CHECK(mismatches == 0);
  CHECK(shortcut > 100000);  // the shortcut is exercised
}

TEMPLATE_TEST_CASE("ris-mis hard case: batched candidates give the one-at-a-time reservoir bit for bit",
                   "[hardcases][ris-mis]", float, double) {
  using T = TestType;
  lit_room<T> f{16};
  const defensive_mixture<T> flux = make_vpl_distribution(build_flux_weights(f.view), f.view, T(0.05));
  const std::vector<dprsm_plane<T>> planes = build_dprsm_planes(f.view);
  dprsm_view<T> with_planes = f.view;
  with_planes.planes = planes.data();
  const T tol = T(0.2);
  int compared = 0, kept = 0;
  for (const dprsm_view<T>* view : {&f.view, &with_planes})
    for (const vpl_mode mode : {vpl_mode::point, vpl_mode::patch})
      for (const int m : {1, 2, 7, 8, 9, 16, 17, 33})
        for (const T n1 : {T(0), T(4)})
          for (std::size_t i = 0; i < f.gps.size(); ++i) {
            INFO("planes " << (view->planes != nullptr) << " mode " << int(mode) << " M " << m << " n1 " << n1
                           << " point " << f.gps[i].name);
            const gather_point<T>& gp = f.gps[i].gp;
            counter_rng a = make_counter_rng(7u, std::uint32_t(i)), b = a;
            const ris_reservoir<T> fast = ris_mis_resample(gp, *view, flux, a, m, n1, T(4), mode, tol);
            const ris_reservoir<T> ref = resample_reference(gp, *view, flux, b, m, n1, T(4), mode, tol);
            CHECK(a.counter == b.counter);
            CHECK(fast.kept.texel == ref.kept.texel);
            CHECK(same_bits(fast.kept.xi.x, ref.kept.xi.x));
            CHECK(same_bits(fast.kept.xi.y, ref.kept.xi.y));
            CHECK(same_bits(fast.target, ref.target));
            CHECK(same_bits(fast.weight_sum, ref.weight_sum));
            CHECK(same_bits(fast.confidence, ref.confidence));
            ++compared;
            if (ris_reservoir_has_sample(fast)) ++kept;
          }
  CHECK(compared > 0);
  CHECK(kept > compared / 4);  // the comparison sees real selections, not only empty reservoirs
}

TEMPLATE_TEST_CASE("ris-mis hard case: the unit-normal forms match their normalising forms on degenerate input",
                   "[hardcases][ris-mis]", float, double) {
  using T = TestType;
  using lim = std::numeric_limits<T>;
  lit_room<T> f{16};
  const T nan = lim::quiet_NaN(), inf = lim::infinity();
  const std::vector<vec3<T>> normals = {vec3<T>(T(0), T(1), T(0)),
                                        vec3<T>(T(0), T(-1), T(0)),
                                        vec3<T>(T(0)),
                                        vec3<T>(nan, T(1), T(0)),
                                        vec3<T>(inf, T(0), T(0)),
                                        vec3<T>(T(1e-30), T(2e-30), T(0)),
                                        vec3<T>(T(3e30), T(1e30), T(0)),
                                        vec3<T>(lim::denorm_min(), T(0), T(0)),
                                        vec3<T>(T(0.3), T(0.9), T(-0.2))};
  const std::vector<vec3<T>> points = {vec3<T>(T(0.1), T(0.2), T(0.3)), vec3<T>(T(-0.4), T(0.9), T(0.5)),
                                       vec3<T>(nan, T(0), T(0)), vec3<T>(inf, T(1), T(0)),
                                       vec3<T>(T(1e30), T(0), T(0)), f.view.light.position};
  const vec3<T> c = f.view.light.position;
  int cases = 0;
  for (const vec3<T>& n : normals)
    for (const vec3<T>& y : points) {
      INFO("n " << n.x << " " << n.y << " " << n.z << " y " << y.x << " " << y.y << " " << y.z);
      const vec3<T> n_u = unit_or_zero(n);
      const vec3<T> rho(T(0.5), T(0.6), T(0.7));
      const vec3<T> a = radiance_reference(c, f.view.light.intensity, y, n, rho);
      CHECK(same_bits(reflected_radiance(c, f.view.light.intensity, y, n, rho), a));
      CHECK(same_bits(reflected_radiance_unit_normal(c, f.view.light.intensity, y, n_u, rho), a));
      for (std::size_t i = 0; i < f.gps.size(); ++i)
        for (int variant = 0; variant < 3; ++variant) {
          gather_point<T> gp = f.gps[i].gp;
          if (variant == 1) gp.shading_normal = n;  // degenerate shading normals
          if (variant == 2) gp.position = y;         // the VPL at the gather point, or a non-finite one
          const vpl<T> v{y, n, vec3<T>(T(1), T(2), T(3))};
          const vec3<T> ref = mis_value_reference(gp, f.view, 0, v, T(0.01), T(0.5), T(4), T(4));
          const vec3<T> fast = mis_vpl_unshadowed_unit(gp, make_mis_receiver(gp), f.view, 0, v, n_u, T(0.01),
                                                       T(0.5), T(4), T(4));
          CHECK(same_bits(mis_vpl_unshadowed(gp, f.view, 0, v, T(0.01), T(0.5), T(4), T(4)), ref));
          CHECK(same_bits(fast, ref));
          CHECK(finite3(fast));
          ++cases;
        }
    }
  CHECK(cases > 0);
  // The lit test from a texel's plane record (dprsm_patch_vpl's use) against the direct form, for
  // every texel with a plane and points on, in front of and behind it, and degenerate ones.
  int planes = 0;
  for (int t = 0; t < f.view.texel_count(); ++t) {
    const dprsm_plane<T> rec = f.view.plane_at(t);
    if (rec.height == T(0)) continue;
    ++planes;
    const vec3<T> y_t = f.view.position[t], n_t = f.view.normal[t];
    for (const T s : {T(0.5), T(0.99), T(1), T(1.01), T(2)})
      for (const T tol : {T(0), T(0.01), nan, T(-1)}) {
        const vec3<T> q = c + (y_t - c) * s;
        const T d = scaled_length(q - c);
        CHECK(dprsm_plane_side_of_unit(c, y_t, rec.normal, std::abs(rec.height), q, d, tol, f.view.resolution) ==
              dprsm_plane_side_of(c, y_t, n_t, q, d, tol, f.view.resolution));
      }
    for (const vec3<T>& q : points) {
      const T d = scaled_length(q - c);
      CHECK(dprsm_plane_side_of_unit(c, y_t, rec.normal, std::abs(rec.height), q, d, T(0.01), f.view.resolution) ==
            dprsm_plane_side_of(c, y_t, n_t, q, d, T(0.01), f.view.resolution));
    }
  }
  CHECK(planes > 0);
  // mis_balance_value forms the denominator once for the three channels: balance_combined's value
  // in each, on degenerate counts, pdfs and values too.
  const std::vector<T> values = {T(0), T(1), T(-2), T(1e-30), T(3e38), lim::min(), lim::denorm_min(), nan, inf};
  for (const T n1 : {T(0), T(4), nan, inf})
    for (const T p1 : {T(0), T(0.3), T(1e-38), T(1e30), inf, nan})
      for (const T p2 : {T(0), T(2), lim::denorm_min(), inf})
        for (const T fx : values) {
          const vec3<T> fv(fx, T(0.5), -fx);
          const vec3<T> b = mis_balance_value(fv, n1, p1, T(4), p2);
          CHECK(same_bits(b.x, balance_combined(fv.x, n1, p1, T(4), p2)));
          CHECK(same_bits(b.y, balance_combined(fv.y, n1, p1, T(4), p2)));
          CHECK(same_bits(b.z, balance_combined(fv.z, n1, p1, T(4), p2)));
          CHECK(finite3(b));
        }
}
