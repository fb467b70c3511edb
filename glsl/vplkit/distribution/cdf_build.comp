// SPDX-License-Identifier: MIT
// vplkit kernel: builds discrete CDFs and their guide tables on the GPU from float weights, in the
// layout discrete_cdf.glsl samples: the GPU side of the vplkit::discrete_cdf<float> build, for D
// distributions of n weights each per set of dispatches (work group z = distribution).
//
// Interface: cdf_build_params.h, shared with the C++ host (bindings, local size, ITEMS, the
// parameter block, the blocks / info records). Options: VPLKIT_CDF_BUILD_PASS (1..6: compile one
// pass per program), VPLKIT_CDF_BUILD_FLOAT_FLOAT (float pairs instead of double, without fp64).
// Dispatch the passes vplkit::gpu::cdf_build_pass_needed names (1, 3, 5 up to 2^20 weights with the
// defaults; 1 to 5 above) in order with a shader-storage barrier between them, or all six: the
// same output. Nothing needs clearing first. Output: what discrete_cdf<float> stores (cdf[0] = 0,
// cdf[n] = 1, a zero weight never sampled, the C++ guide for the stored cdf, no value between 0
// and 2^-103); info[d] gets the float total and the count of rejected (negative, NaN, infinite)
// weights, which count as 0, as do weights below the smallest normal float. Every cdf value is the
// C++ value or a float neighbour. Passes, group counts, how and why, the accuracy bound and measurements:
// docs/glsl/distribution.md, "cdf_build.comp".
#include "vplkit/distribution/cdf_build_params.h"
#include "vplkit/distribution/discrete_cdf.glsl"

layout(local_size_x = VPLKIT_CDF_BUILD_LOCAL_SIZE, local_size_y = 1, local_size_z = 1) in;

layout(std430, binding = VPLKIT_CDF_BUILD_BINDING_WEIGHTS) readonly buffer vplkit_cdf_build_weights_buffer {
  float vplkit_cdf_build_weights[];
};
layout(std430, binding = VPLKIT_CDF_BUILD_BINDING_CDF) buffer vplkit_cdf_build_cdf_buffer {
  float vplkit_cdf_build_cdf[];
};
layout(std430, binding = VPLKIT_CDF_BUILD_BINDING_GUIDE) buffer vplkit_cdf_build_guide_buffer {
  uint vplkit_cdf_build_guide[];
};
layout(std430, binding = VPLKIT_CDF_BUILD_BINDING_BLOCKS) buffer vplkit_cdf_build_blocks_buffer {
  vplkit_cdf_build_block vplkit_cdf_build_blocks[];
};
layout(std430, binding = VPLKIT_CDF_BUILD_BINDING_INFO) buffer vplkit_cdf_build_info_buffer {
  vplkit_cdf_build_info vplkit_cdf_build_infos[];
};
layout(std140, binding = VPLKIT_CDF_BUILD_BINDING_PARAMS) uniform vplkit_cdf_build_uniforms {
  vplkit_cdf_build_params vplkit_cdf_build;
};

// The accessors of discrete_cdf.glsl on this kernel's buffers (every referenced accessor needs a
// body: docs/glsl.md, "Accessors and Mesa's linker").
float vplkit_load_cdf(uint distribution, uint i) {
  return vplkit_cdf_build_cdf[distribution * (vplkit_cdf_build.n + 1u) + i];
}
uint vplkit_load_guide(uint distribution, uint j) {
  return vplkit_cdf_build_guide[distribution * (vplkit_discrete_guide_size(vplkit_cdf_build.n) + 1u) + j];
}

shared VPLKIT_CDF_BUILD_ACC vplkit_cdf_build_s_acc[VPLKIT_CDF_BUILD_LOCAL_SIZE];
shared uint vplkit_cdf_build_s_uint[VPLKIT_CDF_BUILD_LOCAL_SIZE];
shared VPLKIT_CDF_BUILD_ACC vplkit_cdf_build_s_offset;  // pass 3, one chunk: the block's offset
shared uint vplkit_cdf_build_s_max;                      // vplkit_cdf_build_group_max
shared uint vplkit_cdf_build_s_lo[2], vplkit_cdf_build_s_len[2], vplkit_cdf_build_s_count[2];  // pass 6

// ---- the accumulator ----------------------------------------------------------------------------
#ifdef VPLKIT_CDF_BUILD_FLOAT_FLOAT
// (hi, lo) with hi = fl(hi + lo). Every operation is `precise`: error-free transformations rely
// on each + and * being rounded once, in the written order (no FMA contraction, no reassociation).
vec2 vplkit_cdf_build_two_sum(float a, float b) {
  precise float s = a + b;
  precise float bb = s - a;
  precise float e = (a - (s - bb)) + (b - bb);
  return vec2(s, e);
}

