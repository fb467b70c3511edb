// SPDX-License-Identifier: MIT
// vplkit GLSL pack: the light-space frame of a DPRSM, mirroring include/vplkit/paraboloid/
// light_frame.hpp (T = float). The light position c and a right-handed orthonormal basis
// (axis_x, axis_y, axis_z), axis_z the "front axis" (centre of the front paraboloid). Light-space
// coordinates of a world direction d are (dot(d, axis_x), dot(d, axis_y), dot(d, axis_z)).
//
// C++ member functions become free functions taking the frame first:
//   light_frame<T>()                  <-> vplkit_light_frame_identity()
//   light_frame<T>(position, axis)    <-> vplkit_make_light_frame(position, axis)
//   frame.to_light(dir) etc.          <-> vplkit_light_frame_to_light(frame, dir) etc.
#ifndef VPLKIT_PARABOLOID_LIGHT_FRAME_GLSL
#define VPLKIT_PARABOLOID_LIGHT_FRAME_GLSL

#include "vplkit/core/unit_or_zero.glsl"

struct vplkit_light_frame {
  vec3 position;
  vec3 axis_x;
  vec3 axis_y;
  vec3 axis_z;
};

// Identity frame at the origin: light space = world space.
vplkit_light_frame vplkit_light_frame_identity() {
  return vplkit_light_frame(vec3(0.0), vec3(1.0, 0.0, 0.0), vec3(0.0, 1.0, 0.0),
                            vec3(0.0, 0.0, 1.0));
}

// Frame at light_position whose front paraboloid looks along front_axis (any length, any
// direction, (0,0,-1) included). The C++ constructor throws for a non-finite position or a zero /
// non-finite axis; here that is a precondition (a zero axis gives axis_z = 0). Tangents follow
// Duff et al. 2017: s = copysign(1, z) picks the formula whose denominator has |s + z| >= 1.
// copysign is read from the sign bit, so z = -0.0 takes s = -1 exactly as std::copysign does.
vplkit_light_frame vplkit_make_light_frame(vec3 light_position, vec3 front_axis) {
  vplkit_light_frame f;
  f.position = light_position;
  vec3 n = vplkit_unit_or_zero(front_axis);
  float s = ((floatBitsToUint(n.z) & 0x80000000u) != 0u) ? -1.0 : 1.0;
  float a = -1.0 / (s + n.z);
  float b = n.x * n.y * a;
  f.axis_x = vec3(1.0 + s * n.x * n.x * a, s * b, -s * n.x);
  f.axis_y = vec3(b, s + n.y * n.y * a, -n.y);
  f.axis_z = n;
  return f;
}

// World direction -> light-space direction (rotation only; lengths are preserved).
vec3 vplkit_light_frame_to_light(vplkit_light_frame f, vec3 dir) {
  return vec3(dot(dir, f.axis_x), dot(dir, f.axis_y), dot(dir, f.axis_z));
}
// Light-space direction -> world direction.
vec3 vplkit_light_frame_to_world(vplkit_light_frame f, vec3 dir) {
  return f.axis_x * dir.x + f.axis_y * dir.y + f.axis_z * dir.z;
}

// World point -> light-space vector from the light to it, and back.
vec3 vplkit_light_frame_to_light_point(vplkit_light_frame f, vec3 p) {
  return vplkit_light_frame_to_light(f, p - f.position);
}
vec3 vplkit_light_frame_to_world_point(vplkit_light_frame f, vec3 q) {
  return f.position + vplkit_light_frame_to_world(f, q);
}

#endif  // VPLKIT_PARABOLOID_LIGHT_FRAME_GLSL
