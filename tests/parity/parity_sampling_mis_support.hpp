// SPDX-License-Identifier: MIT
#pragma once
// Helpers shared by parity_sampling_test.cpp and parity_mis_test.cpp (not a test program: only
// parity_*.cpp files become programs).
//
// Denormals: llvmpipe keeps them, most GPUs flush them to zero. device_flushes_denormals() asks
// the device once; on a flushing device the tests compute their C++ reference inside a
// cpu_denormals_like_device scope, which sets the x86 FTZ and DAZ bits, so the CPU flushes the
// same inputs and intermediates the GPU does.
#include <parity_harness.hpp>

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

using input_rng = vplkit_test::counter_input_rng;

// True when the GL device flushes denormal inputs or results of float arithmetic to zero.
inline bool device_flushes_denormals() {
  static const bool flushes = [] {
    const float dmin = std::numeric_limits<float>::denorm_min();
    const float fmin = std::numeric_limits<float>::min();
    const std::vector<float> in = {1e-40f, dmin, fmin, 1.0f, 0.5f};
    kernel_call probe = per_item("", {input(0, in, "float v")}, "uint bits", R"(
  if (i != 0u) return;
  bits[0] = floatBitsToUint(v[0] * v[3]);  // denormal input (DAZ)
  bits[1] = floatBitsToUint(v[1] * v[3]);
  bits[2] = floatBitsToUint(v[2] * v[4]);  // denormal result (FTZ))");
    probe.local_size = {1, 1, 1};
    const auto out = run_compute<std::uint32_t>(probe, 3);
    const bool f = out[0] != bits_of(1e-40f) || out[1] != bits_of(dmin) ||
                   out[2] != bits_of(fmin * 0.5f);
    std::cout << "parity: the device " << (f ? "flushes" : "keeps") << " float denormals"
              << std::endl;
    return f;
  }();
  return flushes;
}

// While alive, makes the CPU flush denormals like the device (x86 FTZ + DAZ) when `on`, and keep
// them when not.
class cpu_denormals_like_device {
public:
  explicit cpu_denormals_like_device(bool on) {
#ifdef VPLKIT_PARITY_HAVE_MXCSR
    saved_ = _mm_getcsr();
    // FTZ (bit 15) | DAZ (bit 6) exactly when the device flushes, whatever mode the reference of
    // this process runs in (tests/support/fp_mode.hpp): this reference is the device's.
    _mm_setcsr(on ? (saved_ | 0x8040u) : (saved_ & ~0x8040u));
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

}  // namespace vplkit::parity::sampmis