vec2 vplkit_cdf_build_fast_two_sum(float a, float b) {  // |a| >= |b| or a == 0
  precise float s = a + b;
  precise float e = b - (s - a);
  return vec2(s, e);
}

// Joldes, Muller, Popescu (2017), AccurateDWPlusDW: relative error <= 3 * 2^-48 (+ underflow).
vec2 vplkit_cdf_build_acc_add(vec2 a, vec2 b) {
  vec2 s = vplkit_cdf_build_two_sum(a.x, b.x);
  vec2 t = vplkit_cdf_build_two_sum(a.y, b.y);
  precise float c = s.y + t.x;
  vec2 v = vplkit_cdf_build_fast_two_sum(s.x, c);
  precise float w = t.y + v.y;
  return vplkit_cdf_build_fast_two_sum(v.x, w);
}

vec2 vplkit_cdf_build_acc_zero() { return vec2(0.0); }
vec2 vplkit_cdf_build_acc_from(float w) { return vec2(w, 0.0); }
bool vplkit_cdf_build_acc_is_zero(vec2 a) { return a.x == 0.0; }

float vplkit_cdf_build_acc_total(vec2 a) {
  return !vplkit_is_finite(a.x) ? uintBitsToFloat(0x7F800000u) : a.x;
}

// x * 2^k for |k| <= 254, exact unless the result leaves the normal range: two factors 2^(k/2),
// 2^(k - k/2) that are normal floats (ldexp's handling of large k varies between drivers).
float vplkit_cdf_build_scale(float x, int k) {
  int k1 = k / 2;
  int k2 = k - k1;
  precise float y = x * uintBitsToFloat(uint(127 + k1) << 23u);
  precise float z = y * uintBitsToFloat(uint(127 + k2) << 23u);
  return z;
}

// Dekker's exact product a * b = p + e (Veltkamp split; |a|, |b| <= 4 here, so no overflow).
vec2 vplkit_cdf_build_two_prod(float a, float b) {
  precise float ca = 4097.0 * a;
  precise float ah = ca - (ca - a);
  precise float al = a - ah;
  precise float cb = 4097.0 * b;
  precise float bh = cb - (cb - b);
  precise float bl = b - bh;
  precise float p = a * b;
  precise float e = ((ah * bh - p) + ah * bl + al * bh) + al * bl;
  return vec2(p, e);
}

// What normalising needs, computed once per work group: the total scaled by 2^k into [1, 2).
struct vplkit_cdf_build_norm {
  vec2 total;
  int k;
};

vplkit_cdf_build_norm vplkit_cdf_build_make_norm(vec2 total) {
  int e = int((floatBitsToUint(total.x) >> 23u) & 0xFFu) - 127;  // total.x is a normal float
  vplkit_cdf_build_norm r;
  r.k = -e;
  r.total = vec2(vplkit_cdf_build_scale(total.x, r.k), vplkit_cdf_build_scale(total.y, r.k));
  return r;
}

// min(P / total, 1) rounded to float: q0 = Ph / Th (GLSL division, <= 2.5 ulp), the exact
// residual P - q0 T (Dekker product; Ph - p is exact by Sterbenz), one correction q1 = r / Th;
// q0 + q1 is within ~2^-44 of P / total and is rounded once.
float vplkit_cdf_build_ratio(vec2 p, vplkit_cdf_build_norm norm) {
  float ph = vplkit_cdf_build_scale(p.x, norm.k);
  float pl = vplkit_cdf_build_scale(p.y, norm.k);
  float th = norm.total.x;
  float tl = norm.total.y;
  float q0 = ph / th;
  vec2 prod = vplkit_cdf_build_two_prod(q0, th);
  precise float r = (((ph - prod.x) - prod.y) + pl) - q0 * tl;
  precise float q = q0 + r / th;
  return min(q, 1.0);
}
#else
double vplkit_cdf_build_acc_add(double a, double b) { return a + b; }
double vplkit_cdf_build_acc_zero() { return 0.0lf; }
double vplkit_cdf_build_acc_from(float w) { return double(w); }
bool vplkit_cdf_build_acc_is_zero(double a) { return a == 0.0lf; }

float vplkit_cdf_build_acc_total(double a) {
  return a <= 3.4028234663852886e38lf ? float(a) : uintBitsToFloat(0x7F800000u);
}

// The C++ multiplies by 1 / total (computed in double) instead of dividing per weight; so does
// this. One Newton step guards against a double division that is less than correctly rounded
// (GLSL promises little for doubles); with an exact one it changes at most the last bit.
struct vplkit_cdf_build_norm {
  double inv;
};

vplkit_cdf_build_norm vplkit_cdf_build_make_norm(double total) {
  double inv = 1.0lf / total;
  inv = inv + inv * (1.0lf - total * inv);
  return vplkit_cdf_build_norm(inv);
}

