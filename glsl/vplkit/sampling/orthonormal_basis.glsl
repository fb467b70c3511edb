// SPDX-License-Identifier: MIT
// vplkit GLSL pack: a right-handed orthonormal frame (t, b, n) around a normal; the float mirror
// of include/vplkit/sampling/orthonormal_basis.hpp (docs/api/sampling.md, docs/glsl/sampling.md).
//
// Duff et al. 2017, "Building an orthonormal basis, revisited" (JCGT 6(1)), branchless listing:
//   s = (n.z >= 0 ? 1 : -1);  a = -1 / (s + n.z);  c = n.x n.y a
//   t = (1 + s n.x^2 a, s c, -s n.x);   b = (c, s + n.y^2 a, -n.y)
// s comes from `n.z >= 0.0` (GLSL has no copysign), exactly as in the C++, so n.z = -0.0 takes
// s = +1 on both sides. |s + n.z| >= 1: nothing cancels near n = (0,0,-1).
// The input is divided by its largest component magnitude before it is normalised, so huge
// (3e38) or tiny components neither overflow nor underflow; a zero, NaN or infinite input gets
// the canonical frame (1,0,0), (0,1,0), (0,0,1). On a GPU that flushes denormals to zero a normal
// whose components are all denormal reads as zero and gets the canonical frame too.
// GLSL-only lines (marked): the non-finite test on the bits, and an exact power-of-two rescaling
// that keeps the divisor in the range where GLSL specifies division.
#ifndef VPLKIT_SAMPLING_ORTHONORMAL_BASIS_GLSL
#define VPLKIT_SAMPLING_ORTHONORMAL_BASIS_GLSL

#include "vplkit/core/constants.glsl"

struct vplkit_orthonormal_basis {
  vec3 t;  // tangent
  vec3 b;  // bitangent
  vec3 n;  // normal (unit)
};

// Unit vector along n; (0,0,1) when n is zero, NaN or infinite.
vec3 vplkit_onb_normalize(vec3 n) {
  float ax = abs(n.x), ay = abs(n.y), az = abs(n.z);
  // Not finite (NaN or inf) -> canonical. The C++ writes !(ax <= big && ay <= big && az <= big);
  // GLSL decides it on the bits (exponent all ones): compilers may fold a chain of comparisons
  // into max(), which drops a NaN (docs/glsl.md, "NaN, FMA and compiler rewrites").
  if (any(equal(floatBitsToUint(n) & 0x7F800000u, uvec3(0x7F800000u)))) return vec3(0.0, 0.0, 1.0);
  float m = ax > ay ? (ax > az ? ax : az) : (ay > az ? ay : az);
  // GLSL-only, exact: GLSL specifies x / y only for |y| in [2^-126, 2^126] (GPUs divide through a
  // reciprocal, which underflows to 0 above 2^126). Scaling n and m by one power of two first
  // brings m into that range without changing n / m: every component that the scaling rounds
  // (below 2^-94) has a quotient below 2^-220, which is 0 either way. A device that flushes
  // denormals turns a denormal m into 0 here, and the test below then gives the canonical frame.
  if (m >= 85070591730234615865843651857942052864.0) {  // 2^126
    n *= 2.3283064365386962890625e-10;                  // 2^-32
    m *= 2.3283064365386962890625e-10;
  } else if (m < vplkit_FLT_MIN) {
    n *= 4294967296.0;  // 2^32
    m *= 4294967296.0;
  }
  if (!(m > 0.0)) return vec3(0.0, 0.0, 1.0);
  vec3 s = n / m;  // largest component is +-1 (exactly, where division is IEEE)
  return s / sqrt(s.x * s.x + s.y * s.y + s.z * s.z);
}

vplkit_orthonormal_basis vplkit_make_orthonormal_basis(vec3 normal) {
  vec3 n = vplkit_onb_normalize(normal);
  float s = n.z >= 0.0 ? 1.0 : -1.0;
  float a = -1.0 / (s + n.z);
  float c = n.x * n.y * a;
  vplkit_orthonormal_basis f;
  f.t = vec3(1.0 + s * n.x * n.x * a, s * c, -s * n.x);
  f.b = vec3(c, s + n.y * n.y * a, -n.y);
  f.n = n;
  return f;
}

// local = (x along t, y along b, z along n).
vec3 vplkit_to_world(vplkit_orthonormal_basis f, vec3 local) {
  return f.t * local.x + f.b * local.y + f.n * local.z;
}

vec3 vplkit_to_local(vplkit_orthonormal_basis f, vec3 world) {
  return vec3(dot(world, f.t), dot(world, f.b), dot(world, f.n));
}

#endif  // VPLKIT_SAMPLING_ORTHONORMAL_BASIS_GLSL
