// SPDX-License-Identifier: MIT
#pragma once
// Whether this parity program is the `[fma]` build (tests/parity/CMakeLists.txt): its C++ reference
// is compiled with -mfma -ffp-contract=fast, so it contracts a*b+c the way NVIDIA's compiler does
// outside `precise`. A comparison that is exact on llvmpipe only because both sides round every
// product must then use the bound it uses on a real GPU (docs/testing.md, "The C++ reference with
// FMA contraction").

// Catch2 tags for a test case whose exact comparison holds only when the C++ reference rounds
// every product (the library's documented requirement for it, e.g. the `precise` SAT of
// triangle_box_overlap): in the [fma] build its failures are reported but do not fail the run
// ("[!mayfail]"), since a GPU honours `precise` and the contracting reference is then the odd one.
#ifdef VPLKIT_PARITY_FMA_MODEL
#define VPLKIT_PARITY_NEEDS_UNCONTRACTED_REFERENCE "[!mayfail]"
#else
#define VPLKIT_PARITY_NEEDS_UNCONTRACTED_REFERENCE ""
#endif

namespace vplkit_test {

#ifdef VPLKIT_PARITY_FMA_MODEL
inline constexpr bool reference_contracts = true;
#else
inline constexpr bool reference_contracts = false;
#endif

}  // namespace vplkit_test