// C++: q = P * inv; T(q < 1 ? q : 1). The conversion to float rounds to nearest.
float vplkit_cdf_build_ratio(double p, vplkit_cdf_build_norm norm) {
  double q = p * norm.inv;
  return float(q < 1.0lf ? q : 1.0lf);
}
#endif

// ---- work-group scans ---------------------------------------------------------------------------
void vplkit_cdf_build_sync() {
  memoryBarrierShared();
  barrier();
}

// Inclusive scan of one accumulator per invocation (Hillis-Steele). Afterwards s_acc[t] holds
// invocation t's inclusive value (s_acc[LOCAL_SIZE - 1] the group's total) until the next call.
VPLKIT_CDF_BUILD_ACC vplkit_cdf_build_group_scan(VPLKIT_CDF_BUILD_ACC x) {
  uint t = gl_LocalInvocationID.x;
  vplkit_cdf_build_sync();  // earlier readers of s_acc are done
  vplkit_cdf_build_s_acc[t] = x;
  vplkit_cdf_build_sync();
  for (uint off = 1u; off < uint(VPLKIT_CDF_BUILD_LOCAL_SIZE); off <<= 1u) {
    VPLKIT_CDF_BUILD_ACC y = t >= off ? vplkit_cdf_build_s_acc[t - off] : vplkit_cdf_build_acc_zero();
    vplkit_cdf_build_sync();
    if (t >= off) {
      x = vplkit_cdf_build_acc_add(y, x);
      vplkit_cdf_build_s_acc[t] = x;
    }
    vplkit_cdf_build_sync();
  }
  return x;
}

// The same for uints, with max (use_max) or + (counts); s_uint as s_acc above. Exact either way.
uint vplkit_cdf_build_group_scan_uint(uint x, bool use_max) {
  uint t = gl_LocalInvocationID.x;
  vplkit_cdf_build_sync();
  vplkit_cdf_build_s_uint[t] = x;
  vplkit_cdf_build_sync();
  for (uint off = 1u; off < uint(VPLKIT_CDF_BUILD_LOCAL_SIZE); off <<= 1u) {
    uint y = t >= off ? vplkit_cdf_build_s_uint[t - off] : 0u;
    vplkit_cdf_build_sync();
    if (t >= off) {
      x = use_max ? max(y, x) : y + x;
      vplkit_cdf_build_s_uint[t] = x;
    }
    vplkit_cdf_build_sync();
  }
  return x;
}

// ---- helpers ------------------------------------------------------------------------------------
uint vplkit_cdf_build_block_count(uint n) {
  return (n + uint(VPLKIT_CDF_BUILD_BLOCK) - 1u) / uint(VPLKIT_CDF_BUILD_BLOCK);
}

// Weight i of distribution d; negative, NaN and infinite weights (C++: rejected) count as 0.
// -0 and every weight below the smallest normal float (of either sign) are valid zeros (C++
// detail::weight_value, the normal-range contract: a device may flush them on input, so every
// device counts them as 0). Tested on the bits: no dependence on the driver's NaN comparisons or
// on its denormal mode.
float vplkit_cdf_build_weight(uint d, uint i, inout uint zeroed) {
  float w = vplkit_cdf_build_weights[d * vplkit_cdf_build.n + i];
  uint bits = floatBitsToUint(w);
  if ((bits & 0x7FFFFFFFu) < 0x00800000u) return 0.0;  // +-0 and the denormals
  if (bits >= 0x7F800000u) {  // sign set, Inf or NaN
    zeroed += 1u;
    return 0.0;
  }
  return w;
}

// A normalised prefix sum as stored: 0 below discrete_cdf_min_value<float>() = 2^-103 (C++
// discrete_cdf build), so that every stored value is 0 or normal, every pmf (a difference of two
// stored values) is 0 or normal, and the guide table's ceil(cdf * m) is the same on a device that
// flushes denormals. Returned as bits, the form the prefix max works on.
uint vplkit_cdf_build_stored_bits(float q) {
  uint bits = floatBitsToUint(q);
  return bits >= 0x0C000000u ? bits : 0u;  // 0x0C000000: 2^-103
}

// ---- cross-block scans --------------------------------------------------------------------------
// Passes 2 and 4 scan the per-block records in chunks of BLOCK blocks, carried in order. When all
// blocks fit one chunk (B <= BLOCK: n <= 2^20 with the defaults), passes 3 and 5 run that scan
// themselves, each work group for its own blocks (a few KB read from cache, the same operations in
// the same order, so the same bits), and passes 2 and 4 have nothing to do: the host may skip them
// (vplkit::gpu::cdf_build_pass_needed). On a GPU that removes two dependent dispatches of one work
// group each.
bool vplkit_cdf_build_one_chunk(uint blocks) { return blocks <= uint(VPLKIT_CDF_BUILD_BLOCK); }

