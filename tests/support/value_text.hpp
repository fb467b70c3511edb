// SPDX-License-Identifier: MIT
#pragma once
// Values as text for test messages (not part of the library): enough digits to round-trip, and a
// float's bits next to it, so a failure can be replayed from its message.
#include <float_bits.hpp>

#include <vplkit/core/vector.hpp>

#include <cstdint>
#include <iomanip>
#include <sstream>
#include <string>

namespace vplkit_test {

inline std::string show(float v) {
  std::ostringstream s;
  s << std::setprecision(9) << v << " (0x" << std::hex << std::setw(8) << std::setfill('0') << bits_of(v)
    << ")";
  return s.str();
}
inline std::string show(double v) {
  std::ostringstream s;
  s << std::setprecision(17) << v;
  return s.str();
}
inline std::string show(std::int64_t v) { return std::to_string(v); }
inline std::string show(std::uint64_t v) { return std::to_string(v); }
inline std::string show(int v) { return show(static_cast<std::int64_t>(v)); }
inline std::string show(unsigned v) { return show(static_cast<std::uint64_t>(v)); }

inline std::string show3(float x, float y, float z) { return "(" + show(x) + ", " + show(y) + ", " + show(z) + ")"; }
inline std::string show3(vplkit::vec3<float> v) { return show3(v.x, v.y, v.z); }
inline std::string show2(vplkit::vec2<float> v) { return "(" + show(v.x) + ", " + show(v.y) + ")"; }
inline std::string showi3(vplkit::ivec3 v) {
  return "(" + std::to_string(v.x) + ", " + std::to_string(v.y) + ", " + std::to_string(v.z) + ")";
}

}  // namespace vplkit_test
