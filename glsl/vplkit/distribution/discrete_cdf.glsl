// SPDX-License-Identifier: MIT
// vplkit GLSL pack: sampling a discrete distribution by inverse transform; mirrors the sampling
// side of include/vplkit/distribution/discrete_cdf.hpp (T = float). The arrays come from the C++
// discrete_cdf<float> (upload cdf() and guide()) or from the kernel cdf_build.comp, in the same
// layout: cdf[0 .. n] (cdf[0] = 0, cdf[n] = 1, n + 1 zeros when empty) and the guide[0 .. m],
// m = vplkit_discrete_guide_size(n). Sampling returns the largest i with cdf[i] <= u, never a zero
// weight, and exactly the index the C++ returns for the same floats and u (comparisons and exact
// u * 2^k only). ACCESSORS vplkit_load_cdf(distribution, i) and vplkit_load_guide(distribution, j),
// `distribution` being the descriptor's id: define both, even for the binary search alone
// (docs/glsl/distribution.md, "Accessors").
#ifndef VPLKIT_DISTRIBUTION_DISCRETE_CDF_GLSL
#define VPLKIT_DISTRIBUTION_DISCRETE_CDF_GLSL

#include "vplkit/distribution/discrete_sample.glsl"
#include "vplkit/distribution/weights.glsl"

float vplkit_load_cdf(uint distribution, uint i);
uint vplkit_load_guide(uint distribution, uint j);

// What the C++ discrete_cdf<float> object knows besides its arrays, passed by value:
//   id         : handed to the accessors;
//   size       : n (C++ size());
//   guide_size : m (C++ guide_size(); vplkit_discrete_guide_size(n));
//   total      : the sum of the weights (C++ total()); only its being 0 is used (empty()).
// e.g. vplkit_discrete_cdf(0u, n, m, total) with the C++ object's size(), guide_size(), total(),
// or the n, m of a cdf_build.comp run and the total it wrote.
struct vplkit_discrete_cdf {
  uint id;
  uint size;
  uint guide_size;
  float total;
};

// Guide table size for n weights: the smallest power of two >= n (at least 1); n <= 2^31.
uint vplkit_discrete_guide_size(uint n) {
  uint m = 1u;
  while (m < n) m <<= 1u;
  return m;
}

// Largest i in [lo, hi] with cdf[i] <= u, given cdf[lo] <= u and cdf non-decreasing (C++
// discrete_cdf_search: `distribution` stands for the C++ cdf pointer). ceil(log2(hi - lo + 1))
// halvings, the same steps as the C++.
uint vplkit_discrete_cdf_search(uint distribution, uint lo, uint hi, float u) {
  uint len = hi - lo + 1u;
  while (len > 1u) {
    uint half_len = len / 2u;
    lo = vplkit_load_cdf(distribution, lo + half_len) <= u ? lo + half_len : lo;
    len -= half_len;
  }
  return lo;
}

// Guided inverse transform (cutpoint method); u already clamped, the distribution non-empty.
// u in [j/m, (j+1)/m) means cdf[guide[j]] <= j/m <= u, and no i above guide[j+1] has
// cdf[i] <= u: the answer lies in [guide[j], guide[j+1]]. u * m is exact (m a power of two), so
// j is the true bucket of u and the result is exactly the plain binary search's. Buckets with at
// most 3 candidates take two steps; the steps may read cdf[hi + 1], which exists and is > u.
uint vplkit_discrete_cdf_sample_guided(uint distribution, uint m, float u) {
  uint j = uint(u * float(m));
  uint lo = vplkit_load_guide(distribution, j);
  uint hi = vplkit_load_guide(distribution, j + 1u);
  if (hi - lo > 3u) return vplkit_discrete_cdf_search(distribution, lo, hi, u);
  uint c = lo + 2u < hi + 1u ? lo + 2u : hi + 1u;
  lo += (c - lo) * uint(vplkit_load_cdf(distribution, c) <= u);
  lo += uint(vplkit_load_cdf(distribution, lo + 1u) <= u);
  return lo;
}

// C++ empty(): total == 0. Tested on the bits (+0 or -0), so that a device that flushes denormals
// does not call a distribution with a denormal total empty; size 0 is empty too (the C++ total of
// no weights is 0), so a zero-size descriptor never reads the arrays.
bool vplkit_discrete_cdf_empty(vplkit_discrete_cdf d) {
  return (floatBitsToUint(d.total) << 1u) == 0u || d.size == 0u;
}

// Probability that sampling returns i: the width of bin i of the stored CDF (one subtraction,
// correctly rounded in GLSL 4.x as in IEEE); 0 for i >= size (and, from the stored zeros, for an
// empty distribution).
float vplkit_discrete_cdf_pmf(vplkit_discrete_cdf d, uint i) {
  return i < d.size ? vplkit_load_cdf(d.id, i + 1u) - vplkit_load_cdf(d.id, i) : 0.0;
}

// Inverse transform with the guide table. u NaN or < 0 is taken as 0, u >= 1 as the largest float
// below 1. Returns the largest i with cdf[i] <= u and its pmf; {0, 0} when empty.
vplkit_discrete_sample vplkit_discrete_cdf_sample(vplkit_discrete_cdf d, float u) {
  if (vplkit_discrete_cdf_empty(d)) return vplkit_discrete_sample(0u, 0.0);
  u = vplkit_discrete_clamp_u(u);
  uint i = vplkit_discrete_cdf_sample_guided(d.id, d.guide_size, u);
  return vplkit_discrete_sample(i, vplkit_load_cdf(d.id, i + 1u) - vplkit_load_cdf(d.id, i));
}

// The same index by a plain binary search over the whole CDF (no guide table needed).
vplkit_discrete_sample vplkit_discrete_cdf_sample_binary_search(vplkit_discrete_cdf d, float u) {
  if (vplkit_discrete_cdf_empty(d)) return vplkit_discrete_sample(0u, 0.0);
  u = vplkit_discrete_clamp_u(u);
  uint i = vplkit_discrete_cdf_search(d.id, 0u, d.size - 1u, u);
  return vplkit_discrete_sample(i, vplkit_load_cdf(d.id, i + 1u) - vplkit_load_cdf(d.id, i));
}

#endif  // VPLKIT_DISTRIBUTION_DISCRETE_CDF_GLSL
