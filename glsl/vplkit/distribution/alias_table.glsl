// SPDX-License-Identifier: MIT
// vplkit GLSL pack: sampling with Walker's alias method (mirrors the sampling side of
// include/vplkit/distribution/alias_table.hpp, T = float). Build the table with the C++
// alias_table<float> (Vose's method in double) and upload bins() as it is.
//
// O(1): bucket j uniform, keep j when the fraction f < threshold[j], else take alias[j]. Not
// monotone in u: prefer discrete_cdf.glsl for stratified / low-discrepancy u.
// Stored array: n bins, 12 bytes each, std430-compatible with vplkit_alias_bin (C++
// alias_bin<float> { float threshold; float pmf; uint32_t alias; }). A zero weight has threshold
// exactly 0 and an alias whose weight is > 0, so it is never returned, whatever u is. An empty
// table (all weights 0) stores n bins {0, 0, 0}.
// Both samplers return exactly the C++ index and pmf: the bucket is u * n (one correctly rounded
// product, exactly as in C++) truncated, the fraction x - j is exact, the rest is comparisons.
// For n > 2^24, float(n) and float(j) are rounded conversions on both sides (GLSL leaves the
// rounding of uint -> float to the implementation; round-to-nearest everywhere we know of).
//
// ACCESSOR (the including shader defines it):
//   vplkit_alias_bin vplkit_load_alias_bin(uint table, uint j);  // bin j of table `table`, j < n
// e.g. layout(std430, binding = 2) readonly buffer Bins { vplkit_alias_bin bins[]; };
//      vplkit_alias_bin vplkit_load_alias_bin(uint t, uint j) { return bins[t * N + j]; }
#ifndef VPLKIT_DISTRIBUTION_ALIAS_TABLE_GLSL
#define VPLKIT_DISTRIBUTION_ALIAS_TABLE_GLSL

#include "vplkit/distribution/discrete_sample.glsl"
#include "vplkit/distribution/weights.glsl"

struct vplkit_alias_bin {
  float threshold;
  float pmf;
  uint alias;
};

vplkit_alias_bin vplkit_load_alias_bin(uint table, uint j);

// The C++ alias_table<float> besides its bins: id (handed to the accessor), size() and total()
// (only its being 0 is used).
struct vplkit_alias_table {
  uint id;
  uint size;
  float total;
};

// Bucket j in [0, n - 1] and the kept-or-aliased decision (C++ alias_table_pick; `table` stands
// for the bins pointer).
uint vplkit_alias_table_pick(uint table, uint j, float f) {
  vplkit_alias_bin b = vplkit_load_alias_bin(table, j);
  uint a = b.alias;
  return a + (j - a) * uint(f < b.threshold);
}

// Bucket floor(x) of x = u * n, clamped to n - 1 (u * n may round up to n when n is not a power
// of two).
uint vplkit_alias_table_bucket(float x, uint n) {
  uint j = uint(x);
  return j < n ? j : n - 1u;
}

// C++ empty(): total == 0, on the bits (see vplkit_discrete_cdf_empty); size 0 is empty too.
bool vplkit_alias_table_empty(vplkit_alias_table t) {
  return (floatBitsToUint(t.total) << 1u) == 0u || t.size == 0u;
}

// w_i / total as the C++ stored it; 0 for i >= size.
float vplkit_alias_table_pmf(vplkit_alias_table t, uint i) {
  return i < t.size ? vplkit_load_alias_bin(t.id, i).pmf : 0.0;
}

// One u for both decisions: x = u * n, bucket floor(x), fraction x - floor(x) (exact). The
// fraction keeps only the bits of u below the bucket bits (see the C++ comment): use the two-u
// overload unless n is small. u is clamped as in discrete_cdf.
vplkit_discrete_sample vplkit_alias_table_sample(vplkit_alias_table t, float u) {
  if (vplkit_alias_table_empty(t)) return vplkit_discrete_sample(0u, 0.0);
  uint n = t.size;
  // precise: fused into x - float(j) below, u * n - j would skip the rounding of x the C++ has.
  precise float x = vplkit_discrete_clamp_u(u) * float(n);
  uint j = vplkit_alias_table_bucket(x, n);
  float f = vplkit_discrete_clamp_u(x - float(j));
  uint i = vplkit_alias_table_pick(t.id, j, f);
  return vplkit_discrete_sample(i, vplkit_load_alias_bin(t.id, i).pmf);
}

// u1 picks the bucket, u2 decides between the bucket and its alias: full precision.
vplkit_discrete_sample vplkit_alias_table_sample(vplkit_alias_table t, float u1, float u2) {
  if (vplkit_alias_table_empty(t)) return vplkit_discrete_sample(0u, 0.0);
  uint n = t.size;
  uint j = vplkit_alias_table_bucket(vplkit_discrete_clamp_u(u1) * float(n), n);
  uint i = vplkit_alias_table_pick(t.id, j, vplkit_discrete_clamp_u(u2));
  return vplkit_discrete_sample(i, vplkit_load_alias_bin(t.id, i).pmf);
}

#endif  // VPLKIT_DISTRIBUTION_ALIAS_TABLE_GLSL
