// SPDX-License-Identifier: MIT
#pragma once
// Whether this parity program is the `[fma]` build (tests/parity/CMakeLists.txt): its C++ reference
// is compiled with -mfma -ffp-contract=fast, so it contracts a*b+c the way NVIDIA's compiler does
// outside `precise`. A comparison that is exact on llvmpipe only because both sides round every
// product must then use the bound it uses on a real GPU (docs/testing.md, "The C++ reference with
// FMA contraction"). A decision whose GLSL is `precise` keeps its exact comparison: its reference
// is compiled without contraction in every program (uncontracted_reference.hpp).

namespace vplkit_test {

#ifdef VPLKIT_PARITY_FMA_MODEL
inline constexpr bool reference_contracts = true;
#else
inline constexpr bool reference_contracts = false;
#endif

}  // namespace vplkit_test
