// SPDX-License-Identifier: MIT
// vplkit GLSL pack: what a discrete sampler returns (mirrors
// include/vplkit/distribution/discrete_sample.hpp, T = float).
//
// The chosen index and the probability of choosing it. Every sampler returns exactly what its pmf
// function would return for that index (same expression, same rounding). pmf == 0 means "no
// sample" (an empty distribution): test it before dividing.
#ifndef VPLKIT_DISTRIBUTION_DISCRETE_SAMPLE_GLSL
#define VPLKIT_DISTRIBUTION_DISCRETE_SAMPLE_GLSL

// C++ discrete_sample<float> { std::size_t index; float pmf; } (index as uint: distributions on
// the GPU hold fewer than 2^32 entries).
struct vplkit_discrete_sample {
  uint index;
  float pmf;
};

#endif  // VPLKIT_DISTRIBUTION_DISCRETE_SAMPLE_GLSL
