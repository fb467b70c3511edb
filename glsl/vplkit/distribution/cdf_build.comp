// vplkit kernel: builds discrete CDFs and their guide tables on the GPU, from float weights, in the
// layout discrete_cdf.glsl samples (the GPU side of the vplkit::discrete_cdf<float> build;
// docs/glsl/distribution.md states its accuracy against the C++ build).
//
// Interface (no #version: the host prepends "#version 430" (GL) or "#version 450" (Vulkan, plus
// "#extension GL_GOOGLE_include_directive : require"), then its #defines):
//   VPLKIT_CDF_BUILD_BINDING_WEIGHTS (default 0) SSBO, std430, readonly: float weights[D * n]
//   VPLKIT_CDF_BUILD_BINDING_CDF     (default 1) SSBO, std430: float cdf[D * (n + 1)]
//   VPLKIT_CDF_BUILD_BINDING_GUIDE   (default 2) SSBO, std430: uint guide[D * (m + 1)]
//   VPLKIT_CDF_BUILD_BINDING_BLOCKS  (default 3) SSBO, std430, scratch:
//                                                vplkit_cdf_build_block blocks[D * B]  (32 bytes each)
//   VPLKIT_CDF_BUILD_BINDING_INFO    (default 4) SSBO, std430: vplkit_cdf_build_info info[D] (16 bytes)
//   VPLKIT_CDF_BUILD_BINDING_PARAMS  (default 0) uniform block, std140: uint n; uint pass;
//   VPLKIT_CDF_BUILD_LOCAL_SIZE      (default 256) invocations per work group
//   VPLKIT_CDF_BUILD_ITEMS           (default 4)   weights per invocation; a block is
//                                                  LOCAL_SIZE * ITEMS weights
//   VPLKIT_CDF_BUILD_PASS            (optional) 1..6: compile only that pass (one program per
//                                    pass); without it the uniform `pass` selects it at run time
//   VPLKIT_CDF_BUILD_FLOAT_FLOAT     (optional) accumulate in pairs of floats instead of double,
//                                    for devices without fp64 (see "Precision" below)
// D distributions of n weights each (1 <= n <= 2^31, D * (m + 1) < 2^32), stored back to back:
// distribution d has weights[d * n + i], cdf[d * (n + 1) + i], guide[d * (m + 1) + j] with
// m = vplkit_discrete_guide_size(n), blocks[d * B + b] with B = ceil(n / (LOCAL_SIZE * ITEMS)).
// Dispatch: passes 1 to 6 in order, with a shader-storage barrier
// (glMemoryBarrier(GL_SHADER_STORAGE_BARRIER_BIT)) between them; passes 1, 3, 5, 6 with
// (G, 1, D) work groups, any G >= 1 (the kernels stride over blocks; G = min(B, 65535) is the
// natural choice), passes 2 and 4 with (1, 1, D) (only work group 0 of a distribution works there;
// more groups return at once). Nothing needs clearing beforehand.
//   1 block sums        blocks[b].sum, blocks[b].zeroed
//   2 block offsets     blocks[b].offset (exclusive scan of the sums), info[d] (total, zeroed)
//   3 normalise         cdf[i + 1] = prefix max within the block of the normalised partial sums
//   4 block prefix max  blocks[b].prefix_max_bits
//   5 finish the cdf    cdf[0] = 0, cdf[i + 1] = max(cdf[i + 1], prefix max of earlier blocks),
//                       cdf[n] = 1 (0 when empty)
//   6 guide             guide[j] = the largest i in [0, n - 1] with cdf[i] <= j / m
// (G for pass 6: the kernel strides over runs of LOCAL_SIZE * ITEMS guide entries; m + 1 entries
// need ceil((m + 1) / (LOCAL_SIZE * ITEMS)) groups to go without striding.)
//
// Output: what discrete_cdf<float> stores (discrete_cdf.glsl): cdf[0] = 0, cdf[n] = 1 exactly,
// non-decreasing, a zero weight gives exactly equal neighbours (so it is never sampled), the guide
// exactly as the C++ defines it for the stored cdf; an all-zero distribution gives n + 1 zeros and
// m + 1 zero guide entries (empty, as in C++). info[d].total = the sum of the weights rounded to
// float (the vplkit_discrete_cdf descriptor's total), info[d].zeroed = how many weights were
// negative, NaN or infinite: the C++ constructor throws for those, the kernel treats them as 0
// (as discrete_cdf::sanitized does). A sum above the largest float gives info[d].total = +Inf
// (as the C++ total()); the cdf is then still right with double accumulation and unspecified with
// VPLKIT_CDF_BUILD_FLOAT_FLOAT.
//
// How: the partial sums P_i are a two-level scan (each invocation sums ITEMS
// weights in order, the work group combines them with a Hillis-Steele scan, pass 2 scans the block
// sums the same way, sequentially over chunks of blocks), so P_i differs from the C++ double
// running sum only by the rounding of a few dozen additions. cdf[i + 1] = float(min(P_i / total, 1))
// for a weight > 0; the prefix MAX over those values (exact: max does not round) then gives a
// monotone CDF in which a zero weight repeats its left neighbour bit for bit, whatever rounding the
// scan did (a floating-point tree scan is not monotone by itself, nor does it leave partial sums
// unchanged across zeros). The last weight > 0 maps to exactly 1: its P is within ~2^-45 of the
// total, and every value within 2^-25 of 1 rounds to 1.
// Precision (measured in tests/parity/parity_distribution_build_test.cpp; the bound is derived in
// docs/glsl/distribution.md): every P_i passes through at most
// k = 3 ITEMS + 2 log2(LOCAL_SIZE) + ceil(B / BLOCK) + 4 roundings of positive terms (~33 at 2^20).
//   double (default): P_i within k 2^-53 of exact (relative). Needs fp64 (GL 4.0 core; Vulkan:
//     shaderFloat64).
//   float-float: each P_i is a pair (hi, lo) of floats added with error-free transformations
//     (TwoSum, `precise`; <= 3 2^-48 per addition); the quotient is refined from a float division
//     with an exact Dekker product; ~2^-40 in all. Cdf values below 2^-126 (weights below 2^-126
//     of the total) lose accuracy: the low word underflows.
// The C++ build is within (n / 4) 2^-53, so a GPU cdf value is the C++ value or a float neighbour,
// and differs only where the exact quotient lies that close to a float rounding tie.
// Denormal weights count on devices that keep denormals (llvmpipe); a device that flushes them
// treats them as 0 (both paths).
#include "vplkit/distribution/discrete_cdf.glsl"

