// SPDX-License-Identifier: MIT
#pragma once
// The light-space frame of a DPRSM: the light position c and a right-handed orthonormal basis
// (axis_x, axis_y, axis_z) with axis_z the "front axis", the centre of the front paraboloid.
// Light-space coordinates of a world direction d are (dot(d, axis_x), dot(d, axis_y),
// dot(d, axis_z)).
#include <vplkit/core/error.hpp>
#include <vplkit/core/unit_or_zero.hpp>
#include <vplkit/core/vector.hpp>

#include <cmath>
#include <string>

namespace vplkit {

template <class T>
struct light_frame {
  vec3<T> position{T(0)};
  vec3<T> axis_x{T(1), T(0), T(0)};
  vec3<T> axis_y{T(0), T(1), T(0)};
  vec3<T> axis_z{T(0), T(0), T(1)};

  // Identity frame at the origin: light space = world space.
  light_frame() = default;

  // Frame at `light_position` whose front paraboloid looks along `front_axis` (any length,
  // any direction, (0,0,-1) included). Throws invalid_input for a non-finite position or a
  // zero / non-finite axis.
  // The tangents follow Duff et al. 2017 ("Building an orthonormal basis, revisited"): the sign
  // s = copysign(1, z) picks the formula whose denominator s + z has |s + z| >= 1, so there is
  // no cancellation anywhere, including at z = -1 where the classic Frisvad form divides by 0.
  light_frame(vec3<T> light_position, vec3<T> front_axis) : position(light_position) {
    if (!std::isfinite(light_position.x) || !std::isfinite(light_position.y) ||
        !std::isfinite(light_position.z))
      throw invalid_input("light_frame: light position is not finite");
    const vec3<T> n = unit_or_zero(front_axis);
    if (!(glm::dot(n, n) > T(0)))
      throw invalid_input("light_frame: front axis is zero, NaN or infinite");
    const T s = std::copysign(T(1), n.z);
    const T a = T(-1) / (s + n.z);
    const T b = n.x * n.y * a;
    axis_x = vec3<T>(T(1) + s * n.x * n.x * a, s * b, -s * n.x);
    axis_y = vec3<T>(b, s + n.y * n.y * a, -n.y);
    axis_z = n;
  }

  // World direction -> light-space direction (rotation only; lengths are preserved).
  vec3<T> to_light(vec3<T> dir) const {
    return vec3<T>(glm::dot(dir, axis_x), glm::dot(dir, axis_y), glm::dot(dir, axis_z));
  }
  // Light-space direction -> world direction.
  vec3<T> to_world(vec3<T> dir) const { return axis_x * dir.x + axis_y * dir.y + axis_z * dir.z; }

  // World point -> light-space vector from the light to it, and back.
  vec3<T> to_light_point(vec3<T> p) const { return to_light(p - position); }
  vec3<T> to_world_point(vec3<T> q) const { return position + to_world(q); }
};

}  // namespace vplkit
