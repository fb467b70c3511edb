// SPDX-License-Identifier: MIT
// Linked into every `<program>[fma]` executable only (tests/parity/CMakeLists.txt): it fails unless
// this build really contracts a*b+c into a fused multiply-add, the arithmetic the [fma] entries
// model (NVIDIA's compiler contracts freely; GLSL 4.30 "precise" and docs/math.md, "GPU arithmetic
// model"). Without it, a toolchain that ignored -ffp-contract=fast would leave the [fma] entries
// testing the plain IEEE reference a second time.
#include <catch2/catch.hpp>

#include <cstdint>
#include <cstring>

#ifndef VPLKIT_PARITY_FMA_MODEL
#error "fma_model_check.cpp belongs to the [fma] parity executables only"
#endif

namespace {

// Loaded through volatile so the compiler cannot fold the expression; the arithmetic itself is
// plain a * b + c, which -ffp-contract=fast turns into one vfmadd.
float multiply_add(float a, float b, float c) {
  return a * b + c;
}

}  // namespace

TEST_CASE("fma model: the reference contracts a*b+c into one rounding", "[fma]") {
  // a * b = 1 + 2^-11 + 2^-24 exactly. Rounded to float it is 1 + 2^-11 (a tie, to even), so the
  // uncontracted sum with c = -(1 + 2^-11) is 0; the fused one keeps the 2^-24.
  volatile float a = 1.0f + 0x1p-12f;
  volatile float b = 1.0f + 0x1p-12f;
  volatile float c = -(1.0f + 0x1p-11f);
  float const fused = multiply_add(a, b, c);
  INFO("a*b+c = " << fused << " (0 means not contracted)");
  CHECK(fused == 0x1p-24f);
}
