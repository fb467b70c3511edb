// SPDX-License-Identifier: MIT
// vplkit GLSL pack: counter-based random numbers, bit for bit those of
// include/vplkit/sampling/rng.hpp (docs/api/sampling.md states the algorithm and known answers).
//
// Only 32-bit unsigned arithmetic with wrap-around (GLSL uint and C++ std::uint32_t agree on it:
// `*` and `+` are modulo 2^32, `>>` is logical), no floating point inside the hash; the float
// conversion keeps 24 bits, which a float holds exactly, so the floats agree too.
//   vplkit_pcg_hash(v):        Jarzynski & Olano 2020 (JCGT 9(3)), PCG RXS-M-XS of one LCG step
//   vplkit_rng_key(seed, s):   vplkit_pcg_hash(vplkit_pcg_hash(s) ^ seed ^ 0x9E3779B9u)
//   vplkit_rng_next_u32(r):    vplkit_pcg_hash(r.key + vplkit_pcg_hash(r.counter)); ++r.counter
//   vplkit_uint_to_unit_float: float(h >> 8u) * 2^-24, in [0, 1 - 2^-24]
// C++'s rng_next_double has no mirror (the pack is float only); on the CPU it widens exactly the
// float that vplkit_rng_next_float returns. rng_next_unit<float> is vplkit_rng_next_unit.
#ifndef VPLKIT_SAMPLING_RNG_GLSL
#define VPLKIT_SAMPLING_RNG_GLSL

uint vplkit_pcg_hash(uint v) {
  uint state = v * 747796405u + 2891336453u;
  uint word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
  return (word >> 22u) ^ word;
}

// Key of one independent stream (pixel, gather point, ...) under a seed (frame, pass).
uint vplkit_rng_key(uint seed, uint stream) {
  return vplkit_pcg_hash(vplkit_pcg_hash(stream) ^ seed ^ 0x9E3779B9u);
}

// Plain value type: keep it in registers, copy it to fork a stream. The counter wraps after 2^32
// draws. std430 layout: two uints, 8 bytes (C++ vplkit::counter_rng).
struct vplkit_counter_rng {
  uint key;
  uint counter;
};

vplkit_counter_rng vplkit_make_counter_rng(uint seed, uint stream) {
  return vplkit_counter_rng(vplkit_rng_key(seed, stream), 0u);
}

uint vplkit_rng_next_u32(inout vplkit_counter_rng r) {
  uint h = vplkit_pcg_hash(r.key + vplkit_pcg_hash(r.counter));
  r.counter += 1u;
  return h;
}

// Exact: a uint below 2^24 converts to float without rounding, and the product with a power of
// two does not round either.
float vplkit_uint_to_unit_float(uint h) {
  return float(h >> 8u) * (1.0 / 16777216.0);
}

float vplkit_rng_next_float(inout vplkit_counter_rng r) {
  return vplkit_uint_to_unit_float(vplkit_rng_next_u32(r));
}

// C++ rng_next_unit<T>(r) = T(rng_next_float(r)); the float instantiation.
float vplkit_rng_next_unit(inout vplkit_counter_rng r) {
  return vplkit_rng_next_float(r);
}

#endif  // VPLKIT_SAMPLING_RNG_GLSL
