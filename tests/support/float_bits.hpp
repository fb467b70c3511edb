// SPDX-License-Identifier: MIT
#pragma once
// Floats as bits for the tests (vplkit::float_bits underneath): the float limits the hard cases use, exact
// comparisons of GPU and C++ results, and the ordered ulp distance the parity bounds are stated in.
#include <vplkit/core/float_bits.hpp>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <type_traits>
#include <vector>

namespace vplkit_test {

// The float limits the hard cases are made of.
constexpr float flt_eps = std::numeric_limits<float>::epsilon();  // 2^-23
constexpr float flt_min = std::numeric_limits<float>::min();      // smallest normal
constexpr float flt_denorm_min = std::numeric_limits<float>::denorm_min();
constexpr float flt_max = std::numeric_limits<float>::max();
constexpr float flt_inf = std::numeric_limits<float>::infinity();
constexpr float flt_nan = std::numeric_limits<float>::quiet_NaN();
constexpr double pi = 3.14159265358979323846;

inline std::uint32_t bits_of(float f) { return vplkit::float_bits(f); }

inline std::vector<std::uint32_t> bits_of(const std::vector<float>& v) {
  std::vector<std::uint32_t> out(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) out[i] = bits_of(v[i]);
  return out;
}

// Bit-for-bit equality of two values (vectors included): "the same result", NaNs and signed
// zeros told apart.
template <class V>
bool same_bits(const V& a, const V& b) {
  static_assert(std::is_trivially_copyable<V>::value, "same_bits compares object representations");
  return std::memcmp(&a, &b, sizeof a) == 0;
}

inline float float_of(std::uint32_t u) { return vplkit::float_from_bits(u); }

// Ordered distance in float ulps (+0 and -0 are 0 apart); infinite when one side is NaN or the
// two differ in infinity.
inline double ulp_distance(float a, float b) {
  if (std::isnan(a) || std::isnan(b)) {
    return std::isnan(a) && std::isnan(b) ? 0.0 : std::numeric_limits<double>::infinity();
  }
  if (std::isinf(a) || std::isinf(b)) {
    return a == b ? 0.0 : std::numeric_limits<double>::infinity();
  }
  // Map the sign-magnitude bit patterns onto one line of integers: adjacent floats are 1 apart
  // and +0 / -0 coincide.
  auto ordered = [](float f) {
    const std::uint32_t u = bits_of(f);
    const std::int64_t magnitude = static_cast<std::int64_t>(u & 0x7fffffffu);
    return (u >> 31) != 0 ? -magnitude : magnitude;
  };
  return std::fabs(static_cast<double>(ordered(a) - ordered(b)));
}

}  // namespace vplkit_test