// Chunk c's block offsets: off[k] = carry + the sum of the block sums before block c + t ITEMS + k
// in the chunk (exclusive), for this invocation's ITEMS blocks; `chunk` = the chunk's sum. Block
// sums are added ITEMS at a time per invocation, the work group combines them (Hillis-Steele).
void vplkit_cdf_build_chunk_offsets(uint d, uint blocks, uint c, VPLKIT_CDF_BUILD_ACC carry,
                                    out VPLKIT_CDF_BUILD_ACC off[VPLKIT_CDF_BUILD_ITEMS],
                                    out VPLKIT_CDF_BUILD_ACC chunk) {
  uint t = gl_LocalInvocationID.x;
  uint first = c + t * uint(VPLKIT_CDF_BUILD_ITEMS);
  VPLKIT_CDF_BUILD_ACC x[VPLKIT_CDF_BUILD_ITEMS];
  VPLKIT_CDF_BUILD_ACC s = vplkit_cdf_build_acc_zero();
  for (uint k = 0u; k < uint(VPLKIT_CDF_BUILD_ITEMS); ++k) {
    x[k] = vplkit_cdf_build_acc_zero();
    if (first + k < blocks) x[k] = vplkit_cdf_build_blocks[d * blocks + first + k].sum;
    s = vplkit_cdf_build_acc_add(s, x[k]);
  }
  vplkit_cdf_build_group_scan(s);
  VPLKIT_CDF_BUILD_ACC excl = t > 0u ? vplkit_cdf_build_s_acc[t - 1u] : vplkit_cdf_build_acc_zero();
  chunk = vplkit_cdf_build_s_acc[VPLKIT_CDF_BUILD_LOCAL_SIZE - 1];
  VPLKIT_CDF_BUILD_ACC running = vplkit_cdf_build_acc_add(carry, excl);
  for (uint k = 0u; k < uint(VPLKIT_CDF_BUILD_ITEMS); ++k) {
    off[k] = running;
    running = vplkit_cdf_build_acc_add(running, x[k]);
  }
}

// The zeroed weights of chunk c's blocks (exact).
uint vplkit_cdf_build_chunk_zeroed(uint d, uint blocks, uint c) {
  uint first = c + gl_LocalInvocationID.x * uint(VPLKIT_CDF_BUILD_ITEMS);
  uint z = 0u;
  for (uint k = 0u; k < uint(VPLKIT_CDF_BUILD_ITEMS); ++k) {
    if (first + k < blocks) z += vplkit_cdf_build_blocks[d * blocks + first + k].zeroed;
  }
  vplkit_cdf_build_group_scan_uint(z, false);
  return vplkit_cdf_build_s_uint[VPLKIT_CDF_BUILD_LOCAL_SIZE - 1];
}

// The largest x over the work group (exact in any order: max does not round).
uint vplkit_cdf_build_group_max(uint x) {
  vplkit_cdf_build_sync();
  if (gl_LocalInvocationID.x == 0u) vplkit_cdf_build_s_max = 0u;
  vplkit_cdf_build_sync();
  if (x != 0u) atomicMax(vplkit_cdf_build_s_max, x);
  vplkit_cdf_build_sync();
  return vplkit_cdf_build_s_max;
}

// ---- passes -------------------------------------------------------------------------------------
// 1: block sums (and the count of zeroed weights per block).
void vplkit_cdf_build_pass_block_sums(uint d) {
  uint n = vplkit_cdf_build.n;
  uint blocks = vplkit_cdf_build_block_count(n);
  uint t = gl_LocalInvocationID.x;
  for (uint b = gl_WorkGroupID.x; b < blocks; b += gl_NumWorkGroups.x) {
    uint first = b * uint(VPLKIT_CDF_BUILD_BLOCK) + t * uint(VPLKIT_CDF_BUILD_ITEMS);
    VPLKIT_CDF_BUILD_ACC s = vplkit_cdf_build_acc_zero();
    uint zeroed = 0u;
    for (uint k = 0u; k < uint(VPLKIT_CDF_BUILD_ITEMS); ++k) {
      if (first + k < n) {
        s = vplkit_cdf_build_acc_add(s, vplkit_cdf_build_acc_from(vplkit_cdf_build_weight(d, first + k, zeroed)));
      }
    }
    VPLKIT_CDF_BUILD_ACC total = vplkit_cdf_build_group_scan(s);
    uint zeroed_total = vplkit_cdf_build_group_scan_uint(zeroed, false);
    if (t == uint(VPLKIT_CDF_BUILD_LOCAL_SIZE) - 1u) {
      vplkit_cdf_build_blocks[d * blocks + b].sum = total;
      vplkit_cdf_build_blocks[d * blocks + b].zeroed = zeroed_total;
    }
  }
}