#ifndef VPLKIT_CDF_BUILD_BINDING_WEIGHTS
#define VPLKIT_CDF_BUILD_BINDING_WEIGHTS 0
#endif
#ifndef VPLKIT_CDF_BUILD_BINDING_CDF
#define VPLKIT_CDF_BUILD_BINDING_CDF 1
#endif
#ifndef VPLKIT_CDF_BUILD_BINDING_GUIDE
#define VPLKIT_CDF_BUILD_BINDING_GUIDE 2
#endif
#ifndef VPLKIT_CDF_BUILD_BINDING_BLOCKS
#define VPLKIT_CDF_BUILD_BINDING_BLOCKS 3
#endif
#ifndef VPLKIT_CDF_BUILD_BINDING_INFO
#define VPLKIT_CDF_BUILD_BINDING_INFO 4
#endif
#ifndef VPLKIT_CDF_BUILD_BINDING_PARAMS
#define VPLKIT_CDF_BUILD_BINDING_PARAMS 0
#endif
#ifndef VPLKIT_CDF_BUILD_LOCAL_SIZE
#define VPLKIT_CDF_BUILD_LOCAL_SIZE 256
#endif
#ifndef VPLKIT_CDF_BUILD_ITEMS
#define VPLKIT_CDF_BUILD_ITEMS 4
#endif
#define VPLKIT_CDF_BUILD_BLOCK (VPLKIT_CDF_BUILD_LOCAL_SIZE * VPLKIT_CDF_BUILD_ITEMS)

