// SPDX-License-Identifier: MIT
#pragma once
// A float's bit pattern and back: the host side of GLSL's floatBitsToUint / uintBitsToFloat. A
// GPU record that mixes uints and floats (the mixtures' metadata, packed components, scene
// tables) is uploaded as uint words, and a GPU result is compared with the C++ one bit for bit,
// so host code needs the exact 32 bits of a float, which only a copy of its object
// representation gives portably in C++17 (std::bit_cast is C++20).
#include <cstdint>
#include <cstring>

namespace vplkit {

// GLSL floatBitsToUint(x).
inline std::uint32_t float_bits(float x) noexcept {
  static_assert(sizeof(float) == sizeof(std::uint32_t), "float must be 32 bits");
  std::uint32_t u = 0;
  std::memcpy(&u, &x, sizeof u);
  return u;
}

// GLSL uintBitsToFloat(u).
inline float float_from_bits(std::uint32_t u) noexcept {
  float x = 0.0f;
  std::memcpy(&x, &u, sizeof x);
  return x;
}

}  // namespace vplkit
