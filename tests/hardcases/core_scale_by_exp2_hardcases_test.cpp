// SPDX-License-Identifier: MIT
// core/normal_range.hpp's scale_by_exp2 and core/unit_or_zero.hpp's unit_or_zero: their host
// shortcuts (float and double) against the general forms that every T runs, over the whole range of
// magnitudes: the three products by normal powers of two, and the scaled normalisation. The
// shortcuts exist for speed only, so they must not change a bit, with IEEE arithmetic and under
// FTZ|DAZ.
#include <fp_mode.hpp>

#include <vplkit/core/normal_range.hpp>
#include <vplkit/core/unit_or_zero.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <sstream>
#include <vector>

namespace {

// scale_by_exp2's general form, as the header writes it for every T.
template <class T>
T three_products(T x, int k) {
  constexpr int kmax = vplkit::scale_by_exp2_max<T>;
  k = k < -kmax ? -kmax : k > kmax ? kmax : k;
  const int k1 = k / 3;
  const int k2 = (k - k1) / 2;
  const int k3 = k - k1 - k2;
  const T y = x * vplkit::exp2i<T>(k1);
  const T z = y * vplkit::exp2i<T>(k2);
  return vplkit::flush_denormal(z * vplkit::exp2i<T>(k3));
}

template <class T>
bool same_bits(T a, T b) {
  if (std::isnan(a) && std::isnan(b)) return true;
  return std::memcmp(&a, &b, sizeof a) == 0;
}

// Every binade (the denormals' included) with a few mantissas, both signs, and the specials.
template <class T>
std::vector<T> magnitudes(int exponent_step) {
  using lim = std::numeric_limits<T>;
  std::vector<T> xs = {T(0), -T(0), lim::infinity(), -lim::infinity(), lim::quiet_NaN(), lim::max(),
                       lim::min(), lim::denorm_min()};
  const T mantissas[] = {T(1), T(1.5), T(1.2345678901234567), T(2) - lim::epsilon()};
  for (int e = lim::min_exponent - lim::digits; e <= lim::max_exponent - 1; e += exponent_step)
    for (const T m : mantissas) {
      const T x = std::ldexp(m, e);
      xs.push_back(x);
      xs.push_back(-x);
    }
  return xs;
}

template <class T>
void check_scale_by_exp2(int exponent_step, int k_step) {
  const std::vector<T> xs = magnitudes<T>(exponent_step);
  const int kmax = vplkit::scale_by_exp2_max<T> + 30;
  for (const bool ftz : {false, true}) {
    const vplkit_test::fp_mode_scope mode(ftz);
    std::size_t compared = 0, differ = 0;
    std::ostringstream first;
    for (const T x : xs)
      for (int k = -kmax; k <= kmax; k += k_step) {
        const T fast = vplkit::scale_by_exp2(x, k), ref = three_products(x, k);
        ++compared;
        if (!same_bits(fast, ref) && differ++ == 0)
          first << std::hexfloat << x << " * 2^" << k << ": " << fast << ", three products " << ref;
      }
    INFO((ftz ? "FTZ|DAZ" : "IEEE") << ", " << compared << " pairs; first difference: " << first.str());
    CHECK(differ == 0);
    CHECK(compared > 100000);
  }
}

template <class T>
void check_unit_or_zero(int exponent_step) {
  const std::vector<T> xs = magnitudes<T>(exponent_step);
  const T second[] = {T(0), T(1), T(-0.75), T(1e-3), std::numeric_limits<T>::min()};
  for (const bool ftz : {false, true}) {
    const vplkit_test::fp_mode_scope mode(ftz);
    std::size_t compared = 0, differ = 0;
    std::ostringstream first;
    for (const T x : xs)
      for (const T y : second)
        for (int e = -8; e <= 8; e += 4) {
          // The second and third components relative to x's binade and far from it.
          const T s = std::isfinite(x) && x != T(0) ? std::ldexp(y, vplkit::binary_exponent(std::abs(x)) + e) : y;
          const vplkit::vec3<T> v(x, s, T(0.5) * s);
          const vplkit::vec3<T> fast = vplkit::unit_or_zero(v), ref = vplkit::detail::unit_or_zero_scaled(v);
          ++compared;
          if (!(same_bits(fast.x, ref.x) && same_bits(fast.y, ref.y) && same_bits(fast.z, ref.z)) && differ++ == 0)
            first << std::hexfloat << "(" << v.x << ", " << v.y << ", " << v.z << ")";
        }
    INFO((ftz ? "FTZ|DAZ" : "IEEE") << ", " << compared << " vectors; first difference: " << first.str());
    CHECK(differ == 0);
    CHECK(compared > 5000);
  }
}

}  // namespace

TEST_CASE("scale_by_exp2: the single product (float) is the three products' bits, every binade and k",
          "[core][hardcase]") {
  check_scale_by_exp2<float>(1, 1);
}

TEST_CASE("scale_by_exp2: the single product (double) is the three products' bits, every binade and k",
          "[core][hardcase]") {
  check_scale_by_exp2<double>(17, 7);
}

TEST_CASE("unit_or_zero: the host shortcut (float) is the scaled form's bits", "[core][hardcase]") {
  check_unit_or_zero<float>(1);
}

TEST_CASE("unit_or_zero: the host shortcut (double) is the scaled form's bits", "[core][hardcase]") {
  check_unit_or_zero<double>(9);
}