// 2 (more than one chunk only): exclusive scan of the block sums (work group 0; chunks carried in
// order), the total and the zeroed count.
void vplkit_cdf_build_pass_block_offsets(uint d) {
  if (gl_WorkGroupID.x != 0u) return;
  uint n = vplkit_cdf_build.n;
  uint blocks = vplkit_cdf_build_block_count(n);
  if (vplkit_cdf_build_one_chunk(blocks)) return;  // pass 3 scans the block sums itself
  uint t = gl_LocalInvocationID.x;
  VPLKIT_CDF_BUILD_ACC carry = vplkit_cdf_build_acc_zero();
  uint zeroed = 0u;
  for (uint c = 0u; c < blocks; c += uint(VPLKIT_CDF_BUILD_BLOCK)) {
    uint first = c + t * uint(VPLKIT_CDF_BUILD_ITEMS);
    VPLKIT_CDF_BUILD_ACC off[VPLKIT_CDF_BUILD_ITEMS];
    VPLKIT_CDF_BUILD_ACC chunk;
    vplkit_cdf_build_chunk_offsets(d, blocks, c, carry, off, chunk);
    for (uint k = 0u; k < uint(VPLKIT_CDF_BUILD_ITEMS); ++k) {
      if (first + k < blocks) vplkit_cdf_build_blocks[d * blocks + first + k].offset = off[k];
    }
    carry = vplkit_cdf_build_acc_add(carry, chunk);
    zeroed += vplkit_cdf_build_chunk_zeroed(d, blocks, c);
  }
  if (t == 0u) {
    vplkit_cdf_build_infos[d].sum = carry;
    vplkit_cdf_build_infos[d].total = vplkit_cdf_build_acc_total(carry);
    vplkit_cdf_build_infos[d].zeroed = zeroed;
  }
}

// 3: normalised partial sums, prefix max within each block. With one chunk, every work group
// first scans the block sums (pass 2's work, for its blocks) and group 0 writes the total.
void vplkit_cdf_build_pass_normalise(uint d) {
  uint n = vplkit_cdf_build.n;
  uint blocks = vplkit_cdf_build_block_count(n);
  uint t = gl_LocalInvocationID.x;
  bool one_chunk = vplkit_cdf_build_one_chunk(blocks);
  VPLKIT_CDF_BUILD_ACC own_offsets[VPLKIT_CDF_BUILD_ITEMS];  // one chunk: this invocation's blocks'
  VPLKIT_CDF_BUILD_ACC total;
  if (one_chunk) {  // the same for the whole group: uniform control flow
    VPLKIT_CDF_BUILD_ACC chunk;
    vplkit_cdf_build_chunk_offsets(d, blocks, 0u, vplkit_cdf_build_acc_zero(), own_offsets, chunk);
    total = vplkit_cdf_build_acc_add(vplkit_cdf_build_acc_zero(), chunk);
    if (gl_WorkGroupID.x == 0u) {
      uint zeroed = vplkit_cdf_build_chunk_zeroed(d, blocks, 0u);
      if (t == 0u) {
        vplkit_cdf_build_infos[d].sum = total;
        vplkit_cdf_build_infos[d].total = vplkit_cdf_build_acc_total(total);
        vplkit_cdf_build_infos[d].zeroed = zeroed;
      }
    }
  } else {
    total = vplkit_cdf_build_infos[d].sum;
  }
  bool empty = vplkit_cdf_build_acc_is_zero(total);
  vplkit_cdf_build_norm norm = vplkit_cdf_build_make_norm(empty ? vplkit_cdf_build_acc_from(1.0) : total);
  for (uint b = gl_WorkGroupID.x; b < blocks; b += gl_NumWorkGroups.x) {
    VPLKIT_CDF_BUILD_ACC offset;
    if (one_chunk) {  // block b's offset, from the invocation that holds it
      vplkit_cdf_build_sync();
      if (t == b / uint(VPLKIT_CDF_BUILD_ITEMS)) {
        for (uint k = 0u; k < uint(VPLKIT_CDF_BUILD_ITEMS); ++k) {
          if (k == b % uint(VPLKIT_CDF_BUILD_ITEMS)) vplkit_cdf_build_s_offset = own_offsets[k];
        }
      }
      vplkit_cdf_build_sync();
      offset = vplkit_cdf_build_s_offset;
    } else {
      offset = vplkit_cdf_build_blocks[d * blocks + b].offset;
    }
    uint first = b * uint(VPLKIT_CDF_BUILD_BLOCK) + t * uint(VPLKIT_CDF_BUILD_ITEMS);
    float w[VPLKIT_CDF_BUILD_ITEMS];
    uint zeroed = 0u;
    VPLKIT_CDF_BUILD_ACC s = vplkit_cdf_build_acc_zero();
    for (uint k = 0u; k < uint(VPLKIT_CDF_BUILD_ITEMS); ++k) {
      w[k] = first + k < n ? vplkit_cdf_build_weight(d, first + k, zeroed) : 0.0;
      s = vplkit_cdf_build_acc_add(s, vplkit_cdf_build_acc_from(w[k]));
    }
    vplkit_cdf_build_group_scan(s);
    VPLKIT_CDF_BUILD_ACC excl = t > 0u ? vplkit_cdf_build_s_acc[t - 1u] : vplkit_cdf_build_acc_zero();
    VPLKIT_CDF_BUILD_ACC p = vplkit_cdf_build_acc_add(offset, excl);
    uint q[VPLKIT_CDF_BUILD_ITEMS];
    uint running = 0u;
    for (uint k = 0u; k < uint(VPLKIT_CDF_BUILD_ITEMS); ++k) {
      p = vplkit_cdf_build_acc_add(p, vplkit_cdf_build_acc_from(w[k]));
      // A zero weight contributes nothing to the max: it repeats its left neighbour exactly.
      uint bits = (w[k] > 0.0 && !empty) ? vplkit_cdf_build_stored_bits(vplkit_cdf_build_ratio(p, norm)) : 0u;
      running = max(running, bits);
      q[k] = running;
    }
    uint block_max = vplkit_cdf_build_group_scan_uint(running, true);
    uint excl_max = t > 0u ? vplkit_cdf_build_s_uint[t - 1u] : 0u;
    for (uint k = 0u; k < uint(VPLKIT_CDF_BUILD_ITEMS); ++k) {
      if (first + k < n) {
        vplkit_cdf_build_cdf[d * (n + 1u) + first + k + 1u] = uintBitsToFloat(max(excl_max, q[k]));
      }
    }
    if (t == uint(VPLKIT_CDF_BUILD_LOCAL_SIZE) - 1u) vplkit_cdf_build_blocks[d * blocks + b].max_bits = block_max;
  }
}

