// SPDX-License-Identifier: MIT
#pragma once
// Forward error bounds from the GPU arithmetic model (docs/math.md, "GPU arithmetic model";
// tests/support/gpu_precision.hpp), for parity checks of ill-conditioned results: a ray/triangle
// t, u, v from a nearly parallel ray, a hit distance from a division. Where the GPU's division is
// not correctly rounded or it contracts a*b+c, such a result can move by thousands of ulps on one
// side and not the other; an ulp bound cannot follow that, a bound from the operation chain can.
//
// `fe` carries a value v (the chain evaluated in double from the same float inputs) and e, a bound
// on |x - v| for x the chain evaluated by any arithmetic inside the model:
//   + - *    correctly rounded: relative 0.5 ulp (spec::add_mul_ulps) of the result;
//   a*b+c    contracted or not: one rounding fewer than the above, so inside the same bound;
//   /        2.5 ulp (spec::div_ulps), sqrt 4.5 ulp (spec::sqrt_ulps);
//   every op plus spec::flushed_product_abs (a denormal result flushed to 0).
// Each op also charges 2^-53 of its result for the double evaluation of v. The recursion is the
// standard first-order running error analysis (Higham, "Accuracy and Stability of Numerical
// Algorithms", 2nd ed., section 3.3) with the products of two errors kept, so it is a bound, not an
// estimate. Two conforming evaluations (the C++ reference and the GPU) then differ by at most 2 e.
#include <gpu_precision.hpp>
#include <parity_harness.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

namespace vplkit_test {

struct fe {
  double v = 0;
  double e = 0;
  fe() = default;
  fe(double value, double error = 0) : v(value), e(error) {}  // NOLINT: exact float inputs convert
};

namespace fe_detail {
inline constexpr double add_mul_rel = spec::rel(spec::add_mul_ulps) + 0x1p-53;
inline constexpr double div_rel = spec::rel(spec::div_ulps) + 0x1p-53;
inline constexpr double sqrt_rel = spec::rel(spec::sqrt_ulps) + 0x1p-53;
inline double round_err(double v, double e, double rel) {
  return e + rel * (std::fabs(v) + e) + spec::flushed_product_abs;
}
}  // namespace fe_detail

inline fe operator+(fe a, fe b) {
  const double v = a.v + b.v;
  return {v, fe_detail::round_err(v, a.e + b.e, fe_detail::add_mul_rel)};
}
inline fe operator-(fe a, fe b) {
  const double v = a.v - b.v;
  return {v, fe_detail::round_err(v, a.e + b.e, fe_detail::add_mul_rel)};
}
inline fe operator*(fe a, fe b) {
  const double v = a.v * b.v;
  const double e = std::fabs(a.v) * b.e + std::fabs(b.v) * a.e + a.e * b.e;
  return {v, fe_detail::round_err(v, e, fe_detail::add_mul_rel)};
}
// Unbounded (e = inf) where the divisor's error reaches its value.
inline fe operator/(fe a, fe b) {
  const double v = a.v / b.v;
  const double room = std::fabs(b.v) - b.e;
  if (!(room > 0) || !std::isfinite(v)) return {v, std::numeric_limits<double>::infinity()};
  const double e = (a.e + std::fabs(v) * b.e) / room;
  return {v, fe_detail::round_err(v, e, fe_detail::div_rel)};
}
inline fe fe_sqrt(fe a) {
  const double v = std::sqrt(std::max(a.v, 0.0));
  const double e = std::sqrt(std::max(a.v, 0.0) + a.e) - std::sqrt(std::max(a.v - a.e, 0.0));
  return {v, fe_detail::round_err(v, e, fe_detail::sqrt_rel)};
}
inline fe fe_abs(fe a) { return {std::fabs(a.v), a.e}; }
inline fe fe_max(fe a, fe b) { return a.v >= b.v ? fe{a.v, std::max(a.e, b.e)} : fe{b.v, std::max(a.e, b.e)}; }

// Per element: gpu and cpu agree when their bits are equal, both are NaN, or |gpu - cpu| <=
// bound[k] (the sum of the two sides' forward error bounds). The report names the worst ratio
// |gpu - cpu| / bound and the first failures, like the harness's comparisons.
inline vplkit::parity::comparison compare_within_bounds(const vplkit::parity::series<float>& s,
                                                        const std::vector<double>& bound,
                                                        const vplkit::parity::describe_fn& describe,
                                                        const std::string& what) {
  using vplkit::parity::show;
  vplkit::parity::comparison c;
  c.count = s.gpu.size();
  double worst_ratio = 0;
  std::size_t unbounded = 0;
  std::string first;
  for (std::size_t k = 0; k < s.gpu.size(); ++k) {
    const float g = s.gpu[k], r = s.cpu[k];
    std::uint32_t gb, rb;
    std::memcpy(&gb, &g, 4);
    std::memcpy(&rb, &r, 4);
    if (gb == rb || (std::isnan(g) && std::isnan(r))) continue;
    if (std::isinf(bound[k])) {
      ++unbounded;
      continue;
    }
    const double d = std::fabs(double(g) - double(r));
    const double ratio = bound[k] > 0 ? d / bound[k] : std::numeric_limits<double>::infinity();
    if (ratio > worst_ratio) {
      worst_ratio = ratio;
      c.worst_index = k;
      c.worst_abs = d;
    }
    if (d <= bound[k]) continue;
    if (c.failures++ < 10)
      first += "    [" + std::to_string(k) + "] gpu=" + show(g) + " cpu=" + show(r) + " |diff| " + show(float(d)) +
               " bound " + show(float(bound[k])) + (describe ? "  input: " + describe(k) : std::string()) + "\n";
  }
  c.ok = c.failures == 0;
  c.report = "parity " + what + ": " + std::to_string(c.count) +
             " floats, bound = the forward error bound of both sides (per element)\n  worst |diff| / bound: " +
             show(float(worst_ratio)) + " at [" + std::to_string(c.worst_index) + "]" +
             (describe && c.count ? "  input: " + describe(c.worst_index) : std::string()) + "\n  " +
             std::to_string(unbounded) + " differing elements with no finite bound (divisor within its own error)\n";
  c.report += c.ok ? "  PASS\n" : "  FAIL: " + std::to_string(c.failures) + " outside the bound; first ones:\n" + first;
  return c;
}

}  // namespace vplkit_test

