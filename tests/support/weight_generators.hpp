// SPDX-License-Identifier: MIT
#pragma once
// Weight arrays the distribution tests sample from (not part of the library).
//  - exponential_weights<T>: Exp(1) weights with an optional fraction of zeros, drawn with the
//    standard library's distributions (their algorithms are implementation-defined: fine for
//    tests that check properties, not for printed measurements).
//  - portable::*: splitmix64 streams mapped by hand, the same arrays with every standard library
//    (the GPU parity tests, which print what they measure).
#include <random_streams.hpp>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <random>
#include <vector>

namespace vplkit_test {

template <class T>
std::vector<T> exponential_weights(std::size_t n, unsigned seed, double zero_fraction = 0.0) {
  std::mt19937 rng(seed);
  std::exponential_distribution<double> ex(1.0);
  std::uniform_real_distribution<double> uni(0.0, 1.0);
  std::vector<T> w(n);
  for (auto& x : w) x = uni(rng) < zero_fraction ? T(0) : T(ex(rng));
  return w;
}

namespace portable {

// Weights f(g) for a fresh splitmix stream g of `seed`.
template <class F>
std::vector<float> weights_from(std::size_t n, std::uint64_t seed, F f) {
  splitmix_rng g(seed);
  std::vector<float> w(n);
  for (float& x : w) x = f(g);
  return w;
}

inline std::vector<float> random_weights(std::size_t n, std::uint64_t seed) {
  return weights_from(n, seed, [](splitmix_rng& g) { return float(g.uniform()); });
}

inline std::vector<float> exponential_weights(std::size_t n, std::uint64_t seed) {
  return weights_from(n, seed, [](splitmix_rng& g) { return float(-std::log(1.0 - g.uniform())); });
}

// Log-uniform in [10^lo, 10^hi].
inline std::vector<float> log_uniform_weights(std::size_t n, double lo, double hi, std::uint64_t seed) {
  return weights_from(n, seed,
                      [&](splitmix_rng& g) { return float(std::pow(10.0, lo + (hi - lo) * g.uniform())); });
}

// Random weights with zero runs at both ends (each `edge` long), zero runs of 1 to 3000 inside
// (crossing block boundaries) and isolated zeros: about 40 % zeros between the edges.
inline std::vector<float> zero_run_weights(std::size_t n, std::size_t edge, std::uint64_t seed) {
  splitmix_rng g(seed);
  std::vector<float> w(n);
  for (float& x : w) x = float(g.uniform()) + 0.01f;
  for (std::size_t i = 0; i < edge && i < n; ++i) w[i] = 0.0f;
  for (std::size_t i = n > edge ? n - edge : 0; i < n; ++i) w[i] = 0.0f;
  for (std::size_t i = edge; i + edge < n; ++i) {
    const std::uint32_t r = g.next_u32() % 2000u;
    if (r < 1) {
      const std::size_t len = 1 + g.next_u32() % 3000u;
      for (std::size_t k = i; k < i + len && k < n; ++k) w[k] = 0.0f;
      i += len;
    } else if (r < 120) {
      w[i] = 0.0f;
    }
  }
  return w;
}

}  // namespace portable
}  // namespace vplkit_test
