// SPDX-License-Identifier: MIT
#pragma once
// What the Vulkan test cases share: a context whose validation messages fail the test case, and
// small comparison helpers (bits, ulps, printing).
#include "vulkan_compute.hpp"

#include <float_bits.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <iostream>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

namespace vplkit::vk_test {

// Runs body(context&) on a fresh instance and device. Every validation message of severity warning
// or error recorded while they lived (creation, the body, destruction) fails the test case.
template <class Body>
void with_vulkan(Body&& body) {
  validation_log log;
  {
    context ctx(log);
    std::cout << "vulkan: " << ctx.describe() << std::endl;
    body(ctx);
  }
  for (const std::string& m : log.messages) UNSCOPED_INFO("validation: " << m);
  CHECK(log.messages.size() == 0u);
}

using vplkit_test::bits_of;

// Distance in float steps (0 for equal values, +-0 equal; infinite across NaN). Stricter than
// vplkit_test::ulp_distance: NaN against NaN is infinitely far too, so no bound passes a NaN.
inline double ulp_distance(float a, float b) {
  if (std::isnan(a) || std::isnan(b)) return std::numeric_limits<double>::infinity();
  auto ordered = [](float f) {
    const std::int64_t u = std::int64_t(bits_of(f));
    return u & 0x80000000 ? -(u & 0x7FFFFFFF) : u;
  };
  return double(std::llabs(ordered(a) - ordered(b)));
}

inline std::string show(double v) {
  std::ostringstream s;
  s.precision(9);
  s << v;
  return s.str();
}

// The first differing index of two equally long arrays, -1 if none; with a note for the report.
template <class T>
std::ptrdiff_t first_difference(const std::vector<T>& a, const std::vector<T>& b) {
  if (a.size() != b.size()) return std::ptrdiff_t(std::min(a.size(), b.size()));
  for (std::size_t i = 0; i < a.size(); ++i)
    if (!(a[i] == b[i])) return std::ptrdiff_t(i);
  return -1;
}

// Largest relative difference |a - b| / |b| (0 where both are 0), and where.
struct worst_relative {
  double value = 0;
  std::size_t index = 0;
};
inline worst_relative max_relative(const std::vector<float>& a, const std::vector<float>& b) {
  worst_relative w;
  for (std::size_t i = 0; i < a.size() && i < b.size(); ++i) {
    const double d = std::fabs(double(a[i]) - double(b[i]));
    const double r = d == 0 ? 0 : d / std::max(std::fabs(double(b[i])), 1e-300);
    if (r > w.value || std::isnan(r)) {
      w.value = std::isnan(r) ? std::numeric_limits<double>::infinity() : r;
      w.index = i;
    }
  }
  return w;
}

}  // namespace vplkit::vk_test
