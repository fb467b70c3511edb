#pragma once
// Helpers shared by parity_sampling_test.cpp and parity_mis_test.cpp (not a test program: only
// parity_*.cpp files become programs).
//
// Denormals: llvmpipe keeps them, most GPUs flush them to zero. device_flushes_denormals() asks
// the device once; on a flushing device the tests compute their C++ reference inside a
// cpu_denormals_like_device scope, which sets the x86 FTZ and DAZ bits, so the CPU flushes the
// same inputs and intermediates the GPU does.
#include <parity_harness.hpp>

#include <vplkit/sampling/rng.hpp>

#include <cstdint>
#include <cstring>
#include <iostream>
#include <limits>
#include <string>
#include <vector>

#if defined(__SSE__) || defined(_M_X64) || defined(__x86_64__)
#include <xmmintrin.h>
#define VPLKIT_PARITY_HAVE_MXCSR 1
#endif

namespace vplkit::parity::sampmis {

struct f4 {
  float x, y, z, w;
};

inline std::uint32_t bits_of(float f) {
  std::uint32_t u = 0;
  std::memcpy(&u, &f, sizeof u);
  return u;
}

// True when the GL device flushes denormal inputs or results of float arithmetic to zero.
inline bool device_flushes_denormals() {
  static const bool flushes = [] {
    const float dmin = std::numeric_limits<float>::denorm_min();
    const float fmin = std::numeric_limits<float>::min();
    const std::vector<float> in = {1e-40f, dmin, fmin, 1.0f, 0.5f};
    const std::string kernel = R"(
layout(std430, binding = 0) readonly buffer In { float v[]; };
layout(std430, binding = 1) writeonly buffer Out { uint bits[]; };
void main() {
  if (gl_GlobalInvocationID.x != 0u) return;
  bits[0] = floatBitsToUint(v[0] * v[3]);  // denormal input (DAZ)
  bits[1] = floatBitsToUint(v[1] * v[3]);
  bits[2] = floatBitsToUint(v[2] * v[4]);  // denormal result (FTZ)
})";
    const auto out = run_compute<std::uint32_t>(kernel, {1, 1, 1}, {input(0, in)}, 1, 3);
    const bool f = out[0] != bits_of(1e-40f) || out[1] != bits_of(dmin) ||
                   out[2] != bits_of(fmin * 0.5f);
    std::cout << "parity: the device " << (f ? "flushes" : "keeps") << " float denormals"
              << std::endl;
    return f;
  }();
  return flushes;
}

// While alive, makes the CPU flush denormals like the device (x86 FTZ + DAZ) when `on`.
class cpu_denormals_like_device {
public:
  explicit cpu_denormals_like_device(bool on) {
#ifdef VPLKIT_PARITY_HAVE_MXCSR
    saved_ = _mm_getcsr();
    if (on) _mm_setcsr(saved_ | 0x8040u);  // FTZ (bit 15) | DAZ (bit 6)
#else
    if (on) WARN("the device flushes denormals but this CPU cannot; denormal cases may differ");
#endif
  }
  ~cpu_denormals_like_device() {
#ifdef VPLKIT_PARITY_HAVE_MXCSR
    _mm_setcsr(saved_);
#endif
  }
  cpu_denormals_like_device(const cpu_denormals_like_device&) = delete;
  cpu_denormals_like_device& operator=(const cpu_denormals_like_device&) = delete;

private:
  unsigned saved_ = 0;
};

// Deterministic test inputs from vplkit's own generator: the same on every platform (the
// standard library's distributions are not).
struct input_rng {
  vplkit::counter_rng r;
  explicit input_rng(std::uint32_t seed) : r(vplkit::make_counter_rng(seed, 0x5A3Bu)) {}
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

}  // namespace vplkit::parity::sampmis
