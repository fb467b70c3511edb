// SPDX-License-Identifier: MIT
// vplkit GLSL pack: cosine-weighted directions on the hemisphere z >= 0 (local frame); the float
// mirror of include/vplkit/sampling/cosine_hemisphere.hpp (docs/api/sampling.md).
//
// Malley's method on Shirley & Chiu's concentric disk map:
//   a = clamp(2u - 1, -1, 1);  a == (0, 0): r = 0, phi = 0
//   |a.x| > |a.y|:  r = a.x,  phi = (pi/4) (a.y / a.x)
//   otherwise:      r = a.y,  phi = pi/2 - (pi/4) (a.x / a.y)
//   direction = (r cos phi, r sin phi, sqrt(max(0, (1 - |r|)(1 + |r|))))
// z is taken from r, not from the disk point: 1 - |r| is exact near the rim, so z >= 0 always,
// also at u = 0 and u = 1 (the rim, z = 0). r and phi are computed exactly as in the C++ (a is
// exact; the one division has a divisor in [2^-24, 1]); the direction then differs from the CPU's
// by the GPU's cos/sin error, which GLSL does not bound tightly (see docs/glsl/sampling.md).
#ifndef VPLKIT_SAMPLING_COSINE_HEMISPHERE_GLSL
#define VPLKIT_SAMPLING_COSINE_HEMISPHERE_GLSL

#include "vplkit/core/normal_range.glsl"

struct vplkit_concentric_polar {
  float r;    // signed radius, |r| <= 1
  float phi;  // angle in [-pi/4, 3pi/4]
};

vplkit_concentric_polar vplkit_concentric_disk_polar(vec2 u) {
  const float pi = 3.14159265358979323846;
  float ax = 2.0 * u.x - 1.0;
  float ay = 2.0 * u.y - 1.0;
  ax = ax < -1.0 ? -1.0 : (ax > 1.0 ? 1.0 : ax);
  ay = ay < -1.0 ? -1.0 : (ay > 1.0 ? 1.0 : ay);
  vplkit_concentric_polar p = vplkit_concentric_polar(0.0, 0.0);
  if (ax == 0.0 && ay == 0.0) return p;
  if (abs(ax) > abs(ay)) {
    p.r = ax;
    p.phi = (pi / 4.0) * (ay / ax);
  } else {
    p.r = ay;
    p.phi = pi / 2.0 - (pi / 4.0) * (ax / ay);
  }
  return p;
}

// u in [0,1]^2 -> uniform point on the unit disk (Shirley-Chiu).
vec2 vplkit_concentric_disk(vec2 u) {
  vplkit_concentric_polar p = vplkit_concentric_disk_polar(u);
  return vec2(p.r * cos(p.phi), p.r * sin(p.phi));
}

// u in [0,1]^2 (1 included) -> unit direction with z >= 0, density cos(theta)/pi per steradian.
vec3 vplkit_sample_cosine_hemisphere(vec2 u) {
  vplkit_concentric_polar p = vplkit_concentric_disk_polar(u);
  float ar = abs(p.r);
  float z2 = (1.0 - ar) * (1.0 + ar);
  return vec3(p.r * cos(p.phi), p.r * sin(p.phi), sqrt(z2 > 0.0 ? z2 : 0.0));
}

// Solid-angle density of vplkit_sample_cosine_hemisphere; 0 below the horizon (and for NaN).
float vplkit_cosine_hemisphere_pdf(float cos_theta) {
  const float inv_pi = 0.318309886183790671537767526745028724;
  // A cosine, or a density, below the smallest normal float is 0, as in the C++.
  return cos_theta >= vplkit_FLT_MIN ? vplkit_flush_denormal(cos_theta * inv_pi) : 0.0;
}

#endif  // VPLKIT_SAMPLING_COSINE_HEMISPHERE_GLSL
