// SPDX-License-Identifier: MIT
// vplkit GLSL pack: a right-handed orthonormal frame (t, b, n) around a normal; the float mirror
// of include/vplkit/sampling/orthonormal_basis.hpp (docs/api/sampling.md, docs/glsl/sampling.md).
//
// Duff et al. 2017, "Building an orthonormal basis, revisited" (JCGT 6(1)), branchless listing:
//   s = (n.z >= 0 ? 1 : -1);  a = -1 / (s + n.z);  c = n.x n.y a
//   t = (1 + s n.x^2 a, s c, -s n.x);   b = (c, s + n.y^2 a, -n.y)
// s comes from `n.z >= 0.0` (GLSL has no copysign), exactly as in the C++, so n.z = -0.0 takes
// s = +1 on both sides. |s + n.z| >= 1: nothing cancels near n = (0,0,-1).
// The input is normalised by vplkit_unit_or_zero (an exact power-of-two scaling first, so huge
// (3e38) or tiny components neither overflow nor underflow); a zero, NaN or infinite input, or one
// with no component of at least the smallest normal float, gets the canonical frame (1,0,0),
// (0,1,0), (0,0,1), on every device. GLSL-only line (marked): the non-finite test on the bits.
#ifndef VPLKIT_SAMPLING_ORTHONORMAL_BASIS_GLSL
#define VPLKIT_SAMPLING_ORTHONORMAL_BASIS_GLSL

#include "vplkit/core/constants.glsl"
#include "vplkit/core/normal_range.glsl"
#include "vplkit/core/unit_or_zero.glsl"

struct vplkit_orthonormal_basis {
  vec3 t;  // tangent
  vec3 b;  // bitangent
  vec3 n;  // normal (unit)
};

// Unit vector along n; (0,0,1) when n is zero, NaN or infinite, or has no component of at least
// the smallest normal float (vplkit_unit_or_zero, as the C++).
vec3 vplkit_onb_normalize(vec3 n) {
  // Not finite (NaN or inf) -> canonical, decided on the bits: compilers may fold a chain of
  // comparisons into max(), which drops a NaN (docs/glsl.md, "NaN, FMA and compiler rewrites").
  if (!vplkit_is_finite(n)) return vec3(0.0, 0.0, 1.0);
  vec3 u = vplkit_unit_or_zero(n);
  return (u.x == 0.0 && u.y == 0.0 && u.z == 0.0) ? vec3(0.0, 0.0, 1.0) : u;
}

// Products that can fall below the smallest normal float are flushed, as in the C++.
vplkit_orthonormal_basis vplkit_make_orthonormal_basis(vec3 normal) {
  vec3 n = vplkit_onb_normalize(normal);
  float s = n.z >= 0.0 ? 1.0 : -1.0;
  float a = -1.0 / (s + n.z);
  float c = vplkit_flush_denormal(n.x * n.y * a);
  vplkit_orthonormal_basis f;
  f.t = vec3(1.0 + vplkit_flush_denormal(s * n.x * n.x * a), s * c, -s * n.x);
  f.b = vec3(c, s + vplkit_flush_denormal(n.y * n.y * a), -n.y);
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