#ifdef VPLKIT_CDF_BUILD_FLOAT_FLOAT
#define VPLKIT_CDF_BUILD_ACC vec2
#else
#define VPLKIT_CDF_BUILD_ACC double
#endif

layout(local_size_x = VPLKIT_CDF_BUILD_LOCAL_SIZE, local_size_y = 1, local_size_z = 1) in;

// Per block of one distribution. sum / offset: the accumulator (double, or (hi, lo) floats);
// max_bits / prefix_max_bits: float bits of the block's largest normalised value and of the
// largest one in all earlier blocks (non-negative floats order like their bits).
struct vplkit_cdf_build_block {
  VPLKIT_CDF_BUILD_ACC sum;
  VPLKIT_CDF_BUILD_ACC offset;
  uint max_bits;
  uint prefix_max_bits;
  uint zeroed;
  uint pad;
};

// Per distribution: sum (the accumulator, internal), total (float, for the descriptor), zeroed.
struct vplkit_cdf_build_info {
  VPLKIT_CDF_BUILD_ACC sum;
  float total;
  uint zeroed;
};

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
layout(std140, binding = VPLKIT_CDF_BUILD_BINDING_PARAMS) uniform vplkit_cdf_build_params {
  uint vplkit_cdf_build_n;
  uint vplkit_cdf_build_pass;
};

// The accessors of discrete_cdf.glsl on this kernel's buffers (Mesa's linker wants a body for
// every accessor an included function calls, called or not).
float vplkit_load_cdf(uint distribution, uint i) {
  return vplkit_cdf_build_cdf[distribution * (vplkit_cdf_build_n + 1u) + i];
}
uint vplkit_load_guide(uint distribution, uint j) {
  return vplkit_cdf_build_guide[distribution * (vplkit_discrete_guide_size(vplkit_cdf_build_n) + 1u) + j];
}

shared VPLKIT_CDF_BUILD_ACC vplkit_cdf_build_s_acc[VPLKIT_CDF_BUILD_LOCAL_SIZE];
shared uint vplkit_cdf_build_s_uint[VPLKIT_CDF_BUILD_LOCAL_SIZE];

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
  return (floatBitsToUint(a.x) & 0x7F800000u) == 0x7F800000u ? uintBitsToFloat(0x7F800000u) : a.x;
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
// -0 is a valid zero. Tested on the bits: no dependence on the driver's NaN comparisons.
float vplkit_cdf_build_weight(uint d, uint i, inout uint zeroed) {
  float w = vplkit_cdf_build_weights[d * vplkit_cdf_build_n + i];
  uint bits = floatBitsToUint(w);
  if (bits == 0x80000000u) return 0.0;
  if (bits >= 0x7F800000u) {  // sign set, Inf or NaN
    zeroed += 1u;
    return 0.0;
  }
  return w;
}

