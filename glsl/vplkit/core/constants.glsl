// SPDX-License-Identifier: MIT
// vplkit GLSL pack: numeric constants shared by every part.
// Rules of the pack (docs/glsl.md): no #version, no bindings, every identifier prefixed vplkit_,
// guarded against double inclusion. Literals are written with enough digits that the compiler's
// float rounding gives the same bits as the C++ side's static_cast<float>(double constant);
// parity_constants_test checks them bit for bit.
#ifndef VPLKIT_CORE_CONSTANTS_GLSL
#define VPLKIT_CORE_CONSTANTS_GLSL

const float vplkit_PI = 3.14159265358979323846;
const float vplkit_TWO_PI = 6.28318530717958647692;
const float vplkit_HALF_PI = 1.57079632679489661923;
const float vplkit_INV_PI = 0.318309886183790671538;
const float vplkit_INV_TWO_PI = 0.159154943091895335769;
const float vplkit_INV_FOUR_PI = 0.0795774715459476678845;

// Largest float below 1 (0x3F7FFFFF): uniform variates are clamped to it so that u = 1 never
// indexes one past a CDF.
const float vplkit_ONE_MINUS_EPSILON = 0.999999940395355224609375;
// 2^-24: (hash >> 8) * 2^-24 turns a 32-bit hash into a float in [0, 1) exactly (docs/math.md
// section 6).
const float vplkit_TWO_POW_MINUS_24 = 5.9604644775390625e-8;
// Largest finite float and smallest normal float.
const float vplkit_FLT_MAX = 3.40282346638528859811704183484516925e+38;
const float vplkit_FLT_MIN = 1.17549435082228750796873653722224568e-38;

#endif  // VPLKIT_CORE_CONSTANTS_GLSL