// 4 (more than one chunk only): exclusive prefix max of the block maxima (work group 0).
void vplkit_cdf_build_pass_block_prefix_max(uint d) {
  if (gl_WorkGroupID.x != 0u) return;
  uint n = vplkit_cdf_build.n;
  uint blocks = vplkit_cdf_build_block_count(n);
  if (vplkit_cdf_build_one_chunk(blocks)) return;  // pass 5 takes the maxima itself
  uint t = gl_LocalInvocationID.x;
  uint carry = 0u;
  for (uint c = 0u; c < blocks; c += uint(VPLKIT_CDF_BUILD_BLOCK)) {
    uint first = c + t * uint(VPLKIT_CDF_BUILD_ITEMS);
    uint x[VPLKIT_CDF_BUILD_ITEMS];
    uint running = 0u;
    for (uint k = 0u; k < uint(VPLKIT_CDF_BUILD_ITEMS); ++k) {
      x[k] = 0u;
      if (first + k < blocks) x[k] = vplkit_cdf_build_blocks[d * blocks + first + k].max_bits;
      running = max(running, x[k]);
    }
    vplkit_cdf_build_group_scan_uint(running, true);
    uint excl = t > 0u ? vplkit_cdf_build_s_uint[t - 1u] : 0u;
    uint chunk = vplkit_cdf_build_s_uint[VPLKIT_CDF_BUILD_LOCAL_SIZE - 1];
    uint prefix = max(carry, excl);
    for (uint k = 0u; k < uint(VPLKIT_CDF_BUILD_ITEMS); ++k) {
      if (first + k < blocks) vplkit_cdf_build_blocks[d * blocks + first + k].prefix_max_bits = prefix;
      prefix = max(prefix, x[k]);
    }
    carry = max(carry, chunk);
  }
}

// 5: the prefix max across blocks, the two ends, and the guide (as pass 6 defines it, below). With
// one chunk each work group takes the largest of the earlier blocks' maxima itself (at most BLOCK
// of them). The guide: work group b owns i in [b BLOCK, (b + 1) BLOCK), whose a_i it has just
// made (a_(b BLOCK) = ceil(P m) with P the prefix max of the earlier blocks, which is cdf[b BLOCK];
// a_((b + 1) BLOCK) from its own last value), so it writes the j of [a_(b BLOCK), a_((b + 1) BLOCK))
// -- the runs of its own i, each j found by a binary search in shared memory -- and reads nothing
// another work group writes. The runs of all blocks tile [0, m]. Pass 6 is then not needed (it
// writes the same guide again from the stored cdf).
#if VPLKIT_CDF_BUILD_BLOCK > 4096
#error "cdf_build.comp: LOCAL_SIZE x ITEMS must be at most 4096 (pass 5 keeps a block's a_i in shared memory)"
#endif
shared uint vplkit_cdf_build_s_a[VPLKIT_CDF_BUILD_BLOCK + 1];