// ---- passes -------------------------------------------------------------------------------------
// 1: block sums (and the count of zeroed weights per block).
void vplkit_cdf_build_pass_block_sums(uint d) {
  uint n = vplkit_cdf_build_n;
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

// 2: exclusive scan of the block sums (work group 0; chunks of BLOCK block sums, carried in
// order), the total and the zeroed count.
void vplkit_cdf_build_pass_block_offsets(uint d) {
  if (gl_WorkGroupID.x != 0u) return;
  uint n = vplkit_cdf_build_n;
  uint blocks = vplkit_cdf_build_block_count(n);
  uint t = gl_LocalInvocationID.x;
  VPLKIT_CDF_BUILD_ACC carry = vplkit_cdf_build_acc_zero();
  uint zeroed = 0u;
  for (uint c = 0u; c < blocks; c += uint(VPLKIT_CDF_BUILD_BLOCK)) {
    uint first = c + t * uint(VPLKIT_CDF_BUILD_ITEMS);
    VPLKIT_CDF_BUILD_ACC x[VPLKIT_CDF_BUILD_ITEMS];
    VPLKIT_CDF_BUILD_ACC s = vplkit_cdf_build_acc_zero();
    uint z = 0u;
    for (uint k = 0u; k < uint(VPLKIT_CDF_BUILD_ITEMS); ++k) {
      x[k] = vplkit_cdf_build_acc_zero();
      if (first + k < blocks) {
        x[k] = vplkit_cdf_build_blocks[d * blocks + first + k].sum;
        z += vplkit_cdf_build_blocks[d * blocks + first + k].zeroed;
      }
      s = vplkit_cdf_build_acc_add(s, x[k]);
    }
    vplkit_cdf_build_group_scan(s);
    VPLKIT_CDF_BUILD_ACC excl = t > 0u ? vplkit_cdf_build_s_acc[t - 1u] : vplkit_cdf_build_acc_zero();
    VPLKIT_CDF_BUILD_ACC chunk = vplkit_cdf_build_s_acc[VPLKIT_CDF_BUILD_LOCAL_SIZE - 1];
    VPLKIT_CDF_BUILD_ACC running = vplkit_cdf_build_acc_add(carry, excl);
    for (uint k = 0u; k < uint(VPLKIT_CDF_BUILD_ITEMS); ++k) {
      if (first + k < blocks) vplkit_cdf_build_blocks[d * blocks + first + k].offset = running;
      running = vplkit_cdf_build_acc_add(running, x[k]);
    }
    carry = vplkit_cdf_build_acc_add(carry, chunk);
    vplkit_cdf_build_group_scan_uint(z, false);
    zeroed += vplkit_cdf_build_s_uint[VPLKIT_CDF_BUILD_LOCAL_SIZE - 1];
  }
  if (t == 0u) {
    vplkit_cdf_build_infos[d].sum = carry;
    vplkit_cdf_build_infos[d].total = vplkit_cdf_build_acc_total(carry);
    vplkit_cdf_build_infos[d].zeroed = zeroed;
  }
}

// 3: normalised partial sums, prefix max within each block.
void vplkit_cdf_build_pass_normalise(uint d) {
  uint n = vplkit_cdf_build_n;
  uint blocks = vplkit_cdf_build_block_count(n);
  uint t = gl_LocalInvocationID.x;
  VPLKIT_CDF_BUILD_ACC total = vplkit_cdf_build_infos[d].sum;
  bool empty = vplkit_cdf_build_acc_is_zero(total);
  vplkit_cdf_build_norm norm = vplkit_cdf_build_make_norm(empty ? vplkit_cdf_build_acc_from(1.0) : total);
  for (uint b = gl_WorkGroupID.x; b < blocks; b += gl_NumWorkGroups.x) {
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
    VPLKIT_CDF_BUILD_ACC p = vplkit_cdf_build_acc_add(vplkit_cdf_build_blocks[d * blocks + b].offset, excl);
    uint q[VPLKIT_CDF_BUILD_ITEMS];
    uint running = 0u;
    for (uint k = 0u; k < uint(VPLKIT_CDF_BUILD_ITEMS); ++k) {
      p = vplkit_cdf_build_acc_add(p, vplkit_cdf_build_acc_from(w[k]));
      // A zero weight contributes nothing to the max: it repeats its left neighbour exactly.
      uint bits = (w[k] > 0.0 && !empty) ? floatBitsToUint(vplkit_cdf_build_ratio(p, norm)) : 0u;
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

// 4: exclusive prefix max of the block maxima (work group 0).
void vplkit_cdf_build_pass_block_prefix_max(uint d) {
  if (gl_WorkGroupID.x != 0u) return;
  uint n = vplkit_cdf_build_n;
  uint blocks = vplkit_cdf_build_block_count(n);
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

// 5: the prefix max across blocks, and the two ends.
void vplkit_cdf_build_pass_finish(uint d) {
  uint n = vplkit_cdf_build_n;
  uint blocks = vplkit_cdf_build_block_count(n);
  uint t = gl_LocalInvocationID.x;
  bool empty = vplkit_cdf_build_acc_is_zero(vplkit_cdf_build_infos[d].sum);
  uint base = d * (n + 1u);
  for (uint b = gl_WorkGroupID.x; b < blocks; b += gl_NumWorkGroups.x) {
    uint prefix = vplkit_cdf_build_blocks[d * blocks + b].prefix_max_bits;
    for (uint k = 0u; k < uint(VPLKIT_CDF_BUILD_ITEMS); ++k) {
      uint i = b * uint(VPLKIT_CDF_BUILD_BLOCK) + k * uint(VPLKIT_CDF_BUILD_LOCAL_SIZE) + t;
      if (i + 1u < n) {
        if (prefix != 0u) {
          uint c = floatBitsToUint(vplkit_cdf_build_cdf[base + i + 1u]);
          vplkit_cdf_build_cdf[base + i + 1u] = uintBitsToFloat(max(c, prefix));
        }
      } else if (i + 1u == n) {
        vplkit_cdf_build_cdf[base + n] = empty ? 0.0 : 1.0;
      }
      if (i == 0u) vplkit_cdf_build_cdf[base] = 0.0;
    }
  }
}

// 6: guide[j] = the largest i in [0, n - 1] with cdf[i] <= j / m. cdf[i] <= j / m <=>
// a_i = ceil(cdf[i] * m) <= j, where cdf[i] * m is exact (m a power of two) and so is every
// integer conversion: exact for every j up to 2^31 (j / m as a float would not be above 2^24).
// So guide[j] = i exactly for a_i <= j < a_(i+1) (a_n taken as m + 1): each i owns a run of j.
// A work group takes BLOCK consecutive j, finds the owners of its first and last j by binary
// search, and lets its invocations write the runs of the owners in between, clipped to its j:
// linear work, each entry written once, at most BLOCK entries per invocation. (Owners can be
// many when tiny weights crowd into one j: then up to n / LOCAL_SIZE reads per invocation.)
uint vplkit_cdf_build_guide_owner(uint base, uint n, float fm, uint j) {
  uint lo = 0u;
  uint len = n;
  while (len > 1u) {
    uint half_len = len / 2u;
    lo = uint(ceil(vplkit_cdf_build_cdf[base + lo + half_len] * fm)) <= j ? lo + half_len : lo;
    len -= half_len;
  }
  return lo;
}

void vplkit_cdf_build_pass_guide(uint d) {
  uint n = vplkit_cdf_build_n;
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
    vplkit_cdf_build_sync();  // the previous iteration's readers of s_uint are done
    if (t < 2u) vplkit_cdf_build_s_uint[t] = vplkit_cdf_build_guide_owner(base, n, fm, t == 0u ? j0 : j1 - 1u);
    vplkit_cdf_build_sync();
    uint lo = vplkit_cdf_build_s_uint[0];
    uint hi = vplkit_cdf_build_s_uint[1];
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
  uint pass = vplkit_cdf_build_pass;
#endif
  if (pass == 1u) vplkit_cdf_build_pass_block_sums(d);
  else if (pass == 2u) vplkit_cdf_build_pass_block_offsets(d);
  else if (pass == 3u) vplkit_cdf_build_pass_normalise(d);
  else if (pass == 4u) vplkit_cdf_build_pass_block_prefix_max(d);
  else if (pass == 5u) vplkit_cdf_build_pass_finish(d);
  else if (pass == 6u) vplkit_cdf_build_pass_guide(d);
}
