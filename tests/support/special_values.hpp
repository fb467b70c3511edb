// SPDX-License-Identifier: MIT
#pragma once
// The floating-point values every function of the library must survive (not part of the library,
// nor of Catch: the fuzz harnesses use it too): the hard-case tests start from this list and add
// the values their own domain makes special.
#include <cmath>
#include <cstddef>
#include <initializer_list>
#include <limits>
#include <vector>

namespace vplkit_test {

// Both zeros, the smallest subnormal and normal, 0.5, 1, -1, both infinities and a NaN.
template <class T>
std::vector<T> special_values() {
  const T inf = std::numeric_limits<T>::infinity();
  return {T(0), T(-0.0), std::numeric_limits<T>::denorm_min(), std::numeric_limits<T>::min(), T(0.5), T(1),
          T(-1), inf, -inf, std::numeric_limits<T>::quiet_NaN()};
}

// Whether the three components of a vector (anything with x, y and z: a glm::vec3, a GPU model's
// vector) are all finite: what a hard case asks of every vector a function returns.
template <class V>
bool finite3(const V& v) {
  using std::isfinite;
  return isfinite(v.x) && isfinite(v.y) && isfinite(v.z);
}

// special_values and `more`, in that order.
template <class T>
std::vector<T> special_values_and(std::initializer_list<T> more) {
  std::vector<T> v = special_values<T>();
  v.insert(v.end(), more);
  return v;
}

// Appends the bucket edges j / n of an n-bucket table (j = 0..n) and the floats either side of
// each: where a threshold test of the wrong strictness would leak.
template <class T>
void append_bucket_edges(std::vector<T>& us, std::size_t n) {
  for (std::size_t j = 0; j <= n; ++j) {
    const T e = T(j) / T(n);
    us.push_back(e);
    us.push_back(std::nextafter(e, T(0)));
    us.push_back(std::nextafter(e, T(2)));
  }
}

}  // namespace vplkit_test