void vplkit_cdf_build_pass_finish(uint d) {
  uint n = vplkit_cdf_build.n;
  uint blocks = vplkit_cdf_build_block_count(n);
  uint t = gl_LocalInvocationID.x;
  bool one_chunk = vplkit_cdf_build_one_chunk(blocks);
  bool empty = vplkit_cdf_build_acc_is_zero(vplkit_cdf_build_infos[d].sum);
  uint base = d * (n + 1u);
  uint m = vplkit_discrete_guide_size(n);
  float fm = float(m);
  uint guide_base = d * (m + 1u);
  uint block = uint(VPLKIT_CDF_BUILD_BLOCK);
  if (empty) {  // every guide entry 0, split over the work groups
    for (uint j = gl_WorkGroupID.x * uint(VPLKIT_CDF_BUILD_LOCAL_SIZE) + t; j <= m;
         j += gl_NumWorkGroups.x * uint(VPLKIT_CDF_BUILD_LOCAL_SIZE)) {
      vplkit_cdf_build_guide[guide_base + j] = 0u;
    }
  }
  for (uint b = gl_WorkGroupID.x; b < blocks; b += gl_NumWorkGroups.x) {
    uint prefix;
    if (one_chunk) {
      uint pm = 0u;
      for (uint k = 0u; k < uint(VPLKIT_CDF_BUILD_ITEMS); ++k) {
        uint e = t * uint(VPLKIT_CDF_BUILD_ITEMS) + k;
        if (e < b) pm = max(pm, vplkit_cdf_build_blocks[d * blocks + e].max_bits);
      }
      prefix = vplkit_cdf_build_group_max(pm);
    } else {
      prefix = vplkit_cdf_build_blocks[d * blocks + b].prefix_max_bits;
    }
    vplkit_cdf_build_sync();  // the previous block's readers of s_a are done
    if (t == 0u) vplkit_cdf_build_s_a[0] = uint(ceil(uintBitsToFloat(prefix) * fm));  // cdf[b BLOCK]
    for (uint k = 0u; k < uint(VPLKIT_CDF_BUILD_ITEMS); ++k) {
      uint e = k * uint(VPLKIT_CDF_BUILD_LOCAL_SIZE) + t;
      uint i = b * block + e;
      uint a = m + 1u;  // a_(i + 1): m + 1 for i + 1 = n (and past it)
      if (i + 1u < n) {
        uint c = floatBitsToUint(vplkit_cdf_build_cdf[base + i + 1u]);
        if (prefix != 0u) {
          c = max(c, prefix);
          vplkit_cdf_build_cdf[base + i + 1u] = uintBitsToFloat(c);
        }
        a = uint(ceil(uintBitsToFloat(c) * fm));
      } else if (i + 1u == n) {
        vplkit_cdf_build_cdf[base + n] = empty ? 0.0 : 1.0;
      }
      if (i == 0u) vplkit_cdf_build_cdf[base] = 0.0;
      vplkit_cdf_build_s_a[e + 1u] = a;
    }
    vplkit_cdf_build_sync();
    if (!empty) {  // the same for the whole group
      uint j_end = vplkit_cdf_build_s_a[block];
      for (uint j = vplkit_cdf_build_s_a[0] + t; j < j_end; j += uint(VPLKIT_CDF_BUILD_LOCAL_SIZE)) {
        uint lo = 0u;  // the largest e in [0, BLOCK) with s_a[e] <= j (s_a is non-decreasing)
        uint len = block;
        while (len > 1u) {
          uint half_len = len / 2u;
          lo = vplkit_cdf_build_s_a[lo + half_len] <= j ? lo + half_len : lo;
          len -= half_len;
        }
        vplkit_cdf_build_guide[guide_base + j] = b * block + lo;
      }
    }
  }
}

