// SPDX-License-Identifier: MIT
// The host shortcuts of mis/heuristics.hpp (balance_combined, and mis_balance_value's three
// channels) and mis/pdf_conversion.hpp (vpl_pdf_solid_angle) against the general forms that every
// T runs (balance_divide of balance_denominator; detail::vpl_pdf_solid_angle_scaled). The shortcuts
// exist for speed only (the RIS candidates' weights evaluate both per candidate), so they must not
// change a bit, with IEEE arithmetic and under FTZ|DAZ: checked on random inputs over the whole
// range of magnitudes (every binade, denormals and specials included), and on inputs whose products
// and quotients land next to the smallest normal and the largest finite T, where the shortcuts hand
// over to the general forms.
#include <fp_mode.hpp>

#include <vplkit/estimators/mis_estimator.hpp>
#include <vplkit/mis/heuristics.hpp>
#include <vplkit/mis/pdf_conversion.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <sstream>

namespace {

template <class T>
bool same_bits(T a, T b) {
  if (std::isnan(a) && std::isnan(b)) return true;
  return std::memcmp(&a, &b, sizeof a) == 0;
}

// A value of any binade (denormals included), either sign with `negative`, or now and then a
// special: 0, +-Inf, NaN, the largest and smallest normal.
template <class T>
struct any_magnitude {
  std::mt19937_64 rng;
  explicit any_magnitude(std::uint64_t seed) : rng(seed) {}
  T operator()(bool negative) {
    using lim = std::numeric_limits<T>;
    const std::uint64_t pick = rng() % 64;
    T x;
    if (pick == 0) x = T(0);
    else if (pick == 1) x = lim::infinity();
    else if (pick == 2) x = lim::quiet_NaN();
    else if (pick == 3) x = lim::max();
    else if (pick == 4) x = lim::min();
    else if (pick == 5) x = lim::denorm_min();
    else {
      const int span = lim::max_exponent - (lim::min_exponent - lim::digits);
      const int e = int(rng() % std::uint64_t(span)) + (lim::min_exponent - lim::digits);
      const T m = T(1) + T(rng() >> 11) * T(0x1p-53);  // [1, 2)
      x = std::ldexp(m, e);
    }
    return negative && (rng() & 1u) ? -x : x;
  }
  // A value near `target`: within a few binades and a few ulps of it.
  T near(T target) {
    const int de = int(rng() % 5) - 2;
    T x = std::ldexp(target, de);
    for (int k = int(rng() % 7); k > 0; --k) x = std::nextafter(x, (rng() & 1u) ? T(0) : std::numeric_limits<T>::max());
    return x;
  }
  // A count as the renderers pass them (small integers, halves) or any magnitude.
  T count() {
    const T counts[] = {T(0), T(1), T(2), T(8), T(64), T(1024), T(12.5)};
    return rng() % 4 == 0 ? (*this)(true) : counts[rng() % 7];
  }
};

template <class T>
std::string describe(std::initializer_list<T> xs) {
  std::ostringstream s;
  s << std::hexfloat;
  for (T x : xs) s << x << " ";
  return s.str();
}

// What one case reports: whether the shortcut's bits equal the general form's, whether it took the
// shortcut's path (so that the shortcut is exercised, not only the general form), and the inputs.
struct case_result {
  bool same = true;
  bool shortcut = false;
  std::string inputs;
};

// Runs one_case(gen, i) for i < n, in IEEE mode and again under FTZ|DAZ (the same inputs: the
// generator restarts from seed), and checks that no case differs and that more than a quarter
// took the shortcut. `what` names the inputs in the message of the first difference.
template <class T, class Case>
void check_in_both_fp_modes(std::uint64_t seed, int n, const char* what, Case one_case) {
  for (const bool ftz : {false, true}) {
    const vplkit_test::fp_mode_scope mode(ftz);
    any_magnitude<T> gen(seed);
    std::size_t differ = 0, shortcut = 0;
    std::string first;
    for (int i = 0; i < n; ++i) {
      const case_result r = one_case(gen, i);
      if (r.shortcut) ++shortcut;
      if (!r.same && differ++ == 0) first = r.inputs;
    }
    INFO((ftz ? "FTZ|DAZ" : "IEEE") << ", " << n << " cases (" << shortcut
                                    << " through the shortcut); first difference (" << what << "): " << first);
    CHECK(differ == 0);
    CHECK(shortcut > std::size_t(n / 4));
  }
}

template <class T>
void check_balance(std::uint64_t seed, int n) {
  using lim = std::numeric_limits<T>;
  check_in_both_fp_modes<T>(seed, n, "n1 p1 n2 p2 f", [](any_magnitude<T>& gen, int i) {
    T n1 = gen.count(), n2 = gen.count(), p1 = gen(true), p2 = gen(true);
    vplkit::vec3<T> f(gen(true), gen(true), gen(true));
    if (i % 3 == 1) {
      // Products and quotients next to the ends of the range.
      const T ends[] = {lim::min(), T(2) * lim::min(), lim::max(), T(1)};
      p1 = gen.near(ends[gen.rng() % 4]) / (n1 > T(0) ? n1 : T(1));
      p2 = gen.near(ends[gen.rng() % 4]) / (n2 > T(0) ? n2 : T(1));
      const T d = n1 * p1 + n2 * p2;
      f.x = gen.near(d * ends[gen.rng() % 4]);
      f.y = gen.near(d * lim::min());
      f.z = gen.near(d);
    } else if (i % 3 == 2) {
      // What the estimators pass: moderate counts, densities and values.
      n1 = T(1 + gen.rng() % 64);
      n2 = T(1 + gen.rng() % 64);
      p1 = gen.near(T(0.3));
      p2 = gen.near(T(50));
      f = vplkit::vec3<T>(gen.near(T(0.02)), gen.near(T(0.01)), gen.near(T(1e-3)));
    }
    const vplkit::mis_balance_denominator<T> den = vplkit::balance_denominator(n1, p1, n2, p2);
    const vplkit::vec3<T> fast = vplkit::mis_balance_value(f, n1, p1, n2, p2);
    const vplkit::vec3<T> ref(vplkit::balance_divide(f.x, den), vplkit::balance_divide(f.y, den),
                              vplkit::balance_divide(f.z, den));
    const T one = vplkit::balance_combined(f.x, n1, p1, n2, p2);
    T d;
    case_result r;
    r.shortcut = vplkit::detail::balance_denominator_plain(n1, p1, n2, p2, d);
    r.same = same_bits(fast.x, ref.x) && same_bits(fast.y, ref.y) && same_bits(fast.z, ref.z) && same_bits(one, ref.x);
    if (!r.same) r.inputs = describe({n1, p1, n2, p2, f.x, f.y, f.z});
    return r;
  });
}

template <class T>
void check_vpl_pdf(std::uint64_t seed, int n) {
  using lim = std::numeric_limits<T>;
  check_in_both_fp_modes<T>(seed, n, "pmf d2 A cos", [](any_magnitude<T>& gen, int i) {
    T pmf = gen(true), d2 = gen(true), area = gen(true), c = gen(true);
    if (i % 3 == 1) {
      const T ends[] = {lim::min(), T(2) * lim::min(), lim::max(), T(1)};
      pmf = gen.near(T(1e-6));
      d2 = gen.near(ends[gen.rng() % 4]) / pmf;
      area = gen.near(T(0.5));
      c = gen.near(ends[gen.rng() % 4]) / area;
      if (gen.rng() % 2) d2 = gen.near(pmf * d2 / (ends[gen.rng() % 4]) * (area * c) / pmf);
    } else if (i % 3 == 2) {
      pmf = gen.near(T(1e-5));
      d2 = gen.near(T(4));
      area = gen.near(T(1e-3));
      c = gen.near(T(0.5));
    }
    const T fast = vplkit::vpl_pdf_solid_angle(pmf, d2, area, c);
    const T ref = vplkit::detail::vpl_pdf_solid_angle_scaled(pmf, d2, area, c);
    case_result r;
    // A moderate result: the shortcut's range (a positive finite p2).
    r.shortcut = fast > T(0) && fast < lim::infinity();
    r.same = same_bits(fast, ref);
    if (!r.same) r.inputs = describe({pmf, d2, area, c});
    return r;
  });
}

}  // namespace

TEST_CASE("balance_combined and mis_balance_value: the host shortcut (float) is the general form's bits",
          "[mis][hardcase]") {
  check_balance<float>(11u, 400000);
}

TEST_CASE("balance_combined and mis_balance_value: the host shortcut (double) is the general form's bits",
          "[mis][hardcase]") {
  check_balance<double>(12u, 200000);
}

TEST_CASE("vpl_pdf_solid_angle: the host shortcut (float) is the general form's bits", "[mis][hardcase]") {
  check_vpl_pdf<float>(13u, 400000);
}

TEST_CASE("vpl_pdf_solid_angle: the host shortcut (double) is the general form's bits", "[mis][hardcase]") {
  check_vpl_pdf<double>(14u, 200000);
}
