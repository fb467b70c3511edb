// SPDX-License-Identifier: MIT
#pragma once
// The random inputs of the tests (not part of the library): every stream is fixed by its seed and
// gives the same numbers with every standard library, so a test's inputs -- and the measurements
// it prints -- do not move between machines.
//  - u01(mt19937): the library's RNG convention (docs/math.md section 6), 24 bits on the 2^-24 grid.
//  - random_source: mt19937 mapped to doubles by hand (27 bits), with the shapes the geometric
//    tests draw (directions, boxes, colours).
//  - splitmix_rng: splitmix64, independent of everything in the library (the distribution tests).
//  - counter_input_rng: vplkit's own counter_rng (the sampling / MIS parity tests).
// std::uniform_real_distribution and friends are implementation-defined; only the weight
// generators of weight_generators.hpp that say so use them.
#include <vplkit/core/vector.hpp>
#include <vplkit/sampling/rng.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>

namespace vplkit_test {

using v3f = vplkit::vec3<float>;
using v3d = vplkit::vec3<double>;

// 24 random bits on the 2^-24 grid (for double too, so the double samplers are tested with the u
// a GPU would feed them).
template <class T>
T u01(std::mt19937& rng) {
  return T(rng() >> 8) * T(0x1p-24);
}

// mt19937's output is fixed by the standard; the mapping to floats is ours.
struct random_source {
  std::mt19937 g;
  explicit random_source(std::uint32_t seed) : g(seed) {}
  double unit() { return double(g() >> 5) * (1.0 / 134217728.0); }  // [0, 1), 27 bits
  double uniform(double a, double b) { return a + (b - a) * unit(); }
  int integer(int lo, int hi) { return lo + int(g() % std::uint32_t(hi - lo + 1)); }  // [lo, hi]
  double normal() {  // Box-Muller, enough for directions
    const double u1 = 1.0 - unit(), u2 = unit();
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(6.283185307179586 * u2);
  }
  // A unit direction, uniform on the sphere: a normalised Gaussian, in double.
  v3d direction() {
    v3d d(0.0);
    do d = v3d(normal(), normal(), normal());
    while (glm::dot(d, d) < 1e-6);
    return d / std::sqrt(glm::dot(d, d));
  }
  // A unit direction, uniform on the sphere, from z and the azimuth (two draws, no rejection).
  v3f sphere_direction() {
    const double z = uniform(-1.0, 1.0);
    const double phi = uniform(0.0, 2.0 * 3.14159265358979323846);
    const double r = std::sqrt(std::max(0.0, 1.0 - z * z));
    return v3f(float(r * std::cos(phi)), float(r * std::sin(phi)), float(z));
  }
  v3f point_in(v3d lo, v3d hi) { return v3f(uniform(lo.x, hi.x), uniform(lo.y, hi.y), uniform(lo.z, hi.z)); }
  v3f in_box(double h) { return v3f(float(uniform(-h, h)), float(uniform(-h, h)), float(uniform(-h, h))); }
  v3f colour(double lo, double hi) {
    return v3f(float(uniform(lo, hi)), float(uniform(lo, hi)), float(uniform(lo, hi)));
  }
};

// splitmix64: fixed seeds, independent of the library's own RNG.
struct splitmix_rng {
  std::uint64_t s;
  explicit splitmix_rng(std::uint64_t seed) : s(seed * 0x9E3779B97F4A7C15ull + 1) {}
  std::uint64_t next() {
    std::uint64_t z = (s += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  std::uint32_t next_u32() { return std::uint32_t(next() >> 32); }
  // The library's convention: (h >> 8) * 2^-24, on the 2^-24 grid.
  float grid_float() { return float(next_u32() >> 8) * 0x1p-24f; }
  double uniform() { return double(next() >> 11) * 0x1p-53; }
  // A float in [0, 1) with uniformly random bits below 0x3F800000: every exponent equally often,
  // so tiny values (and denormals) are well represented.
  float any_unit_float() {
    const std::uint32_t bits = std::uint32_t(next() % 0x3F800000ull);
    float f = 0;
    std::memcpy(&f, &bits, sizeof f);
    return f;
  }
};

// vplkit's own generator (bit-exact on every platform and in GLSL) as a source of test inputs.
struct counter_input_rng {
  vplkit::counter_rng r;
  explicit counter_input_rng(std::uint32_t seed) : r(vplkit::make_counter_rng(seed, 0x5A3Bu)) {}
  std::uint32_t next_u32() { return vplkit::rng_next_u32(r); }
  // Uniform in [0, 1) with 53 random bits.
  double uniform() {
    const std::uint64_t hi = next_u32() >> 5, lo = next_u32() >> 6;
    return (static_cast<double>(hi) * 67108864.0 + static_cast<double>(lo)) *
           (1.0 / 9007199254740992.0);
  }
  float uniform_float() { return vplkit::rng_next_float(r); }
  // An index in [0, n).
  std::size_t index(std::size_t n) { return static_cast<std::size_t>(uniform() * static_cast<double>(n)); }
};

}  // namespace vplkit_test