namespace vplkit_test {

// Three components with their bounds.
struct fe3 {
  fe c[3];
  fe& operator[](int k) { return c[k]; }
  const fe& operator[](int k) const { return c[k]; }
};

template <class V>
inline fe3 fe3_of(const V& v, double error = 0) {
  return {{fe(double(v[0]), error), fe(double(v[1]), error), fe(double(v[2]), error)}};
}

// a.x * b.x + a.y * b.y + a.z * b.z, summed left to right (glm::dot, vplkit_voxel_dot).
inline fe fe_dot(const fe3& a, const fe3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

// v / max|v_k| / |v / max|v_k||: the normalisation of dda_unit_direction and bvh_unit_vector (the
// GLSL normalize() of a driver is inside the same bound: spec::normalize_ulps < div + sqrt).
// A non-finite v, or one whose largest |component| is below FLT_MIN, gives 0 on both sides (exact).
inline fe3 fe_unit_vector(const fe3& v) {
  const fe m = fe_max(fe_abs(v[0]), fe_max(fe_abs(v[1]), fe_abs(v[2])));
  if (!std::isfinite(v[0].v) || !std::isfinite(v[1].v) || !std::isfinite(v[2].v) || !(m.v >= 1.17549435e-38))
    return {{fe(0.0), fe(0.0), fe(0.0)}};
  const fe3 s{{v[0] / m, v[1] / m, v[2] / m}};
  const fe len = fe_sqrt(fe_dot(s, s));
  return {{s[0] / len, s[1] / len, s[2] / len}};
}

}  // namespace vplkit_test
