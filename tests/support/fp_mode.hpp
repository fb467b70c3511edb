// SPDX-License-Identifier: MIT
#pragma once
// The floating-point mode a C++ reference runs in. A GPU may flush denormal inputs and results to
// zero (docs/math.md, "GPU arithmetic model"); x86-64 does the same when MXCSR has FTZ (flush-to-zero, bit 15:
// denormal results become 0) and DAZ (denormals-are-zero, bit 6: denormal operands read as 0), which
// is also what a program linked with -ffast-math starts with. The parity and Vulkan tests run their
// C++ references in both modes (docs/testing.md): with VPLKIT_PARITY_FTZ_DAZ=1 in the environment,
// every test case runs with FTZ|DAZ set (a Catch2 listener, fp_mode.cpp of each harness), and the
// harness switches back to IEEE (ieee_scope) around everything that is not the reference: the GL and
// Vulkan drivers (llvmpipe and lavapipe run their shader threads in the mode they were created in)
// and the comparisons.
#include <cstdlib>
#include <cstring>
#include <stdexcept>

#if defined(__x86_64__) || defined(_M_X64) || defined(__i386__)
#include <xmmintrin.h>
#define VPLKIT_TEST_HAS_MXCSR 1
#else
#define VPLKIT_TEST_HAS_MXCSR 0
#endif

namespace vplkit_test {

inline constexpr unsigned mxcsr_ftz = 0x8000u;  // flush-to-zero
inline constexpr unsigned mxcsr_daz = 0x0040u;  // denormals-are-zero

// True when this process runs its references with FTZ|DAZ (VPLKIT_PARITY_FTZ_DAZ=1). Throws when
// it was asked for on a CPU without MXCSR: a requested mode is never skipped silently.
inline bool reference_ftz_daz_requested() {
  static const bool requested = [] {
    const char* v = std::getenv("VPLKIT_PARITY_FTZ_DAZ");
    const bool on = v != nullptr && std::strcmp(v, "1") == 0;
    if (on && !VPLKIT_TEST_HAS_MXCSR) {
      throw std::runtime_error("VPLKIT_PARITY_FTZ_DAZ=1 needs an x86 CPU (MXCSR FTZ|DAZ)");
    }
    return on;
  }();
  return requested;
}

inline unsigned read_mxcsr() {
#if VPLKIT_TEST_HAS_MXCSR
  return _mm_getcsr();
#else
  return 0u;
#endif
}

inline void write_mxcsr(unsigned value) {
#if VPLKIT_TEST_HAS_MXCSR
  _mm_setcsr(value);
#else
  (void)value;
#endif
}

// True while FTZ and DAZ are both set on this thread.
inline bool ftz_daz_active() {
  return (read_mxcsr() & (mxcsr_ftz | mxcsr_daz)) == (mxcsr_ftz | mxcsr_daz);
}

// Sets FTZ|DAZ (on = true) or clears both (on = false) for its lifetime; restores the previous
// MXCSR on exit. Nests.
class fp_mode_scope {
public:
  explicit fp_mode_scope(bool ftz_daz) : saved_(read_mxcsr()) {
    if (!VPLKIT_TEST_HAS_MXCSR && ftz_daz) throw std::runtime_error("FTZ|DAZ needs an x86 CPU (MXCSR)");
    write_mxcsr(ftz_daz ? (saved_ | mxcsr_ftz | mxcsr_daz) : (saved_ & ~(mxcsr_ftz | mxcsr_daz)));
  }
  ~fp_mode_scope() { write_mxcsr(saved_); }
  fp_mode_scope(const fp_mode_scope&) = delete;
  fp_mode_scope& operator=(const fp_mode_scope&) = delete;

private:
  unsigned saved_;
};

// IEEE arithmetic (denormals kept) for the scope: what the harness runs drivers and comparisons in.
class ieee_scope : public fp_mode_scope {
public:
  ieee_scope() : fp_mode_scope(false) {}
};

// The reference's mode for the scope: FTZ|DAZ when the process was asked for it, else unchanged.
class reference_scope {
public:
  reference_scope() : saved_(read_mxcsr()) {
    if (reference_ftz_daz_requested()) write_mxcsr(saved_ | mxcsr_ftz | mxcsr_daz);
  }
  ~reference_scope() { write_mxcsr(saved_); }
  reference_scope(const reference_scope&) = delete;
  reference_scope& operator=(const reference_scope&) = delete;

private:
  unsigned saved_;
};

}  // namespace vplkit_test
