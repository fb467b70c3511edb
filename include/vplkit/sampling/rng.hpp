// SPDX-License-Identifier: MIT
#pragma once
// Counter-based random numbers that a GLSL shader reproduces bit for bit.
//
// Only 32-bit unsigned arithmetic with wrap-around (C++ unsigned and GLSL uint agree on it), no
// 64-bit values and no floating point inside the hash, so CPU and GPU draw identical integers;
// the float conversion keeps 24 bits, which a float holds exactly, so the floats agree too.
//
// Algorithm (the GLSL mirror in glsl/vplkit/ must follow these steps literally):
//   pcg_hash(v):        state = v * 747796405u + 2891336453u
//                       word  = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u
//                       return (word >> 22u) ^ word
//     (Jarzynski & Olano 2020, "Hash functions for GPU rendering", JCGT 9(3): the PCG RXS-M-XS
//      output permutation of one LCG step; a bijection of the 32-bit integers.)
//   rng_key(seed, s):   pcg_hash(pcg_hash(s) ^ seed ^ 0x9E3779B9u)
//   rng_next_u32(r):    h = pcg_hash(r.key + pcg_hash(r.counter)); r.counter += 1u; return h
//   uint_to_unit_float: float(h >> 8u) * 2^-24          (exact: 24 bits, [0, 1 - 2^-24])
// Two hash rounds per number: one round of pcg_hash on (key ^ counter) or (key + counter) makes
// stream k at counter c equal stream k' at some nearby counter; hashing the counter first makes
// such overlaps isolated birthday collisions instead of whole shifted sequences.
#include <cstdint>

namespace vplkit {

inline std::uint32_t pcg_hash(std::uint32_t v) {
  const std::uint32_t state = v * 747796405u + 2891336453u;
  const std::uint32_t word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
  return (word >> 22u) ^ word;
}

// Key of one independent stream (stream = pixel index, gather point, ...) under a seed (frame,
// pass). Consecutive seeds or streams differ in low input bits only; the outer hash spreads that.
// The constant keeps seed 0 from making the key a plain hash-of-hash of the stream index.
inline std::uint32_t rng_key(std::uint32_t seed, std::uint32_t stream) {
  return pcg_hash(pcg_hash(stream) ^ seed ^ 0x9E3779B9u);
}

// Plain value type (GLSL: struct vplkit_counter_rng { uint key; uint counter; }) so a shader keeps
// it in registers and a CPU thread keeps one per pixel. The counter wraps after 2^32 draws.
struct counter_rng {
  std::uint32_t key;
  std::uint32_t counter;
};

inline counter_rng make_counter_rng(std::uint32_t seed, std::uint32_t stream) {
  return counter_rng{rng_key(seed, stream), 0u};
}

inline std::uint32_t rng_next_u32(counter_rng& r) {
  const std::uint32_t h = pcg_hash(r.key + pcg_hash(r.counter));
  r.counter += 1u;
  return h;
}

// The top 24 bits times 2^-24: exactly representable, never 1, the same float on every IEEE
// machine and in GLSL (a uint -> float conversion of a value below 2^24 is exact and the product
// with a power of two is exact).
inline float uint_to_unit_float(std::uint32_t h) {
  return float(h >> 8u) * (1.0f / 16777216.0f);
}

inline float rng_next_float(counter_rng& r) { return uint_to_unit_float(rng_next_u32(r)); }

// The same 24-bit number widened, so a double CPU path consumes exactly what the GPU sees.
inline double rng_next_double(counter_rng& r) { return double(rng_next_float(r)); }

// Template convenience for code written on T = float or double.
template <class T> inline T rng_next_unit(counter_rng& r) { return T(rng_next_float(r)); }

}  // namespace vplkit