// 6 (not needed after pass 5; kept for hosts that dispatch all six): guide[j] = the largest i in
// [0, n - 1] with cdf[i] <= j / m. cdf[i] <= j / m <=>
// a_i = ceil(cdf[i] * m) <= j, where cdf[i] * m is exact (m a power of two) and so is every
// integer conversion: exact for every j up to 2^31 (j / m as a float would not be above 2^24).
// So guide[j] = i exactly for a_i <= j < a_(i+1) (a_n taken as m + 1): each i owns a run of j.
// A work group takes BLOCK consecutive j, finds the owners of its first and last j, and lets its
// invocations write the runs of the owners in between, clipped to its j: linear work, each entry
// written once, at most BLOCK entries per invocation. (Owners can be many when tiny weights crowd
// into one j: then up to n / LOCAL_SIZE reads per invocation.)
//
// The owners are found by a search that probes P - 1 cdf values at once (P = LOCAL_SIZE / 2 for
// each of the two owners): ceil(log_P(n)) rounds of one load each (3 for n <= 2^21 with the
// defaults) where a binary search makes log2(n) dependent loads (19 for 2^19), each a round trip
// to the GPU's cache. Integer counting, so the result is the binary search's.
#if VPLKIT_CDF_BUILD_LOCAL_SIZE < 4
#error "cdf_build.comp: VPLKIT_CDF_BUILD_LOCAL_SIZE must be at least 4 (the guide's owner search)"
#endif
uvec2 vplkit_cdf_build_guide_owners(uint base, uint n, float fm, uint ja, uint jb) {
  uint t = gl_LocalInvocationID.x;
  uint P = uint(VPLKIT_CDF_BUILD_LOCAL_SIZE) / 2u;
  uint side = min(t / P, 2u);  // 0: ja, 1: jb, 2: idle (an odd local size)
  uint q = t - min(side, 1u) * P;  // probe q of this side (probe 0 is lo, known to qualify)
  uint j = side == 0u ? ja : jb;
  vplkit_cdf_build_sync();  // earlier readers of the search state are done
  if (t < 2u) {
    vplkit_cdf_build_s_lo[t] = 0u;
    vplkit_cdf_build_s_len[t] = n;
  }
  vplkit_cdf_build_sync();
  // Candidates [lo, lo + len) hold the owner and a_lo <= j. Probes lo + q step, q = 1 .. P - 1,
  // below lo + len; the a are non-decreasing, so the c that qualify are the first c: the owner
  // lies in [lo + c step, lo + (c + 1) step).
  while (vplkit_cdf_build_s_len[0] > 1u || vplkit_cdf_build_s_len[1] > 1u) {  // read by all: uniform
    if (t < 2u) vplkit_cdf_build_s_count[t] = 0u;
    vplkit_cdf_build_sync();
    if (side < 2u && q > 0u) {
      uint lo = vplkit_cdf_build_s_lo[side];
      uint len = vplkit_cdf_build_s_len[side];
      uint step = (len + P - 1u) / P;
      uint i = lo + q * step;
      if (len > 1u && q * step < len && uint(ceil(vplkit_cdf_build_cdf[base + i] * fm)) <= j) {
        atomicAdd(vplkit_cdf_build_s_count[side], 1u);
      }
    }
    vplkit_cdf_build_sync();
    if (t < 2u && vplkit_cdf_build_s_len[t] > 1u) {
      uint lo = vplkit_cdf_build_s_lo[t];
      uint len = vplkit_cdf_build_s_len[t];
      uint step = (len + P - 1u) / P;
      uint next = lo + vplkit_cdf_build_s_count[t] * step;
      vplkit_cdf_build_s_len[t] = min(step, lo + len - next);
      vplkit_cdf_build_s_lo[t] = next;
    }
    vplkit_cdf_build_sync();
  }
  return uvec2(vplkit_cdf_build_s_lo[0], vplkit_cdf_build_s_lo[1]);
}

void vplkit_cdf_build_pass_guide(uint d) {
  uint n = vplkit_cdf_build.n;
  uint m = vplkit_discrete_guide_size(n);
  float fm = float(m);
  bool empty = vplkit_cdf_build_acc_is_zero(vplkit_cdf_build_infos[d].sum);
  uint base = d * (n + 1u);
  uint guide_base = d * (m + 1u);
  uint t = gl_LocalInvocationID.x;
  uint span = uint(VPLKIT_CDF_BUILD_BLOCK);
  for (uint j0 = gl_WorkGroupID.x * span; j0 <= m; j0 += gl_NumWorkGroups.x * span) {
    uint j1 = min(j0 + span, m + 1u);  // this group's j: [j0, j1)
    if (empty) {
      for (uint j = j0 + t; j < j1; j += uint(VPLKIT_CDF_BUILD_LOCAL_SIZE)) {
        vplkit_cdf_build_guide[guide_base + j] = 0u;
      }
      continue;  // `empty` is the same for the whole group: uniform control flow
    }
    uvec2 owners = vplkit_cdf_build_guide_owners(base, n, fm, j0, j1 - 1u);
    uint lo = owners.x;
    uint hi = owners.y;
    for (uint i = lo + t; i <= hi; i += uint(VPLKIT_CDF_BUILD_LOCAL_SIZE)) {
      uint a = uint(ceil(vplkit_cdf_build_cdf[base + i] * fm));
      uint b = i + 1u < n ? uint(ceil(vplkit_cdf_build_cdf[base + i + 1u] * fm)) : m + 1u;
      for (uint j = max(a, j0); j < min(b, j1); ++j) vplkit_cdf_build_guide[guide_base + j] = i;
    }
  }
}

void main() {
  uint d = gl_WorkGroupID.z;
#ifdef VPLKIT_CDF_BUILD_PASS
  uint pass = uint(VPLKIT_CDF_BUILD_PASS);
#else
  uint pass = vplkit_cdf_build.pass;
#endif
  if (pass == 1u) vplkit_cdf_build_pass_block_sums(d);
  else if (pass == 2u) vplkit_cdf_build_pass_block_offsets(d);
  else if (pass == 3u) vplkit_cdf_build_pass_normalise(d);
  else if (pass == 4u) vplkit_cdf_build_pass_block_prefix_max(d);
  else if (pass == 5u) vplkit_cdf_build_pass_finish(d);
  else if (pass == 6u) vplkit_cdf_build_pass_guide(d);
}
