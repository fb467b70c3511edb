// SPDX-License-Identifier: MIT
// vplkit GLSL pack: dual paraboloid mapping in light space (docs/math.md section 1), direction <->
// (face, uv). Mirrors include/vplkit/paraboloid/paraboloid.hpp (T = float) line for line.
//
// Convention (identical to the C++): the front face covers d.z >= 0 (-0.0 included), the back face
// d.z < 0. The back face is NOT mirrored: uv = (d.x, d.y) / (1 + |d.z|) on both faces, so a rim
// direction (d.z = 0) has the same uv on either face and the two maps join continuously along the
// rim. The back projection is a reflection (z -> -z) of the front one: triangle winding flips.
#ifndef VPLKIT_PARABOLOID_PARABOLOID_GLSL
#define VPLKIT_PARABOLOID_PARABOLOID_GLSL

#include "vplkit/core/normal_range.glsl"
#include "vplkit/core/unit_or_zero.glsl"

const int vplkit_paraboloid_front = 0;
const int vplkit_paraboloid_back = 1;

struct vplkit_paraboloid_point {
  int face;  // vplkit_paraboloid_front or vplkit_paraboloid_back
  vec2 uv;   // in the closed unit disk
};

// 1 - 2 eps (float eps = 2^-23): the C++ factor (T(1) - T(2) * epsilon), exactly 1 - 2^-22.
const float vplkit_paraboloid_clamp_scale = 0.999999761581420898437500;

// Pulls a uv that rounding left just outside the unit disk back inside. On the CPU dot(uv, uv) <= 1
// then holds exactly; GPU inversesqrt is not correctly rounded (GLSL allows 2 ulp), so on a GPU the
// result may still be 1 ulp outside: texel_from_uv clamps and texel_is_valid is
// integer, so that is harmless. Leaves uv untouched when r2 <= 1. A uv with a component beyond
// 2^63, whose r2 may overflow, is normalised scale-first (vplkit_unit_or_zero), as in the C++.
vec2 vplkit_paraboloid_clamp_to_disk(vec2 uv) {
  float r2 = dot(uv, uv);
  if (r2 > 1.0) {
    vec3 v = vec3(uv, 0.0);
    if (vplkit_max_abs_component(v) <= 9.223372036854775808e18) {  // 2^63
      float k = inversesqrt(r2) * vplkit_paraboloid_clamp_scale;
      uv = uv * k;
    } else {
      uv = vplkit_unit_or_zero(v).xy * vplkit_paraboloid_clamp_scale;
    }
  }
  return uv;
}

// Direction (light space, any length) -> face and uv. d is normalised first; a zero or infinite d
// gives {front, (0,0)} (NaN too on the CPU). The denominator is 1 + |d.z| >= 1 on whichever face
// d falls: no cancellation, the back pole is as accurate as the front one.
// The face is decided on d.z itself (0 below the smallest normal float), as in the C++: a tiny
// negative z can normalise to a denormal, which a GPU flushes.
vplkit_paraboloid_point vplkit_paraboloid_from_direction(vec3 d) {
  vec3 n = vplkit_unit_or_zero(d);
  vplkit_paraboloid_point p;
  bool has_direction = n.x != 0.0 || n.y != 0.0 || n.z != 0.0;
  p.face = (has_direction && vplkit_flush_denormal(d.z) < 0.0) ? vplkit_paraboloid_back : vplkit_paraboloid_front;
  float denom = 1.0 + abs(n.z);
  p.uv = vplkit_paraboloid_clamp_to_disk(vec2(n.x, n.y) / denom);
  return p;
}

// (face, uv) -> unit direction in light space: r2 = |uv|^2, d = (2u, 2v, 1 - r2) / (1 + r2), z
// negated on the back face. At r2 = 1 the result has z = +-0, which from_direction files under the
// front face with the same uv (seam convention). For r2 > 1 (map corners, outside every valid
// texel) the formula continues into the other hemisphere.
vec3 vplkit_paraboloid_to_direction(int face, vec2 uv) {
  float r2 = dot(uv, uv);
  float s = 1.0 / (1.0 + r2);
  vec3 d = vec3(2.0 * uv.x * s, 2.0 * uv.y * s, (1.0 - r2) * s);
  if (face == vplkit_paraboloid_back) d.z = -d.z;
  return d;
}

// Solid-angle Jacobian of the map: d(omega) = 4 / (1 + r2)^2 du dv (1 at the rim, 4 at the pole).
float vplkit_paraboloid_jacobian(vec2 uv) {
  float q = 1.0 + dot(uv, uv);
  return 4.0 / (q * q);
}

#endif  // VPLKIT_PARABOLOID_PARABOLOID_GLSL
